"""CAD and mesh import (issue 20, item 2): a .geo script (tests/geometry/data/plate_two_holes.geo), BREP and STEP
files and .msh meshes written with gmsh's API at test time, read into meshio meshes with the part and face cell
sets of modalfe.models.mesh, and the one-line errors for bad files. Volumes and areas are checked against the
exact geometry: a 40 x 30 x 2 mm plate with two 3 mm-radius holes and a 6 mm-radius, 0.5 mm disc on top."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from modalfe.errors import MeshError
from modalfe.geometry.imported import read_geometry

DATA = Path(__file__).parent / "data"
GEO = DATA / "plate_two_holes.geo"
PARTS = {"plate": {"material": "CuBe"}, "ceramic": {"material": "PZT-4"}}
FACES = ("clamp", "electrode_top")
SIZE = 3e-3
PLATE = 0.04 * 0.03 * 0.002 - 2 * math.pi * 0.003**2 * 0.002  # [m^3]
CERAMIC = math.pi * 0.006**2 * 0.0005
ELECTRODE = math.pi * 0.006**2  # [m^2]
CLAMP = 0.03 * 0.002


def _measure(mesh):
    """(volume per part [m^3], area per face group [m^2]) of a meshio mesh through scikit-fem (which also checks
    that the 10-node tetrahedra are numbered as it expects: a wrong node order gives wrong curved volumes)."""
    from skfem import Basis, ElementTetP1, FacetBasis, Functional
    from skfem.io.meshio import from_meshio

    sk = from_meshio(mesh, ignore_orientation=True)
    one = Functional(lambda w: 1.0 + 0.0 * w.x[0])
    volumes = {k[5:]: one.assemble(Basis(sk, ElementTetP1(), elements=v)) for k, v in sk.subdomains.items()}
    areas = {k[5:]: one.assemble(FacetBasis(sk, ElementTetP1(), facets=v)) for k, v in sk.boundaries.items()}
    return volumes, areas


def _bottom_area(mesh) -> float:
    """Area [m^2] of the boundary facets at z = 0 (the plate's underside) of a meshio mesh."""
    from skfem import ElementTetP1, FacetBasis, Functional
    from skfem.io.meshio import from_meshio

    sk = from_meshio(mesh, ignore_orientation=True)
    on_bottom = np.all(np.abs(sk.p[2, sk.facets[:, sk.boundary_facets()]]) < 1e-12, axis=0)
    facets = sk.boundary_facets()[on_bottom]
    return Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(FacetBasis(sk, ElementTetP1(), facets=facets))


@pytest.mark.parametrize("order", [1, 2])
def test_geo_script_parts_and_faces(order):
    mesh = read_geometry(GEO, volumes=PARTS, faces=FACES, size=SIZE, order=order)
    assert set(mesh.cell_sets) == {"part:plate", "part:ceramic", "face:clamp", "face:electrode_top"}
    assert mesh.cells[0].type == ("tetra" if order == 1 else "tetra10")
    volumes, areas = _measure(mesh)
    # the clamp is a flat rectangle: exact at any order (round-off only)
    assert areas["clamp"] == pytest.approx(CLAMP, rel=1e-12)
    if order == 1:
        # straight-sided: the 6 mm disc is a polygon of >= 12 sides per turn (CURVATURE_ELEMENTS), area
        # n/2 sin(2 pi/n) / pi = 0.955 of the circle's at n = 12, closer to 1 with more sides
        assert 0.95 < areas["electrode_top"] / ELECTRODE < 1.0
        assert volumes["ceramic"] / CERAMIC == pytest.approx(areas["electrode_top"] / ELECTRODE, rel=1e-9)
        # the holes are polygons inscribed in the 3 mm circles, >= 12 sides: they miss between 0 and
        # 1 - 12/(2 pi) sin(2 pi/12) = 4.51 % of the circles' area, on the underside and through the thickness
        # (the mean cross-section, volume / thickness); a plate volume off by more (a hole lost, a wrong node
        # order) fails
        holes = 2 * math.pi * 0.003**2
        polygon_deficit = 1 - 12 / (2 * math.pi) * math.sin(2 * math.pi / 12)
        for area in (_bottom_area(mesh), volumes["plate"] / 0.002):
            assert 0.0 < (area - (0.04 * 0.03 - holes)) / holes <= polygon_deficit * (1 + 1e-9)
    else:
        # curved quadratic tetrahedra: a quadratic arc over 1/12 of a turn misses the circle by ~1e-5 of its
        # area (measured 1.1e-4 at most with gmsh's curved boundary nodes); 5e-4 leaves margin
        assert areas["electrode_top"] == pytest.approx(ELECTRODE, rel=5e-4)
        assert volumes["ceramic"] == pytest.approx(CERAMIC, rel=5e-4)
        assert volumes["plate"] == pytest.approx(PLATE, rel=5e-4)


def _occ_plate(gmsh, scale: float) -> None:
    """The plate with two holes and the bonded disc of the .geo fixture, built with the OCC API in units of
    ``scale`` metres, fragmented."""
    occ = gmsh.model.occ
    s = 1.0 / scale
    plate = occ.addBox(0, 0, 0, 0.04 * s, 0.03 * s, 0.002 * s)
    holes = [occ.addCylinder(x * s, 0.015 * s, 0, 0, 0, 0.002 * s, 0.003 * s) for x in (0.01, 0.03)]
    cut, _ = occ.cut([(3, plate)], [(3, h) for h in holes])
    disc = occ.addCylinder(0.02 * s, 0.015 * s, 0.002 * s, 0, 0, 0.0005 * s, 0.006 * s)
    occ.fragment(cut, [(3, disc)])
    occ.synchronize()


def _write_cad(tmp_path: Path, suffix: str, scale: float) -> Path:
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        # OpenCASCADE keeps the unit of the last STEP read (metres, by read_geometry) for the next write, across
        # gmsh sessions: declare the file's own unit
        gmsh.option.setString("Geometry.OCCTargetUnit", "MM" if scale == 1e-3 else "M")
        _occ_plate(gmsh, scale)
        path = tmp_path / f"plate{suffix}"
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def _wrapper(tmp_path: Path, cad: Path, coherence: bool = False) -> Path:
    """A .geo script naming the pieces of ``cad`` (volume 1: the plate, 2: the disc, as OCC numbers them after the
    fragment) and the faces, found by bounding boxes in metres (a STEP file is converted to metres on import);
    ``coherence``: fragment the merged solids first (gmsh ``Coherence``)."""
    e = 1e-6
    text = f"""SetFactory("OpenCASCADE");
Merge "{cad.name}";
{"Coherence;" if coherence else ""}
Physical Volume("plate") = {{1}};
Physical Volume("ceramic") = {{2}};
Physical Surface("clamp") = Surface In BoundingBox{{{-e}, {-e}, {-e}, {e}, {0.03 + e}, {0.002 + e}}};
Physical Surface("electrode_top") = Surface In BoundingBox{{{0.014 - e}, {0.009 - e}, {0.0025 - e},
    {0.026 + e}, {0.021 + e}, {0.0025 + e}}};
"""
    path = tmp_path / f"{cad.stem}_{cad.suffix[1:]}.geo"
    path.write_text(text)
    return path


@pytest.mark.parametrize(("suffix", "unit"), [(".brep", 1.0), (".step", 1e-3)])
def test_cad_files_named_by_a_geo_wrapper(tmp_path, suffix, unit):
    # STEP declares millimetres (gmsh writes it so): read back in metres; BREP has no unit: read as metres. A STEP
    # file keeps each solid's own faces (the fragment's shared face is lost, as in most CAD exports): the merged
    # solids are fragmented again by the wrapper's Coherence
    cad = _write_cad(tmp_path, suffix, unit)
    wrapper = _wrapper(tmp_path, cad, coherence=suffix == ".step")
    mesh = read_geometry(wrapper, volumes=PARTS, faces=FACES, size=SIZE, order=2)
    assert np.ptp(mesh.points, axis=0) == pytest.approx([0.04, 0.03, 0.0025], rel=1e-9)
    volumes, areas = _measure(mesh)
    assert volumes["plate"] == pytest.approx(PLATE, rel=5e-4)  # as for the .geo script's curved mesh
    assert areas["electrode_top"] == pytest.approx(ELECTRODE, rel=5e-4)


def test_a_step_assembly_not_fragmented_is_non_conforming(tmp_path):
    cad = _write_cad(tmp_path, ".step", 1e-3)
    with pytest.raises(MeshError, match=r"plate_step.geo: pieces touch without sharing nodes near .* \(parts "
                                        r"'ceramic' and 'plate'\): non-conforming"):
        read_geometry(_wrapper(tmp_path, cad), volumes=PARTS, faces=FACES, size=SIZE, order=1)


def test_a_bare_cad_file_has_unnamed_pieces(tmp_path):
    cad = _write_cad(tmp_path, ".brep", 1.0)
    with pytest.raises(MeshError, match=r"plate.brep: no physical volume named 'plate'; the file has none"):
        read_geometry(cad, volumes=PARTS, faces=FACES, size=SIZE, order=1)
    with pytest.raises(MeshError, match=r"volume 1 \(bounding box .*\) belongs to no physical volume"):
        read_geometry(cad, volumes={}, faces=(), size=SIZE, order=1)


def _write_msh(tmp_path: Path, order: int) -> Path:
    """The .geo fixture meshed by gmsh and saved as a .msh file (with its physical groups)."""
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(GEO))
        gmsh.option.setNumber("Mesh.MeshSizeMax", SIZE)
        gmsh.option.setNumber("Mesh.ElementOrder", order)
        gmsh.model.mesh.generate(3)
        path = tmp_path / f"plate_{order}.msh"
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def test_msh_files_are_read_as_they_are(tmp_path):
    linear, quadratic = _write_msh(tmp_path, 1), _write_msh(tmp_path, 2)
    mesh = read_geometry(linear, volumes=PARTS, faces=FACES, size=float("nan"), order=1)  # size unused
    assert mesh.cells[0].type == "tetra" and set(mesh.cell_sets) == {f"part:{p}" for p in PARTS} | {
        f"face:{f}" for f in FACES}
    curved = read_geometry(quadratic, volumes=PARTS, faces=FACES, size=SIZE, order=2)
    assert curved.cells[0].type == "tetra10"
    assert _measure(curved)[0]["plate"] == pytest.approx(PLATE, rel=5e-4)
    # linear tetrahedra asked at order 2: made quadratic with straight sides, so the volume is the linear one's
    raised = read_geometry(linear, volumes=PARTS, faces=FACES, size=SIZE, order=2)
    assert raised.cells[0].type == "tetra10"
    assert _measure(raised)[0]["plate"] == pytest.approx(_measure(mesh)[0]["plate"], rel=1e-9)
    with pytest.raises(MeshError, match=r"mesh.order: plate_2.msh holds quadratic tetrahedra; set the order to 2"):
        read_geometry(quadratic, volumes=PARTS, faces=FACES, size=SIZE, order=1)


