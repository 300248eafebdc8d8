"""Gmsh `.msh` files and contact2d, checked with gmsh's own Python API (issue 35, item 3).

contact2d writes no `.msh` file (its meshes leave as VTU: `contact2d mesh` writes mesh.vtu); it
reads them (`mesh = { file = ... }`). So the check runs the other way: the `.msh` files a
scene can hold, read by gmsh's reader (Debian's python3-gmsh) and by contact2d, must give the
same mesh. `contact2d mesh` reports the node and element counts and writes mesh.vtu, read back
with VTK (vtkXMLUnstructuredGridReader); against gmsh's reading of the same file:
- the node count (nodes of the 2D elements) and the element count;
- the element type: gmsh's 3-node triangle (type 2) as VTK_TRIANGLE (5), the 6-node triangle
  (type 9) as VTK_QUADRATIC_TRIANGLE (22);
- every element, compared by its nodes' coordinates (to 1e-12 of the mesh size): the same
  corners, and each mid-side node on the same edge (gmsh's order 3: 0-1, 4: 1-2, 5: 2-0 is
  VTK's, whatever orientation contact2d gives the element).
Files: examples/legacy/v1_beam.msh (MSH 4.1, T3, as shipped) and a disk with a square hole
meshed by gmsh at order 2 (curved mid-sides on the circle) written as MSH 4.1 and 2.2.
"""
import os
import subprocess

import gmsh
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

BINARY = os.environ["C2D_BINARY"]
SOURCE = os.environ["C2D_SOURCE_DIR"]

GMSH_TRIANGLE, GMSH_TRIANGLE6 = 2, 9
VTK_TYPE = {GMSH_TRIANGLE: 5, GMSH_TRIANGLE6: 22}

VTK_LOG = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(VTK_LOG)

RING_SCENE = """title = "A disk with a square hole, meshed by gmsh"
[analysis]
kind = "plane_stress"
element = "T6"
[[material]]
name = "m"
E = 1.0
nu = 0.3
[[body]]
name = "plate"
material = "m"
mesh = {{ file = "{file}" }}
"""


def write_ring(folder):
    """A unit disk less a 0.6 square, meshed by gmsh at order 2: MSH 4.1 and 2.2 files."""
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("ring")
        occ = gmsh.model.occ
        out, _ = occ.cut([(2, occ.addDisk(0, 0, 0, 1.0, 1.0))],
                         [(2, occ.addRectangle(-0.3, -0.3, 0, 0.6, 0.6))])
        occ.synchronize()
        group = gmsh.model.addPhysicalGroup(2, [tag for _, tag in out])
        gmsh.model.setPhysicalName(2, group, "plate")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        paths = {}
        for version in ("4.1", "2.2"):
            gmsh.option.setNumber("Mesh.MshFileVersion", float(version))
            paths[version] = folder / f"ring_{version}.msh"
            gmsh.write(str(paths[version]))
        return paths
    finally:
        gmsh.finalize()


def gmsh_mesh(path):
    """gmsh's reading of a .msh: 2D element type, node coordinates per element (elements,
    nodes, 2), and the number of distinct nodes those elements use."""
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xy = dict(zip(tags, np.asarray(coords).reshape(-1, 3)[:, :2]))
        types, _, element_nodes = gmsh.model.mesh.getElements(2)
        assert len(types) == 1, f"{path}: 2D element types {list(types)}"
        etype = int(types[0])
        props = gmsh.model.mesh.getElementProperties(etype)  # name, dim, order, nodes, ...
        per = props[3]
        nodes = np.asarray(element_nodes[0]).reshape(-1, per)
        return etype, np.array([[xy[t] for t in e] for e in nodes]), len(np.unique(nodes))
    finally:
        gmsh.finalize()


def contact2d_mesh(scene, out):
    """`contact2d mesh`: its reported counts, and mesh.vtu's cells as read by VTK."""
    p = subprocess.run([BINARY, "mesh", str(scene), "--out", str(out)], capture_output=True,
                       text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    words = p.stdout.split("mesh:")[1].split(",")  # "T6 mesh: N nodes, E elements, ..."
    nodes, elements = int(words[0].split()[0]), int(words[1].split()[0])
    mark = len(VTK_LOG.GetOutput())
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(out / "mesh.vtu"))
    reader.Update()
    assert VTK_LOG.GetOutput()[mark:] == "", VTK_LOG.GetOutput()[mark:]
    grid = reader.GetOutput()
    x = vtk_to_numpy(grid.GetPoints().GetData())[:, :2]
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    types = vtk_to_numpy(grid.GetCellTypesArray())
    per = 6 if types[0] == 22 else 3
    return nodes, elements, grid.GetNumberOfPoints(), types, x[conn.reshape(-1, per)]


def element_keys(cells, scale):
    """Each element as its corners and, for T6, the mid-side node of each corner pair; node
    order and orientation aside. Coordinates rounded to 1e-12 of `scale`."""
    def key(p):
        return tuple(np.round(np.asarray(p) / (1e-12 * scale)).astype(np.int64))
    keys = set()
    for c in cells:
        corners = [key(p) for p in c[:3]]
        mids = ()
        if len(c) == 6:
            mids = frozenset((frozenset((corners[i], corners[j])), key(c[3 + k]))
                             for k, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))))
        keys.add((frozenset(corners), mids))
    return keys


@pytest.fixture(scope="module")
def ring(tmp_path_factory):
    return write_ring(tmp_path_factory.mktemp("gmsh_ring"))


def cases(ring):
    folder = next(iter(ring.values())).parent
    scenes = {"v1_beam": os.path.join(SOURCE, "examples", "legacy", "v1_beam.toml")}
    for version, path in ring.items():
        scene = folder / f"ring_{version}.toml"
        scene.write_text(RING_SCENE.format(file=path.name))
        scenes["ring_" + version] = scene
    return scenes


@pytest.mark.parametrize("name,msh,etype", [
    ("v1_beam", None, GMSH_TRIANGLE), ("ring_4.1", "4.1", GMSH_TRIANGLE6),
    ("ring_2.2", "2.2", GMSH_TRIANGLE6)])
def test_contact2d_reads_the_mesh_gmsh_reads(ring, tmp_path, name, msh, etype):
    scene = cases(ring)[name]
    path = ring[msh] if msh else os.path.join(SOURCE, "examples", "legacy", "v1_beam.msh")
    gmsh_type, gmsh_cells, gmsh_nodes = gmsh_mesh(path)
    assert gmsh_type == etype
    nodes, elements, points, types, cells = contact2d_mesh(scene, tmp_path / name)
    assert (nodes, elements) == (gmsh_nodes, len(gmsh_cells))
    assert points == nodes
    assert np.all(types == VTK_TYPE[etype])
    scale = np.abs(gmsh_cells).max()
    assert element_keys(cells, scale) == element_keys(gmsh_cells, scale)
    if etype == GMSH_TRIANGLE6:  # the circle's mid-side nodes are gmsh's, on the circle
        r = np.linalg.norm(cells[:, 3:].reshape(-1, 2), axis=1)
        assert np.isclose(r.max(), 1.0, rtol=0, atol=1e-12)


def test_a_different_mesh_is_caught(ring, tmp_path):
    # The comparison can fail: the ring's T6 elements with two mid-side nodes swapped.
    _, cells, _ = gmsh_mesh(ring["4.1"])
    scale = np.abs(cells).max()
    swapped = cells.copy()
    swapped[0, [3, 4]] = swapped[0, [4, 3]]
    assert element_keys(swapped, scale) != element_keys(cells, scale)
