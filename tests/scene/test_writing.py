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
WINDOWED = {"honeycomb_tile"}  # face groups on windows of a face (mounts, actuator pad): not in the file format


def _round_trip(scene, tmp_path):
    path = tmp_path / f"{scene.name}.toml"
    path.write_text(scene_to_toml(scene), encoding="utf-8")
    return load_scene(path)


@pytest.mark.parametrize("name", sorted(set(BUILTIN) - WINDOWED))
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


def test_windowed_face_refused():
    with pytest.raises(SceneError, match=r"^faces\.\w+: a window"):
        scene_to_toml(load_scene("honeycomb_tile"))


def test_odd_values_written(tmp_path):
    scene = load_scene("tile_eq5").with_overrides(**{"materials.eq5.source": 'a "quoted" note, \u00e9',
                                                     "mesh.max_size": 0.05, "drive.damping": "zeta=0.01"})
    assert _round_trip(scene, tmp_path) == dataclasses.replace(scene, assumptions=())
