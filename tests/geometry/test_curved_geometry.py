"""Cylinders, rings and extruded outlines: validation, exact face areas, curved quadratic meshes, scene files."""

import math

import numpy as np
import pytest
from skfem import Basis, ElementTetP2, FacetBasis, Functional

from modalfe.errors import MeshError, SceneError
from modalfe.geometry.parts import Assembly, Box, Face
from modalfe.geometry.shapes import Cylinder, Extrusion, Ring
from modalfe.models.mesh import build_mesh
from modalfe.scene.loading import scene_from_dict

_one = Functional(lambda w: 1.0 + 0.0 * w.x[0])
PLATE = Box("plate", "plate", "steel", (0.0, 0.0, 0.0), (0.04, 0.03, 0.002))
DISC = Cylinder("disc", "piezo", "PZT-5A", (0.02, 0.015, 0.002), "z", 0.008, 0.001, poling=1)


@pytest.mark.parametrize("make, message", [
    (lambda: Cylinder("c", "r", "steel", (0, 0, 0), "z", 0.0, 1e-3), "radius must be positive"),
    (lambda: Cylinder("c", "r", "steel", (0, 0, 0), "w", 1e-3, 1e-3), "axis must be one of"),
    (lambda: Ring("r", "r", "steel", (0, 0, 0), "z", 2e-3, 2e-3, 1e-3), "inner radius"),
    (lambda: Cylinder("c", "r", "PZT-4", (0, 0, 0), "z", 1e-3, 1e-3, poling="radial"), "radial poling needs a ring"),
    (lambda: Extrusion("e", "r", "steel", ((0, 0), (1, 1), (1, 0), (0, 1)), "z", 0.0, 0.1), "intersects itself"),
    (lambda: Extrusion("e", "r", "steel", ((0, 0), (1, 0), (1, 1), (0, 1)), "z", 0.0, 0.1,
                       holes=(((0.5, 0.5), (1.5, 0.5), (1.5, 0.8)),)), "holes[0] is not inside the outline"),
    (lambda: Assembly((PLATE, Cylinder("c", "r", "steel", (0.02, 0.015, 0.001), "z", 0.005, 0.002))), "overlap"),
    (lambda: Assembly((PLATE, DISC), {"g": (Face("disc", "zmax"),)}), "face side must be one of"),
])
def test_bad_shapes_are_refused_naming_the_field(make, message):
    with pytest.raises(SceneError, match=message.replace("[", r"\[").replace("]", r"\]")):
        make()


def test_a_ring_around_a_shaft_does_not_overlap_it_and_a_disc_on_a_plate_is_bonded():
    shaft = Cylinder("shaft", "s", "steel", (0, 0, 0), "x", 1e-3, 0.01)
    ring = Ring("ring", "r", "PZT-4", (0.004, 0, 0), "x", 1e-3, 3e-3, 2e-3, poling="radial")
    Assembly((shaft, ring))  # the shaft fills the bore exactly: touching, not overlapping
    assert Assembly((PLATE, DISC)).components() == [("plate", "disc")]
    off = Cylinder("off", "r", "steel", (0.05, 0.05, 0.002), "z", 0.003, 0.001)  # corner of its box only
    assert len(Assembly((PLATE, off)).components()) == 2


def test_curved_tet_mesh_has_exact_rim_top_and_volume():
    """Quadratic geometry: the rim's mid-edge nodes lie on the circle, so the rim area and the disc's volume are
    those of the true cylinder to the quadratic interpolation's error (measured ~1e-7 relative; tolerance 1e-5),
    where a polygonal rim of chords h ~ 2 mm on R = 8 mm would be short by (h/R)^2 / 24 ~ 0.3 %."""
    assembly = Assembly((PLATE, DISC), {"rim": (Face("disc", "outer"),), "top": (Face("disc", "top"),),
                                        "under": (Face("plate", "zmin"),)})
    dm = build_mesh(assembly, size=0.003, element="tet", min_layers=1, use_cache=False)
    m = dm.mesh
    assert type(m).__name__ == "MeshTet2"
    mid = m.doflocs[:, m.nvertices:]
    r = np.hypot(mid[0] - 0.02, mid[1] - 0.015)
    on_rim = np.isclose(r, 0.008, atol=1e-6) & (mid[2] > 0.002 + 1e-7)
    assert on_rim.sum() > 50
    chord = 0.5 * (m.p[:, m.edges[0]] + m.p[:, m.edges[1]])
    assert np.abs(r[on_rim] - 0.008).max() < 1e-9 and np.hypot(*(chord[:2, on_rim] - [[0.02], [0.015]])).min() < 0.008
    for group in ("rim", "top", "under"):
        area = _one.assemble(FacetBasis(m, ElementTetP2(), facets=dm.faces[group]))
        assert area == pytest.approx(assembly.face_area(group), rel=1e-5), group
    volume = _one.assemble(Basis(m, ElementTetP2(), elements=dm.parts["disc"]))
    assert volume == pytest.approx(DISC.volume, rel=1e-5)