def test_missing_unreadable_and_unknown_files(tmp_path):
    with pytest.raises(MeshError, match=r"geometry.file: '.*nowhere.step' does not exist"):
        read_geometry(tmp_path / "nowhere.step", volumes=PARTS, faces=FACES, size=SIZE, order=1)
    with pytest.raises(MeshError, match=r"geometry.file: 'plate.stl' is not a STEP, BREP, .geo or .msh file"):
        read_geometry(tmp_path / "plate.stl", volumes=PARTS, faces=FACES, size=SIZE, order=1)
    junk = tmp_path / "junk.msh"
    junk.write_text("this is not a mesh\n")
    with pytest.raises(MeshError, match=r"geometry.file: 'junk.msh' is not a gmsh mesh file"):
        read_geometry(junk, volumes=PARTS, faces=FACES, size=SIZE, order=1)
    broken = tmp_path / "broken.geo"
    broken.write_text("Point(1) = {0, 0, 0};\nPoint(2) = {1, 0, 0}\n")
    with pytest.raises(MeshError, match=r"geometry.file: gmsh cannot read 'broken.geo': .*line 2: syntax error"):
        read_geometry(broken, volumes=PARTS, faces=FACES, size=SIZE, order=1)
    # gmsh's parser is usable again after the syntax error (it was not: every later file failed to parse)
    assert "part:plate" in read_geometry(GEO, volumes=PARTS, faces=FACES, size=SIZE, order=1).cell_sets


