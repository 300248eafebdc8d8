"""contact2d from Python: solve a 2D elastic contact scene in process, compare methods, sweep.

    import contact2d
    s = contact2d.run("examples/hertz_rigid_fast.toml", method="ssn",
                      set=["analysis.mesh_scale=2"])
    s["contact"]["p_max"]          # the summary, as summary.json
    s["fields"]["displacement"]    # NumPy arrays: nodes, elements, displacement, reaction,
                                   # stress (σxx, σyy, σxy per node), contact, steps

A scene is a path to a .toml (or the seed's .dat) file, or a dict with the same tables
(docs/scene.md). `set` overrides keys as `contact2d run --set` does. Bad input raises
contact2d.InputError (a ValueError) with the command line's located message; a file of `out`
that cannot be written raises OSError (errno set, the output folder named); a run that does
not converge returns its summary with that status. compare() and sweep() run the command
line's studies (one `contact2d run` process per case) and return their tables.
"""

import csv
import os
import shutil
import subprocess
import tempfile

from ._contact2d import InputError, executable, to_toml
from ._contact2d import run as _run

__all__ = ["run", "compare", "sweep", "InputError", "executable", "to_toml"]


def _sets(set):
    """`set` as a list of "key=value" strings: one string is one override, not its letters."""
    items = [set] if isinstance(set, (str, bytes)) else list(set)
    for i, s in enumerate(items):
        if not isinstance(s, str):
            raise InputError("set[%d]: expected a string key=value, found %s"
                             % (i, type(s).__name__))
    return items


def run(scene, method="", set=(), out=None):
    """Solves `scene` (a path or a dict) with `method` (default: the scene's) in this process.

    Returns the summary as a dict (summary.json's keys) with the fields as NumPy arrays under
    "fields". With `out`, the run's files are written there as `contact2d run --out` writes
    them. The GIL is released while solving; Ctrl-C (SIGINT) raises KeyboardInterrupt within
    about a second, leaving no work folder.
    """
    return _run(scene if isinstance(scene, dict) else os.fspath(scene), method, _sets(set),
                None if out is None else os.fspath(out))


def _number(cell):
    try:
        return float(cell)
    except ValueError:
        return cell


def _read_table(path):
    """A study's CSV as a dict of columns (numbers as floats, empty cells as NaN)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    columns = rows[0].keys() if rows else []
    return {c: [_number(r[c]) if r[c] != "" else float("nan") for r in rows] for c in columns}


def _study(verb, scene, args, out, table, report):
    keep = out is not None
    folder = os.fspath(out) if keep else tempfile.mkdtemp(prefix="contact2d_" + verb + "_")
    try:
        if isinstance(scene, dict):
            # The study's cases run the command line on a file: the dict written as TOML into
            # the study's folder, where its job list can find it again.
            text = to_toml(scene)
            os.makedirs(folder, exist_ok=True)
            scene = os.path.join(folder, "scene.toml")
            with open(scene, "w") as f:
                f.write(text)
        p = subprocess.run([executable(), verb, os.fspath(scene), *args, "--out", folder,
                            "--quiet"], capture_output=True, text=True)
        if p.returncode == 2:
            lines = (p.stderr or p.stdout).strip().splitlines()
            raise InputError(lines[-1] if lines else verb + ": refused its input")
        if not os.path.exists(os.path.join(folder, table)):
            raise RuntimeError(verb + " wrote no " + table + " (exit " + str(p.returncode) +
                               "): " + p.stderr.strip())
        result = {"table": _read_table(os.path.join(folder, table)),
                  "exit_code": p.returncode}
        with open(os.path.join(folder, report)) as f:
            result["report"] = f.read()
        if keep:
            result["out"] = folder
        return result
    finally:
        if not keep:
            shutil.rmtree(folder, ignore_errors=True)


def compare(scene, methods=None, levels=1, jobs=1, set=(), out=None, metric=None):
    """`contact2d compare`: every chosen method (default: all) on `levels` meshes.

    `scene` is a path or a dict (written as scene.toml into the study's folder). `metric`: what
    to judge by (a reference key, a contact figure or a probe; default: the scene's reference).
    Returns {"table": compare.csv as columns, "report": compare.md (verdict first),
    "exit_code": ..., "out": the folder when `out` is given}.
    """
    args = ["--levels", str(levels), "--jobs", str(jobs)]
    if metric:
        args += ["--metric", metric]
    if methods:
        args += ["--methods", ",".join(methods)]
    for s in _sets(set):
        args += ["--set", s]
    return _study("compare", scene, args, out, "compare.csv", "compare.md")


def sweep(scene, key, values, method=None, jobs=1, set=(), out=None, metric=None):
    """`contact2d sweep`: one run per value of `key` (a list of numbers, or "a:b:log:n").

    `scene` is a path or a dict; `metric` as for compare (default: p_max). A penalty or
    augmentation key is also run once with lagrange on the same mesh, the baseline.
    Returns {"table": sweep.csv as columns, "report": sweep.md, "exit_code": ..., "out": ...}.
    """
    spec = values if isinstance(values, str) else ",".join(repr(float(v)) for v in values)
    args = ["--set", key + "=" + spec, "--jobs", str(jobs)]
    if metric:
        args += ["--metric", metric]
    if method:
        args += ["--method", method]
    for s in _sets(set):
        args += ["--set", s]
    return _study("sweep", scene, args, out, "sweep.csv", "sweep.md")
