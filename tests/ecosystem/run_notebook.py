"""Executes a notebook top to bottom with nbclient (Debian's python3-nbclient and
python3-ipykernel): exit 0 when every cell ran, 1 with the failing cell's error otherwise.

    python3 tests/ecosystem/run_notebook.py examples/notebooks/compare_methods.ipynb [FIGURES]

With FIGURES, fewer PNG figures in the outputs than that is a failure too (a figure that
silently did not render).

The kernel runs in a new temporary folder (under TMPDIR), so whatever the notebook writes
lands there, as do Jupyter's runtime files and IPython's and matplotlib's caches; the notebook
file itself is read, never written. It must be committed clean: no
outputs, no execution counts (checked first). The environment passes to the kernel, so
PYTHONPATH (build/python) and MPLBACKEND=Agg reach it.
"""
import os
import sys
import tempfile
import time

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

CELL_TIMEOUT_S = 120


def main(path, figures_expected=0):
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    dirty = [k for k, c in enumerate(nb.cells)
             if c.cell_type == "code" and (c.outputs or c.execution_count is not None)]
    if dirty:
        print(f"{path}: cells {dirty} hold outputs; commit the notebook cleared", file=sys.stderr)
        return 1
    folder = tempfile.mkdtemp(prefix="notebook_")
    # Jupyter's connection files, IPython's history and matplotlib's font cache go there too,
    # not under HOME.
    for variable, sub in (("JUPYTER_RUNTIME_DIR", "jupyter_runtime"), ("IPYTHONDIR", "ipython"),
                          ("MPLCONFIGDIR", "matplotlib")):
        os.environ[variable] = os.path.join(folder, sub)
    # The kernel's debugger otherwise warns on every start about Python's frozen modules.
    os.environ.setdefault("PYDEVD_DISABLE_FILE_VALIDATION", "1")
    client = NotebookClient(nb, timeout=CELL_TIMEOUT_S, kernel_name="python3",
                            resources={"metadata": {"path": folder}})
    start = time.monotonic()
    try:
        client.execute()
    except CellExecutionError as e:
        print(f"{path}: a cell failed\n{e}", file=sys.stderr)
        return 1
    code = [c for c in nb.cells if c.cell_type == "code"]
    figures = sum(1 for c in code for o in c.outputs if "image/png" in o.get("data", {}))
    print(f"{path}: {len(code)} code cells ran in {time.monotonic() - start:.1f} s "
          f"({figures} figures) in {folder}")
    if figures < figures_expected:
        print(f"{path}: {figures} figures, expected {figures_expected}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        print("usage: run_notebook.py NOTEBOOK.ipynb [FIGURES]", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) == 3 else 0))