def test_group_names_must_match_the_file():
    with pytest.raises(MeshError, match=r"no physical volume named 'foot'; the file has 'ceramic', 'plate'"):
        read_geometry(GEO, volumes={**PARTS, "foot": {}}, faces=FACES, size=SIZE, order=1)
    with pytest.raises(MeshError, match=r"no physical surface named 'clamp_2'; the file has 'clamp', 'electrode_top'"):
        read_geometry(GEO, volumes=PARTS, faces=("clamp_2",), size=SIZE, order=1)
    with pytest.raises(MeshError, match=r"physical volume 'ceramic' is no part of the scene"):
        read_geometry(GEO, volumes={"plate": {}}, faces=FACES, size=SIZE, order=1)


def test_touching_pieces_without_shared_nodes_are_refused(tmp_path):
    # the disc on the plate without BooleanFragments: each volume is meshed on its own, the plate's top face and
    # the disc's bottom face coincide but share no nodes
    text = GEO.read_text().replace("BooleanFragments{ Volume{4, 5}; Delete; }{}", "")
    script = tmp_path / "unfused.geo"
    script.write_text(text)
    with pytest.raises(MeshError, match=r"unfused.geo: pieces touch without sharing nodes near .* \(parts 'ceramic' "
                                        r"and 'plate'\): non-conforming"):
        read_geometry(script, volumes=PARTS, faces=FACES, size=SIZE, order=1)


