"""scene_to_toml: every built-in scene written as a scene file reads back as the same device.

Same device: the same box assembly (parts, regions, materials, poling, face groups) and the same solid
eigenfrequencies to 1e-9 relative on a coarse mesh (the same boxes give the same gmsh mesh and matrices, so
only round-off in the coordinates, < 1 ulp of a metre-scale length, may differ: ~1e-15 in a frequency);
the same analysis, mesh settings, materials, supports, drive (but its seed targets, which the format has no
place for) and working modes; and a box scene (tile_eq5) equal as a Scene but for its assumption lines."""

import dataclasses

import numpy as np
import pytest

from modalfe.errors import SceneError
from modalfe.scene import load_scene
from modalfe.scene.builtin import BUILTIN
from modalfe.scene.writing import scene_to_toml
from modalfe.solve.api import solve_modes

COARSE = {"mesh.elements_per_wavelength": 1.0, "mesh.min_layers": 1, "mesh.order": 1}


def _round_trip(scene, tmp_path):
    path = tmp_path / f"{scene.name}.toml"
    path.write_text(scene_to_toml(scene), encoding="utf-8")
    return load_scene(path)


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_builtin_round_trip(name, tmp_path):
    scene = load_scene(name)
    back = _round_trip(scene, tmp_path)
    assert back.full_assembly() == scene.full_assembly()
    assert back.assembly() == scene.assembly()
    for field in ("name", "kind", "symmetry", "analysis", "mesh", "materials", "electrodes", "clamps", "springs",
                  "masses", "working_modes"):
        assert getattr(back, field) == getattr(scene, field), field
    assert back.drive == dataclasses.replace(scene.drive, targets=())
    assert scene_to_toml(_round_trip(back, tmp_path)) == scene_to_toml(back)  # a written file is a fixed point
    coarse, coarse_back = scene.with_overrides(**COARSE), back.with_overrides(**COARSE)
    near = scene.working_modes[0].near
    f = solve_modes(coarse, near=near, count=3, fidelity="solid", error_estimate=False).frequencies
    g = solve_modes(coarse_back, near=near, count=3, fidelity="solid", error_estimate=False).frequencies
    np.testing.assert_allclose(g, f, rtol=1e-9)


def test_box_scene_equal(tmp_path):
    scene = load_scene("tile_eq5")
    assert _round_trip(scene, tmp_path) == dataclasses.replace(scene, assumptions=())


def test_windowed_faces_in_a_scene_file(tmp_path):
    # the tile's mounts and actuator pad are windows of its facings: written as {face, window} tables, read back
    # in the file's units (mm here: the window scales with them)
    tile = load_scene("honeycomb_tile")
    windowed = {g: fs for g, fs in tile.full_assembly().faces.items() if any(f.window for f in fs)}
    assert windowed  # the case this test is about
    text = scene_to_toml(tile)
    assert '{face = "facing_bottom.zmin", window = [[' in text
    mm = tmp_path / "pad.toml"
    mm.write_text("""units = "mm"
[[parts]]
name = "plate"
material = "CuBe"
origin = [0, 0, 0]
size = [40, 30, 2]
[faces]
pad = [{face = "plate.zmin", window = [[10, 5], [20, 15]]}]
[masses]
pad = 0.01
[analysis]
near = 1000.0
count = 4
""", encoding="utf-8")
    (face,) = load_scene(mm).full_assembly().faces["pad"]
    assert face.window == ((0.01, 0.005), (0.02, 0.015))
    assert load_scene(mm).full_assembly().face_area("pad") == pytest.approx(1e-4, rel=1e-12)