def test_extrusion_with_holes_meshes_its_hole_walls():
    square = ((0.0, 0.0), (0.04, 0.0), (0.04, 0.03), (0.0, 0.03))
    hole = ((0.01, 0.01), (0.02, 0.01), (0.02, 0.02), (0.01, 0.02))
    n = 16
    circle = tuple((0.03 + 0.004 * math.cos(2 * math.pi * k / n), 0.015 + 0.004 * math.sin(2 * math.pi * k / n))
                   for k in range(n))
    plate = Extrusion("plate", "plate", "steel", square, "z", 0.0, 0.002, holes=(hole, circle))
    assembly = Assembly((plate,), {g: (Face("plate", g),) for g in ("side", "hole_1", "hole_2", "top")})
    dm = build_mesh(assembly, size=0.004, element="tet", min_layers=1, use_cache=False)
    for group in assembly.faces:
        area = _one.assemble(FacetBasis(dm.mesh, ElementTetP2(), facets=dm.faces[group]))
        assert area == pytest.approx(assembly.face_area(group), rel=1e-9), group


def test_hexahedra_asked_with_cylinders_on_two_axes_name_mesh_element():
    """Swept hexahedra need every curved part on one axis (modalfe.models.swept); a pin on the side does not."""
    pin = Cylinder("pin", "pin", "steel", (0.04, 0.015, 0.001), "x", 0.0005, 0.004)  # on the plate's xmax face
    assert Assembly((PLATE, DISC)).sweep_axis == 2 and Assembly((PLATE, DISC, pin)).sweep_axis is None
    with pytest.raises(MeshError, match=r"^mesh\.element: .*different axes .*set mesh\.element = 'tet'"):
        build_mesh(Assembly((PLATE, DISC, pin)), size=0.003, element="hex", use_cache=False)