def _prism_mesh(path: Path, with_block: bool) -> None:
    """A square pad extruded in two layers (prisms, physical volume 'pad'), and apart from it, if ``with_block``,
    a block extruded without layers (tetrahedra, 'block'), written to ``path``."""
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        geo = gmsh.model.geo
        pad = geo.extrude([(2, _square(geo, 0.0))], 0, 0, 0.002, numElements=[2], recombine=True)
        block = geo.extrude([(2, _square(geo, 0.02))], 0, 0, 0.002) if with_block else []
        geo.synchronize()
        gmsh.model.addPhysicalGroup(3, [t for d, t in pad if d == 3], name="pad")
        if with_block:
            gmsh.model.addPhysicalGroup(3, [t for d, t in block if d == 3], name="block")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.003)
        gmsh.model.mesh.generate(3)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def _square(geo, x0: float) -> int:
    """A 10 x 10 mm square at z = 0 from x = ``x0`` (gmsh built-in kernel): its surface tag."""
    corners = [geo.addPoint(x0 + dx, dy, 0) for dx, dy in ((0, 0), (0.01, 0), (0.01, 0.01), (0, 0.01))]
    lines = [geo.addLine(a, b) for a, b in zip(corners, corners[1:] + corners[:1])]
    return geo.addPlaneSurface([geo.addCurveLoop(lines)])


def test_mixed_and_unsupported_element_types(tmp_path):
    _prism_mesh(tmp_path / "mixed.msh", with_block=True)
    with pytest.raises(MeshError, match=r"mixed.msh: mixed volume element types \(.*Prism.*\); use one type"):
        read_geometry(tmp_path / "mixed.msh", volumes={"pad": {}, "block": {}}, faces=(), size=SIZE, order=1)
    _prism_mesh(tmp_path / "prisms.msh", with_block=False)
    with pytest.raises(MeshError, match=r"prisms.msh: volume elements 'Prism 6' are not supported"):
        read_geometry(tmp_path / "prisms.msh", volumes={"pad": {}}, faces=(), size=SIZE, order=1)