@pytest.mark.parametrize("ref, message", [
    ({"face": "plate.zmin"}, r"^faces\.pad\[0\]: a windowed face needs"),
    ({"face": "plate.zmin", "window": [[10, 5]]}, r"^faces\.pad\[0\]\.window: "),
    ({"face": "plate.zmin", "window": [[10, 5], [50, 15]]}, r"face window on 'plate\.zmin' lies outside"),
    ({"face": "plate.zmin", "window": [[10, 5], [20, 15]], "depth": 1}, r"^faces\.pad\[0\]\.depth: unknown key"),
])
def test_bad_windows_named(ref, message):
    from modalfe.scene import scene_from_dict

    data = {"units": "mm", "analysis": {"near": 1000.0, "count": 4}, "faces": {"pad": [ref]},
            "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [40, 30, 2]}]}
    with pytest.raises(SceneError, match=message):
        scene_from_dict(data)


def test_builtin_with_round_parts_round_trip(tmp_path):
    # cube_plate's round feet and measurement ceramic are cylinders: written as shape tables, read back equal
    scene = load_scene("cube_plate", foot_shape="round", sensor=(0.032, 0.0345), sensor_shape="round", symmetry=[])
    back = _round_trip(scene, tmp_path)
    assert back.full_assembly() == scene.full_assembly()
    assert back.mesh == scene.mesh and back.kind == scene.kind == "solid"


def test_shaped_scene_round_trip(tmp_path):
    from modalfe.scene import scene_from_dict

    scene = scene_from_dict({
        "units": "mm", "name": "disc-on-plate", "analysis": {"near": 20e3, "count": 4},
        "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [30, 30, 1]},
                  {"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [15, 15, 1], "axis": "z",
                   "radius": 6, "height": 0.5, "poling": "+z"},
                  {"name": "ring", "shape": "ring", "material": "PZT-4", "centre": [15, 15, 1.5], "axis": "z",
                   "inner": 2, "outer": 4, "height": 0.5, "poling": "radial"}],
        "faces": {"top": ["disc.top"], "bottom": ["disc.bottom"], "inner": ["ring.inner"], "outer": ["ring.outer"]},
        "electrodes": {"top": "drive", "bottom": "ground", "inner": "drive", "outer": "ground"},
    })
    back = _round_trip(scene, tmp_path)
    assert back.full_assembly() == scene.full_assembly()
    assert back.mesh == scene.mesh and back.kind == scene.kind == "solid"
    assert scene_to_toml(back) == scene_to_toml(scene)


def test_odd_values_written(tmp_path):
    scene = load_scene("tile_eq5").with_overrides(**{"materials.eq5.source": 'a "quoted" note, \u00e9',
                                                     "mesh.max_size": 0.05, "drive.damping": "zeta=0.01"})
    assert _round_trip(scene, tmp_path) == dataclasses.replace(scene, assumptions=())


def test_imported_scene_round_trip(tmp_path):
    # a geometry-file scene is written with the file's absolute path and its parts by physical group; the faces
    # are the file's physical surfaces, so no [faces] table
    import shutil

    from tests.scene.test_imported_scene import GEO, PARTS, ROLES

    shutil.copy(GEO, tmp_path / "plate.geo")
    source = tmp_path / "scene.toml"
    source.write_text(f'name = "holed"\n[geometry]\nfile = "plate.geo"\n{PARTS}{ROLES}count = 1\n')
    scene = load_scene(source)
    text = scene_to_toml(scene)
    assert f'file = "{(tmp_path / "plate.geo").resolve()}"' in text and "[faces]" not in text
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    back = _round_trip(scene, elsewhere)
    assert back.params == scene.params
    assert back.full_assembly() == scene.full_assembly()
    assert scene_to_toml(back) == text


def test_a_sweep_table_knows_its_geometry_file(tmp_path):
    # a sweep resumes a table only for the same device: editing the geometry file changes the scene's identity
    import shutil

    from modalfe.design.sweep import scene_identity
    from tests.scene.test_imported_scene import GEO, PARTS, ROLES

    shutil.copy(GEO, tmp_path / "plate.geo")
    source = tmp_path / "scene.toml"
    source.write_text(f'name = "holed"\n[geometry]\nfile = "plate.geo"\n{PARTS}{ROLES}count = 1\n')
    before = scene_identity(str(source), load_scene(source))
    with open(tmp_path / "plate.geo", "a") as geo:
        geo.write("\n// edited\n")
    assert scene_identity(str(source), load_scene(source)) != before
