"""contact2d's VTU and PVD files read by VTK's own readers (issue 35, item 3).

Runs examples with the contact2d program into pytest's temporary folder (under TMPDIR), in the
binary (appended raw) and the ASCII encoding (`output.vtu`), and reads every VTU they write with
VTK's vtkXMLUnstructuredGridReader (Debian's python3-vtk9, VTK 9.1) and every PVD with VTK's
XML parser (vtkXMLDataParser: Debian's VTK has no vtkPVDReader, which is ParaView's), each file
it lists then read by VTK. Covered: linear T6 (Hertz), linear T3 with two bodies (the patch
test), load-stepped T6 series (the elastica; the frictional drag, whose thirtieths of the load
are no round numbers), `contact2d mesh`'s mesh.vtu and an adaptive run's adapt.pvd.

What is checked, against what the run itself reports:
- no error or warning from VTK while reading;
- point and cell counts against summary.json's mesh, cell types 5 (VTK_TRIANGLE) for T3 and
  22 (VTK_QUADRATIC_TRIANGLE) for T6, every element counter-clockwise, T6 mid-side nodes in
  VTK's order (3 on edge 0-1, 4 on 1-2, 5 on 2-0) and the cells' area computed
  through VTK's own shape functions (vtkTriangle, vtkQuadraticTriangle) against the
  geometry's, with a positive Jacobian at every Gauss point;
- the array names and component counts;
- the last VTU's points, displacements, smoothed stresses, von Mises and reactions against
  nodes.csv to 1e-11 relative (nodes.csv and the ASCII arrays print 12 significant digits, the
  binary arrays are exact), contact pressures against contact.csv to the same;
- the binary and the ASCII run's arrays agree to 1e-11 relative (the same solve, printed);
- the PVD's time steps against steps.csv's load factors (1e-11 relative), its files in order,
  each step's tip displacement against the steps.csv probe of that step.
"""
import csv
import json
import math
import os
import subprocess

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkQuadraticTriangle, vtkTriangle
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkIOXMLParser import vtkXMLDataParser

BINARY = os.environ["C2D_BINARY"]
SOURCE = os.environ["C2D_SOURCE_DIR"]
EXAMPLES = os.path.join(SOURCE, "examples")

# 12 significant digits (nodes.csv, contact.csv, steps.csv and the ASCII arrays): a printed
# value is within 5e-12 of the exact one, relative.
PRINTED = 1e-11

VTK_TRIANGLE, VTK_QUADRATIC_TRIANGLE = 5, 22

POINT_ARRAYS = {"displacement": 3, "reaction": 3, "stress_smoothed": 3, "von_mises_smoothed": 1,
                "s1_smoothed": 1, "s2_smoothed": 1}
CONTACT_ARRAYS = {"contact_gap": 1, "contact_pressure": 1, "contact_force": 1}
FRICTION_ARRAYS = {"contact_shear": 1, "contact_slip": 1, "contact_state": 1}
CELL_ARRAYS = {"stress_element": 3, "von_mises_element": 1, "zz_local_parameter": 1,
               "body_id": 1, "material_id": 1}

# VTK's messages go to one string; every read checks that it did not grow.
VTK_LOG = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(VTK_LOG)


def vtk_messages(since):
    """What VTK said after the log held `since` characters."""
    return VTK_LOG.GetOutput()[since:]


