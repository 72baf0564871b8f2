"""Antisymmetric mirror families (``Scene.antisymmetry``): the half (quarter) model with the tangential displacement
fixed on the cut returns exactly the whole device's modes that are odd about the plane, and the report solves a
working mode on its family (``WorkingMode.family_scene``)."""

import numpy as np
import pytest

from modalfe.errors import SceneError
from modalfe.geometry import builder_parameters
from modalfe.models.build import build_model
from modalfe.models.symmetry import unfold
from modalfe.response.loads import load_vector
from modalfe.scene import load_scene, scene_from_toml
from modalfe.scene.writing import scene_to_toml
from modalfe.solve.api import solve_modes
from tests.oracles.cases import free_plate_scene


@pytest.mark.parametrize("fidelity", ["solid", "plate"])
def test_the_two_half_models_together_are_the_whole_device(fidelity):
    # same nodes on both sides (y divisions 8 and 4): each half model is the whole discrete problem restricted to
    # fields even or odd about y = 5 mm, so together they hold every mode of the whole, to solver precision
    whole = solve_modes(free_plate_scene(), near=20e3, count=10, fidelity=fidelity, error_estimate=False)
    even = solve_modes(free_plate_scene(symmetry=["y"]), near=20e3, count=10, fidelity=fidelity,
                       error_estimate=False)
    odd = solve_modes(free_plate_scene(antisymmetry=["y"]), near=20e3, count=10, fidelity=fidelity,
                      error_estimate=False)
    halves = sorted([(m.frequency, m.label) for m in (*even, *odd) if m.frequency > 1.0])
    for mode in (m for m in whole if m.frequency > 1.0):
        f, label = min(halves, key=lambda h: abs(h[0] - mode.frequency))
        assert f == pytest.approx(mode.frequency, rel=1e-7)
        assert label == mode.label
    # and no half mode is foreign to the whole device within the whole's span
    span = [m.frequency for m in whole if m.frequency > 1.0]
    inside = [f for f, _ in halves if min(span) * (1 - 1e-6) <= f <= max(span) * (1 + 1e-6)]
    assert len(inside) == len(span)


def test_an_antisymmetric_field_unfolds_odd():
    # the image of a point across an antisymmetry plane carries the normal component unchanged and the two others
    # negated (u(-x) = -R u(x), R the reflection)
    scene = free_plate_scene(antisymmetry=["y"])
    points = np.array([[0.01], [0.002], [0.0005]])
    u = np.array([[1.0], [2.0], [3.0]])
    p, image = unfold(scene, points, u)
    assert p[1, 1] == pytest.approx(0.008)
    assert image[:, 1].tolist() == [-1.0, 2.0, -3.0]


def test_antisymmetry_is_refused_where_it_cannot_hold():
    with pytest.raises(SceneError, match="antisymmetry: not available with piezoelectric parts"):
        load_scene("cube_plate", antisymmetry=["x"]).assembly()
    with pytest.raises(SceneError, match="antisymmetry: the y mid-plane is listed twice"):
        free_plate_scene(symmetry=["y"], antisymmetry=["y"])
    scene = load_scene("honeycomb_tile", antisymmetry=["x", "y"])
    with pytest.raises(SceneError, match="antisymmetry: forced response"):
        load_vector(build_model(scene, "plate")[0], scene.drive.load)


def test_windows_are_clipped_by_the_cut():
    # the tile's actuator pad is centred: a quarter keeps a quarter of its window; a corner mount stays whole
    full = load_scene("honeycomb_tile").full_assembly()
    quarter = load_scene("honeycomb_tile", antisymmetry=["x", "y"]).assembly()
    assert quarter.face_area("actuator") == pytest.approx(full.face_area("actuator") / 4, rel=1e-12)
    assert quarter.face_area("mount_1") == pytest.approx(full.face_area("mount_1"), rel=1e-12)
    assert "mount_3" not in quarter.faces


def test_scene_files_keep_the_families(tmp_path):
    path = tmp_path / "tile.toml"
    path.write_text(scene_to_toml(load_scene("honeycomb_tile", antisymmetry=["x"])))
    again = scene_from_toml(path)
    assert again.antisymmetry == ("x",)
    twist = next(w for w in again.working_modes if w.selector == "(1,1)")
    assert twist.antisymmetric == ("x", "y")


def test_the_report_solves_a_working_mode_on_its_family_where_the_geometry_allows():
    scene = load_scene("honeycomb_tile")
    twist = next(w for w in scene.working_modes if w.selector == "(1,1)")
    family, note = twist.family_scene(scene)
    assert family.antisymmetry == ("x", "y") and family.symmetry == () and note == ""
    # moving one foot breaks the Cu-Be plate's mirror symmetry about x: its (0,6) falls back to the scene as declared
    cube = load_scene("cube_plate")
    feet = [list(f) for f in builder_parameters("cube_plate")["feet"].default]
    first = feet[0][0]
    for foot in feet:  # the pair of feet at the lowest x, moved alike (still mirror-symmetric about y)
        if foot[0] == first:
            foot[0] += 0.002
    moved = load_scene("cube_plate", feet=feet)
    working = moved.working_modes[0]
    family, note = working.family_scene(moved)
    assert family == moved and "not solved on its mirror family alone" in note
    family, note = working.family_scene(cube)
    assert family.symmetry == ("y", "x") and note == ""


def test_a_support_without_its_mirror_image_is_refused_by_a_half_model():
    # a half model stands for the other side by its image: a spring on one side only would be lost (its window in
    # the mirror half dropped) or doubled. Refused, naming the group, for symmetry and antisymmetry alike
    # (refused when the scene is loaded: its checks build the assembly)
    with pytest.raises(SceneError, match=r"^symmetry: springs\.pad has no mirror image of the same value"):
        free_plate_scene(symmetry=["y"], faces={"pad": [{"face": "plate.zmin",
                                                         "window": [[0.01, 0.001], [0.02, 0.003]]}]},
                         springs={"pad": [0.0, 0.0, 1e4]}).assembly()
    # the tile's four mounts mirror one another: equal springs pass, one stiffer mount is refused
    load_scene("honeycomb_tile", antisymmetry=["x", "y"]).assembly()
    with pytest.raises(SceneError, match=r"^antisymmetry: springs\.mount_1 has no mirror image of the same value"):
        load_scene("honeycomb_tile", antisymmetry=["x", "y"], **{"springs.mount_1": [1e5, 1e5, 1e6]}).assembly()
    # a centred window mirrors itself
    centred = free_plate_scene(symmetry=["y"], faces={"pad": [{"face": "plate.zmin",
                                                              "window": [[0.01, 0.002], [0.02, 0.008]]}]},
                               springs={"pad": [0.0, 0.0, 1e4]})
    assert centred.assembly().face_area("pad") == pytest.approx(0.01 * 0.003)