def test_scene_file_with_a_disc_loads_in_file_units_and_is_solid_only():
    data = {"units": "mm", "parts": [
        {"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [40, 30, 2]},
        {"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [20, 15, 2], "axis": "z",
         "radius": 8, "height": 1, "poling": "+z"}],
        "faces": {"electrode_top": ["disc.top"], "electrode_bottom": ["disc.bottom"]},
        "electrodes": {"electrode_top": "drive", "electrode_bottom": "ground"},
        "analysis": {"near": 10e3}, "mesh": {"element": "tet"}}
    scene = scene_from_dict(data)
    disc = scene.assembly().part("disc")
    assert scene.kind == "solid" and scene.device == "shaped"
    assert disc.radius == pytest.approx(0.008) and disc.poling == "+z"
    with pytest.raises(SceneError, match="kind"):
        scene_from_dict({**data, "kind": "plate"})
    with pytest.raises(SceneError, match=r"parts\[1\].radius"):
        scene_from_dict({**data, "parts": [data["parts"][0], {**data["parts"][1], "radius": -1}]})
    with pytest.raises(SceneError, match="covers both"):
        scene_from_dict({**data, "faces": {"electrode_top": ["disc.top", "disc.bottom"]},
                         "electrodes": {"electrode_top": "drive"}})


def test_cube_plate_round_feet_and_sensor_become_cylinders_on_a_solid_swept_hex_scene():
    from modalfe.scene import load_scene

    scene = load_scene("cube_plate", foot_shape="round", sensor=(32e-3, 34.5e-3), sensor_shape="round",
                       symmetry=[])
    full = scene.full_assembly()
    assert scene.kind == "solid" and scene.mesh.element == "hex"  # every cylinder stands on z: swept hexahedra
    assert isinstance(full.part("foot_1"), Cylinder) and full.part("foot_1").radius == pytest.approx(1.5e-3)
    assert full.face_area("foot_1") == pytest.approx(math.pi * 1.5e-3**2)
    assert full.face_area("sensor_top") == pytest.approx(math.pi * 2.5e-3**2)
    with pytest.raises(SceneError, match="foot_shape"):
        load_scene("cube_plate", foot_shape="oval")
    # the feet lie off the y mid-plane: the symmetric half keeps two of them whole
    half = load_scene("cube_plate", foot_shape="round").assembly()
    assert sorted(p.name for p in half.parts if isinstance(p, Cylinder)) == ["foot_1", "foot_2"]
    # a round sensor centred on the y mid-plane is cut through its axis: the half keeps half of it, its cut face in
    # the mirror condition's group (tests/models/test_symmetry_curved.py solves such halves against the whole)
    cut = load_scene("cube_plate", sensor=(32e-3, 19e-3), sensor_shape="round", ceramic_rows=(8e-3, 30e-3)).assembly()
    assert cut.part("sensor").cuts == ((1, pytest.approx(19e-3)),)
    assert Face("sensor", "cut_y") in cut.faces["symmetry_y"]
    assert cut.part("sensor").volume == pytest.approx(0.5 * math.pi * 2.5e-3**2 * 1e-3)
    # off the plane by 0.5 mm, it has no mirror image: the half would not stand for the whole
    with pytest.raises(SceneError, match=r"^symmetry: part 'sensor' has no mirror image about the y mid-plane$"):
        load_scene("cube_plate", sensor=(32e-3, 19.5e-3), sensor_shape="round", ceramic_rows=(8e-3, 30e-3))


def test_round_hole_in_an_extrusion_is_curved_and_named_after_the_polygon_holes():
    square = ((0.0, 0.0), (0.04, 0.0), (0.04, 0.03), (0.0, 0.03))
    hole = ((0.005, 0.005), (0.01, 0.005), (0.01, 0.01), (0.005, 0.01))
    plate = Extrusion("plate", "plate", "CuBe", square, "z", 0.0, 0.002, holes=(hole,),
                      circles=((0.025, 0.015, 0.006),))
    assert plate.sides[-1] == "hole_2" and plate.area("hole_2") == pytest.approx(2 * math.pi * 0.006 * 0.002)
    assembly = Assembly((plate,), {"round": (Face("plate", "hole_2"),), "top": (Face("plate", "top"),)})
    dm = build_mesh(assembly, size=0.003, element="tet", min_layers=1, use_cache=False)
    # curved P2 geometry: the volume is exact to ~(h/R)^4; a polygonal hole of chords h ~ 2 mm would lose
    # ~2 pi^2 / (3 n^2) ~ 2 % of the hole's area (n ~ 19 chords), 0.17 % of the plate's volume
    volume = _one.assemble(Basis(dm.mesh, ElementTetP2(), intorder=4))
    assert volume == pytest.approx(plate.volume, rel=1e-4)
    m = dm.mesh
    wall = np.unique(m.facets[:, dm.faces["round"]])
    assert np.allclose(np.hypot(m.p[0, wall] - 0.025, m.p[1, wall] - 0.015), 0.006, atol=1e-9)
    top = _one.assemble(FacetBasis(m, ElementTetP2(), facets=dm.faces["top"]))
    assert top == pytest.approx(assembly.face_area("top"), rel=1e-4)
    with pytest.raises(SceneError, match=r"circles\[0\] overlaps holes\[0\]"):
        Extrusion("p", "p", "CuBe", square, "z", 0.0, 0.002, holes=(hole,), circles=((0.012, 0.008, 0.003),))
    with pytest.raises(SceneError, match=r"circles\[0\] is not inside"):
        Extrusion("p", "p", "CuBe", square, "z", 0.0, 0.002, circles=((0.038, 0.015, 0.003),))


def test_curved_mesh_survives_the_disk_cache(tmp_path, monkeypatch):
    from modalfe.models import mesh as meshing

    monkeypatch.setenv("MODALFE_CACHE", str(tmp_path))
    assembly = Assembly((Cylinder("d", "d", "PZT-5A", (0, 0, 0), "z", 0.005, 0.001),), {"top": (Face("d", "top"),)})
    first = build_mesh(assembly, size=0.002, element="tet", min_layers=1)
    meshing._memory_cache.pop(first.key)
    again = build_mesh(assembly, size=0.002, element="tet", min_layers=1)
    assert again.seconds == 0.0 and type(again.mesh).__name__ == "MeshTet2"
    assert np.array_equal(again.mesh.doflocs, first.mesh.doflocs) and np.array_equal(again.mesh.t, first.mesh.t)
    assert np.array_equal(again.faces["top"], first.faces["top"])