def contact2d(*args):
    """Runs the program (an argument list, no shell); returns its stdout."""
    p = subprocess.run([BINARY, *args], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, f"contact2d {' '.join(args)}: exit {p.returncode}\n{p.stderr}"
    return p.stdout


def run(out, scene, *sets, extra=()):
    args = ["run", os.path.join(EXAMPLES, scene), "--out", str(out), "--quiet", *extra]
    for s in sets:
        args += ["--set", s]
    contact2d(*args)
    with open(out / "summary.json") as f:
        return json.load(f)


def read_csv(path):
    """A CSV as a dict of columns: floats, or strings where a cell is not a number."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))

    def column(k):
        try:
            return np.array([float(r[k]) for r in rows])
        except ValueError:
            return [r[k] for r in rows]
    return {k: column(k) for k in rows[0]}


def read_vtu(path):
    """The unstructured grid VTK reads from `path`; fails on any message VTK gives."""
    mark = len(VTK_LOG.GetOutput())
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    assert vtk_messages(mark) == "", f"{path}: VTK said {vtk_messages(mark)}"
    assert reader.GetErrorCode() == 0, f"{path}: VTK error code {reader.GetErrorCode()}"
    return reader.GetOutput()


def read_pvd(path):
    """The (timestep, file) pairs of a PVD, parsed by VTK's XML parser, its structure checked."""
    mark = len(VTK_LOG.GetOutput())
    parser = vtkXMLDataParser()
    parser.SetFileName(str(path))
    assert parser.Parse() == 1, f"{path}: VTK could not parse it: {vtk_messages(mark)}"
    root = parser.GetRootElement()
    assert root.GetName() == "VTKFile" and root.GetAttribute("type") == "Collection"
    assert root.GetNumberOfNestedElements() == 1
    collection = root.GetNestedElement(0)
    assert collection.GetName() == "Collection"
    steps = []
    for i in range(collection.GetNumberOfNestedElements()):
        ds = collection.GetNestedElement(i)
        assert ds.GetName() == "DataSet"
        assert ds.GetAttribute("part") == "0"
        steps.append((float(ds.GetAttribute("timestep")), ds.GetAttribute("file")))
    assert vtk_messages(mark) == "", f"{path}: VTK said {vtk_messages(mark)}"
    return steps


def point_arrays(grid):
    pd = grid.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


def cell_arrays(grid):
    cd = grid.GetCellData()
    return {cd.GetArrayName(i): vtk_to_numpy(cd.GetArray(i)) for i in range(cd.GetNumberOfArrays())}


def components(grid, data):
    d = grid.GetPointData() if data == "point" else grid.GetCellData()
    return {d.GetArrayName(i): d.GetArray(i).GetNumberOfComponents()
            for i in range(d.GetNumberOfArrays())}


def cells(grid):
    """Connectivity as an (elements, nodes per element) array, and the cell types."""
    types = vtk_to_numpy(grid.GetCellTypesArray())
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    per = np.diff(offsets)
    assert np.all(per == per[0]), "cells of mixed sizes"
    return conn.reshape(-1, per[0]), types


def vtk_area(x, conn, t6):
    """The cells' area through VTK's own shape functions (vtkTriangle, vtkQuadraticTriangle) and
    the node order as read: the 3-point Gauss rule, exact for a T6's quadratic det J. Returns the
    total and the smallest det J at a Gauss point (negative: a cell folded by its node order)."""
    cell = vtkQuadraticTriangle() if t6 else vtkTriangle()
    n = 6 if t6 else 3
    gauss = ((1 / 6, 1 / 6), (2 / 3, 1 / 6), (1 / 6, 2 / 3))
    total, smallest = 0.0, math.inf
    xy = x[conn][:, :, :2]  # (cells, n, 2)
    for r, t in gauss:
        d = [0.0] * (2 * n)
        cell.InterpolationDerivs([r, t, 0.0], d)
        dr, ds = np.array(d[:n]), np.array(d[n:])
        jr, js = xy.transpose(0, 2, 1) @ dr, xy.transpose(0, 2, 1) @ ds  # (cells, 2)
        det = jr[:, 0] * js[:, 1] - jr[:, 1] * js[:, 0]
        total += det.sum() / 6.0  # weight 1/6: the reference triangle's area is 1/2
        smallest = min(smallest, det.min())
    return total, smallest


def close(a, b, rel):
    """|a - b| <= rel |b| elementwise (exact zeros must stay zeros)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, f"shapes {a.shape} and {b.shape}"
    worst = np.max(np.abs(a - b) - rel * np.abs(b)) if a.size else 0.0
    return worst <= 0.0


def check_grid(grid, summary, area=None, contact=False, friction=False):
    """The grid against the run's summary: counts, types, node order, arrays."""
    mesh = summary["mesh"]
    assert grid.GetNumberOfPoints() == mesh["nodes"]
    assert grid.GetNumberOfCells() == mesh["elements"]
    conn, types = cells(grid)
    t6 = mesh["element"] == "T6"
    assert conn.shape[1] == (6 if t6 else 3)
    assert np.all(types == (VTK_QUADRATIC_TRIANGLE if t6 else VTK_TRIANGLE))
    assert conn.min() >= 0 and conn.max() < mesh["nodes"]
    x = vtk_to_numpy(grid.GetPoints().GetData())
    assert x.shape == (mesh["nodes"], 3) and np.all(x[:, 2] == 0.0)
    a, b, c = (x[conn[:, k], :2] for k in range(3))
    twice_area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    assert np.all(twice_area > 0), "an element is not counter-clockwise"
    if t6:
        # VTK's quadratic triangle: mid-side 3 on edge 0-1, 4 on 1-2, 5 on 2-0. A mid-side node
        # of a curved boundary sits off the chord's midpoint by far less than a tenth of it.
        for mid, (i, j) in ((3, (0, 1)), (4, (1, 2)), (5, (2, 0))):
            chord = x[conn[:, j], :2] - x[conn[:, i], :2]
            off = x[conn[:, mid], :2] - 0.5 * (x[conn[:, i], :2] + x[conn[:, j], :2])
            assert np.all(np.linalg.norm(off, axis=1) < 0.1 * np.linalg.norm(chord, axis=1)), \
                f"mid-side node {mid} is not on edge {i}-{j}"
    total, smallest_det = vtk_area(x, conn, t6)
    assert smallest_det > 0, "a cell folded by its node order"
    if area is not None:
        assert abs(total / area - 1) < area_tolerance(summary), f"area {total} against {area}"
    expected = dict(POINT_ARRAYS, **(CONTACT_ARRAYS if contact else {}),
                    **(FRICTION_ARRAYS if friction else {}))
    assert components(grid, "point") == expected
    assert components(grid, "cell") == CELL_ARRAYS
    for name, values in {**point_arrays(grid), **cell_arrays(grid)}.items():
        assert np.all(np.isfinite(values)), name
    body = cell_arrays(grid)["body_id"]
    assert set(np.unique(body)) == set(range(int(body.max()) + 1))


def area_tolerance(summary):
    # Straight-sided domains: exact to round-off (1e-12). The Hertz quarter disk's arc of
    # 500 mm radius in T6 chords of up to 40 mm (0.08 rad): a parabola through the ends and the
    # mid-side node on the arc misses about R² θ⁵ / 1000 a cell, below 1e-6 of the quarter disk.
    return 1e-6 if summary["mesh"]["element"] == "T6" else 1e-12


def check_against_nodes_csv(grid, out):
    """The VTU's fields against nodes.csv, which prints 12 significant digits."""
    n = read_csv(out / "nodes.csv")
    x = vtk_to_numpy(grid.GetPoints().GetData())
    p = point_arrays(grid)
    assert np.array_equal(n["node"], np.arange(1, grid.GetNumberOfPoints() + 1))
    assert close(x[:, 0], n["x"], PRINTED) and close(x[:, 1], n["y"], PRINTED)
    assert close(p["displacement"][:, 0], n["ux"], PRINTED)
    assert close(p["displacement"][:, 1], n["uy"], PRINTED)
    assert np.all(p["displacement"][:, 2] == 0.0)
    for k, name in enumerate(("sx", "sy", "sxy")):
        assert close(p["stress_smoothed"][:, k], n[name], PRINTED), name
    assert close(p["von_mises_smoothed"], n["vm"], PRINTED)
    assert close(p["reaction"][:, 0], n["rx"], PRINTED)
    assert close(p["reaction"][:, 1], n["ry"], PRINTED)
    # Not all zeros: the comparison compares something.
    assert np.max(np.abs(p["displacement"])) > 0 and np.max(np.abs(p["von_mises_smoothed"])) > 0


def check_against_contact_csv(grid, out):
    """Contact pressure and force at the slave nodes against contact.csv, zero elsewhere."""
    c = read_csv(out / "contact.csv")
    p = point_arrays(grid)
    slave = c["node"].astype(int) - 1
    assert close(p["contact_pressure"][slave], c["pressure"], PRINTED)
    assert close(p["contact_force"][slave], c["force"], PRINTED)
    assert close(p["contact_gap"][slave], c["gap"], PRINTED)
    others = np.setdiff1d(np.arange(grid.GetNumberOfPoints()), slave)
    assert np.all(p["contact_pressure"][others] == 0.0)
    assert np.max(p["contact_pressure"]) > 0


def check_series(out, summary, contact=False, area=None, friction=False):
    """results.pvd and every VTU it lists; returns the grids in order."""
    series = read_pvd(out / "results.pvd")
    steps = read_csv(out / "steps.csv")
    assert len(series) == summary["steps"] == len(steps["step"])
    times = np.array([t for t, _ in series])
    assert close(times, steps["load_factor"], PRINTED), f"{times} != {steps['load_factor']}"
    assert np.all(np.diff(times) > 0)
    files = [f for _, f in series]
    assert files == [f"step_{int(k):04d}.vtu" for k in steps["step"]]
    assert sorted(p.name for p in out.glob("*.vtu")) == sorted(files)
    grids = []
    for _, f in series:
        grid = read_vtu(out / f)
        check_grid(grid, summary, area=area, contact=contact, friction=friction)
        grids.append(grid)
    check_against_nodes_csv(grids[-1], out)
    if contact:
        check_against_contact_csv(grids[-1], out)
    return grids, steps


def same_fields(binary, ascii):
    """The binary and the ASCII run's arrays: the same solve, the ASCII one printed."""
    for name, a in {**point_arrays(binary), **cell_arrays(binary)}.items():
        b = (point_arrays(ascii) | cell_arrays(ascii))[name]
        assert close(b, a, PRINTED), name
    assert np.array_equal(vtk_to_numpy(binary.GetCells().GetConnectivityArray()),
                          vtk_to_numpy(ascii.GetCells().GetConnectivityArray()))


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Each example run once, in both encodings where the test compares them."""
    base = tmp_path_factory.mktemp("vtk_outputs")
    done = {}

    def get(name, scene, *sets, extra=()):
        if name not in done:
            out = base / name
            done[name] = (out, run(out, scene, *sets, extra=extra))
        return done[name]
    return get


@pytest.mark.parametrize("encoding", ["binary", "ascii"])
def test_linear_t6_hertz(runs, encoding):
    out, s = runs("hertz_" + encoding, "hertz_rigid_fast.toml", "output.vtu=" + encoding)
    assert s["status"] == "converged" and s["mesh"]["element"] == "T6"
    head = (out / "step_0001.vtu").read_bytes()[:400].decode("latin-1")
    assert ('format="ascii"' in head) == (encoding == "ascii")
    grids, _ = check_series(out, s, contact=True, area=math.pi * 500.0**2 / 4)
    assert len(grids) == 1


@pytest.mark.parametrize("encoding", ["binary", "ascii"])
def test_linear_t3_two_bodies(runs, encoding):
    out, s = runs("patch_" + encoding, "patch_test.toml", "output.vtu=" + encoding)
    assert s["status"] == "converged" and s["mesh"]["element"] == "T3"
    grids, _ = check_series(out, s, contact=True, area=4.0)
    body = cell_arrays(grids[0])["body_id"]
    assert set(np.unique(body)) == {0, 1}
    # The patch test's own answer, read through VTK: σyy = −10 in both blocks.
    assert np.allclose(cell_arrays(grids[0])["stress_element"][:, 1], -10.0, rtol=1e-6)


def test_binary_and_ascii_hold_the_same_fields(runs):
    for name, scene in (("hertz", "hertz_rigid_fast.toml"), ("patch", "patch_test.toml")):
        b = read_vtu(runs(name + "_binary", scene, "output.vtu=binary")[0] / "step_0001.vtu")
        a = read_vtu(runs(name + "_ascii", scene, "output.vtu=ascii")[0] / "step_0001.vtu")
        same_fields(b, a)


def tip_node(grid, at):
    x = vtk_to_numpy(grid.GetPoints().GetData())[:, :2]
    d = np.linalg.norm(x - np.asarray(at), axis=1)
    # gmsh places the corner node within round-off of the probe's point (6e-12 of 1000 here).
    assert d.min() < 1e-12 * np.abs(x).max(), "no node at the probe's point"
    return int(np.argmin(d))


@pytest.mark.parametrize("encoding", ["binary", "ascii"])
def test_load_stepped_t6_series(runs, encoding):
    # The elastica: 10 load steps, a cantilever 1000 long, tip probes at (1000, 0).
    out, s = runs("elastica_" + encoding, "elastica.toml", "output.vtu=" + encoding)
    assert s["status"] == "converged" and s["steps"] == 10
    grids, steps = check_series(out, s)
    tip = tip_node(grids[0], (1000.0, 0.0))
    for k, grid in enumerate(grids):  # each step's VTU holds that step's state
        u = point_arrays(grid)["displacement"][tip]
        assert close(u[1], steps["tip_uy"][k], PRINTED) and close(u[0], steps["tip_ux"][k], PRINTED)
    # The series moves: the tip's deflection grows step by step.
    assert np.all(np.diff(-steps["tip_uy"]) > 0)


def test_load_stepped_frictional_series_in_thirtieths(runs):
    # A block dragged along a base with Coulomb friction in 30 load steps: λ = 1/30, 2/30, ...
    # are no round numbers, so the PVD's time steps must carry every digit of the load factor.
    out, s = runs("drag", "drag.toml")
    assert s["status"] == "converged" and s["steps"] == 30
    grids, steps = check_series(out, s, contact=True, friction=True, area=6.0 + 0.5)
    assert close(steps["load_factor"], np.arange(1, 31) / 30.0, PRINTED)
    # Each step's VTU holds that step's contact state: its active count against steps.csv.
    for k, grid in enumerate(grids):
        active = np.count_nonzero(point_arrays(grid)["contact_pressure"] > 0)
        assert active == steps["contact_active_nodes"][k], f"step {k + 1}"


def test_mesh_verb_writes_a_grid_vtk_reads(runs, tmp_path):
    out = tmp_path / "mesh"
    text = contact2d("mesh", os.path.join(EXAMPLES, "patch_test.toml"), "--out", str(out))
    # "T3 mesh: N nodes, E elements, D DOFs, ..."
    words = text.split("mesh:")[1].split(",")
    nodes, elements = int(words[0].split()[0]), int(words[1].split()[0])
    grid = read_vtu(out / "mesh.vtu")
    check_grid(grid, {"mesh": {"nodes": nodes, "elements": elements, "element": "T3"}}, area=4.0)
    # The same mesh as the run's.
    _, s = runs("patch_binary", "patch_test.toml", "output.vtu=binary")
    assert (nodes, elements) == (s["mesh"]["nodes"], s["mesh"]["elements"])


def test_adaptive_cycles_series(runs):
    # The cantilever (3 x 0.4, T6), coarse, refined once by the ZZ estimate: two cycles.
    out, s = runs("adapt", "cantilever.toml", "analysis.mesh_scale=4",
                  extra=["--adapt", "target=0.002", "max_cycles=2"])
    series = read_pvd(out / "adapt.pvd")
    cycles = read_csv(out / "adapt.csv")
    assert len(series) == 2 and cycles["dofs"][1] > cycles["dofs"][0]
    assert [t for t, _ in series] == list(cycles["cycle"])
    assert [f for _, f in series] == [f"cycle_{int(c):02d}.vtu" for c in cycles["cycle"]]
    for (_, f), nodes, elements in zip(series, cycles["nodes"], cycles["elements"]):
        grid = read_vtu(out / f)
        check_grid(grid, {"mesh": {"nodes": int(nodes), "elements": int(elements),
                                   "element": "T6"}}, area=3.0 * 0.4)
    # The last cycle is the run's result.
    assert grid.GetNumberOfPoints() == s["mesh"]["nodes"]
    check_against_nodes_csv(grid, out)


def test_damaged_files_are_caught(runs, tmp_path):
    # The checks can fail: a truncated VTU, a cell type changed, two mid-side nodes swapped, a
    # PVD cut short.
    out, _ = runs("patch_binary", "patch_test.toml", "output.vtu=binary")
    data = (out / "step_0001.vtu").read_bytes()
    cut = tmp_path / "cut.vtu"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(AssertionError, match="VTK"):
        read_vtu(cut)
    ascii_out, s = runs("patch_ascii", "patch_test.toml", "output.vtu=ascii")
    text = (ascii_out / "step_0001.vtu").read_text()
    start = text.index('Name="types"')
    values = text[start:].split(">", 1)[1].split("<", 1)[0]
    wrong = tmp_path / "wrong_type.vtu"
    wrong.write_text(text.replace(values, values.replace("5", "22", 1), 1))
    with pytest.raises(AssertionError):
        check_grid(read_vtu(wrong), s, contact=True)
    hertz, s = runs("hertz_binary", "hertz_rigid_fast.toml", "output.vtu=binary")
    grid = read_vtu(hertz / "step_0001.vtu")
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())  # a view: edits the grid
    conn[[3, 4]] = conn[[4, 3]]  # the first cell's mid-sides of edges 0-1 and 1-2
    with pytest.raises(AssertionError, match="mid-side node 3"):
        check_grid(grid, s, contact=True)
    pvd = (hertz / "results.pvd").read_text()
    short = tmp_path / "short.pvd"
    short.write_text(pvd[: pvd.index("</Collection>")])
    with pytest.raises(AssertionError, match="could not parse"):
        read_pvd(short)
