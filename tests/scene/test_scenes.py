"""Scenes: every built-in scene and registered builder, overrides, scene files and bad input."""

import inspect
import json
import pickle
from typing import Any

import numpy as np
import pytest

from modalfe.errors import MeshError, SceneError
from modalfe.geometry import BUILDERS, SCENE_FILE_DEVICES, builder_parameters, check_parameters
from modalfe.scene import load_scene, scene_from_dict
from modalfe.scene.builtin import BUILTIN
from modalfe.scene.frozen import FrozenMap
from modalfe.scene.materials import MATERIALS, material
from tests.helpers import assert_one_line_error

BEAM_FILE = """
name = "bimorph"
units = "mm"
kind = "beam"
[analysis]
near = 2000.0
count = 4
[materials.steel]
E = 200e9
nu = 0.3
rho = 7850.0
[[parts]]
name = "beam"
material = "steel"
origin = [0, 0, 0]
size = [40, 4, 1]
[[parts]]
name = "patch"
region = "piezo"
material = "PZT-5A"
origin = [5, 0, 1]
size = [10, 4, 0.2]
poling = 1
[faces]
clamp = ["beam.xmin"]
electrode_top = ["patch.zmax"]
electrode_bottom = ["patch.zmin"]
[electrodes]
electrode_top = "drive"
electrode_bottom = "ground"
[clamps]
clamp = "xyz"
[[working_modes]]
selector = "bending-z 1"
near = 500.0
targets = [{name = "guess", value = 500.0}]
"""


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_every_builtin_scene_validates_and_builds(name):
    scene = load_scene(name)
    assembly = scene.assembly()
    assert assembly.parts, name
    assert scene.working_modes, f"{name} names no working mode"
    for wm in scene.working_modes:
        assert wm.targets and all(t.source for t in wm.targets)


@pytest.mark.parametrize("name", sorted(set(BUILDERS) - set(SCENE_FILE_DEVICES)))
def test_every_registered_builder_declares_typed_parameters_its_defaults_pass(name):
    parameters = builder_parameters(name)
    assert list(parameters) == list(inspect.signature(BUILDERS[name]).parameters)
    for p in parameters.values():
        assert p.kind is not Any, f"{name}.{p.name} has no type"
        if p.kind is float:
            assert p.unit and p.constraint is not None, f"{name}.{p.name}: a number without unit or constraint"
        p.check(p.default)  # the defaults are valid values of their own parameters
    check_parameters(name, {p.name: p.default for p in parameters.values()})
    assert BUILDERS[name](**{p.name: p.default for p in parameters.values()}) == BUILDERS[name]()


def test_overrides_change_the_geometry():
    thin = load_scene("cube_plate", ceramic_thickness=0.65e-3).assembly().part("ceramic_1")
    assert thin.size[2] == pytest.approx(0.65e-3)
    scene = load_scene("cube_plate", **{"mesh.elements_per_wavelength": 8, "analysis.near": 41e3})
    assert scene.mesh.elements_per_wavelength == 8 and scene.analysis.near == 41e3


def test_scene_file_in_millimetres_equals_metres(tmp_path):
    path = tmp_path / "bimorph.toml"
    path.write_text(BEAM_FILE)
    mm = load_scene(path)
    metres = BEAM_FILE.replace('units = "mm"', 'units = "m"')
    for a, b in (("[40, 4, 1]", "[0.04, 0.004, 0.001]"), ("[5, 0, 1]", "[0.005, 0, 0.001]"),
                 ("[10, 4, 0.2]", "[0.01, 0.004, 0.0002]")):
        metres = metres.replace(a, b)
    (tmp_path / "m.toml").write_text(metres)
    m = load_scene(tmp_path / "m.toml")
    for pa, pb in zip(mm.assembly().parts, m.assembly().parts):
        np.testing.assert_allclose(pa.lo, pb.lo, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(pa.hi, pb.hi, rtol=1e-12, atol=1e-15)
    assert mm.material("steel").rho == 7850.0


def _one_line_error(exc_info, *words):
    text = str(exc_info.value)
    assert "\n" not in text
    for w in words:
        assert w in text, f"'{w}' not named in: {text}"


@pytest.mark.parametrize("key,value,field", [
    ("thickness", 0.0, "thickness"),
    ("thickness", -3e-3, "thickness"),
    ("ceramic_length", -1e-3, "ceramic_length"),
    ("length", float("nan"), "length"),
])
def test_bad_sizes_name_the_field(key, value, field):
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", **{key: value})
    _one_line_error(info, field)


def test_foot_off_the_plate_is_refused():
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", feet=((70e-3, 6e-3),))
    _one_line_error(info, "feet[0]", "off the plate")


def test_ceramic_off_the_plate_is_refused():
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", ceramic_pitch=20e-3)
    _one_line_error(info, "ceramic", "off the plate")


def test_overlapping_parts_are_refused():
    data = {"parts": [
        {"name": "a", "material": "CuBe", "origin": [0, 0, 0], "size": [1, 1, 1]},
        {"name": "b", "material": "CuBe", "origin": [0.5, 0.5, 0.5], "size": [1, 1, 1]},
    ], "analysis": {"near": 1000.0}}
    with pytest.raises(SceneError) as info:
        scene_from_dict(data)
    _one_line_error(info, "'a'", "'b'", "overlap")


def test_unknown_material_is_refused():
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", plate_material="unobtainium")
    _one_line_error(info, "unobtainium", "plate")


def test_material_tensor_must_be_positive_definite():
    C = np.eye(6) * 1e9
    C[0, 0] = -1e9
    with pytest.raises(SceneError) as info:
        material({"name": "bad", "C": C.tolist(), "rho": 1000.0})
    _one_line_error(info, "materials.bad.C", "positive definite")
    with pytest.raises(SceneError) as info:
        material({"name": "iso", "E": 1e9, "nu": 0.5, "rho": 1000.0})
    _one_line_error(info, "nu")


def test_piezo_grades_are_named_with_sources():
    for grade in ("PZT-4", "PZT-5A", "PZT-5H"):
        m = MATERIALS[grade]
        assert m.is_piezoelectric and "Berlincourt" in m.source
        # e31 < 0 < e33 for every poled PZT (Berlincourt 1964 tables)
        assert m.e[2, 0] < 0 < m.e[2, 2]


def test_poled_down_flips_the_coupling_only():
    up = MATERIALS["PZT-5A"]
    down = up.poled(-1)
    np.testing.assert_allclose(down.C, up.C, rtol=1e-12)
    np.testing.assert_allclose(down.e[2, :3], -up.e[2, :3], rtol=1e-12)


def test_unknown_parameter_and_bad_roles_name_the_field():
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", ceramic_colour="red")
    _one_line_error(info, "ceramic_colour")
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", **{"electrodes.electrode_top": "hot"})
    _one_line_error(info, "electrodes.electrode_top")
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", **{"springs.nowhere": [1.0, 1.0, 1.0]})
    _one_line_error(info, "springs.nowhere")
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", **{"analysis.band": [5e3, 1e3]})
    _one_line_error(info, "analysis.band")


def test_unknown_scene_and_bad_toml(tmp_path):
    with pytest.raises(SceneError) as info:
        load_scene("no_such_device")
    _one_line_error(info, "no_such_device")
    bad = tmp_path / "bad.toml"
    bad.write_text("parts = [[[")
    with pytest.raises(SceneError) as info:
        load_scene(bad)
    _one_line_error(info, "bad.toml")


def test_empty_or_failed_mesh_is_a_mesh_error():
    from modalfe.models.mesh import build_mesh

    assembly = BUILDERS["ciliary_beam"]()
    with pytest.raises(MeshError) as info:
        build_mesh(assembly, size=0.0)
    _one_line_error(info, "size")
    with pytest.raises(MeshError) as info:
        build_mesh(assembly, size=1e-3, element="prism")
    _one_line_error(info, "mesh.element")


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_scenes_are_immutable_and_equal_scenes_hash_equal(name):
    scene = load_scene(name)
    again = load_scene(name)
    assert scene == again and hash(scene) == hash(again)
    assert pickle.loads(pickle.dumps(scene)) == scene
    for table in ("params", "electrodes", "clamps", "springs", "masses", "materials"):
        with pytest.raises(TypeError):
            getattr(scene, table)["x"] = 1
    assert hash(scene.with_overrides(**{"mesh.elements_per_wavelength": 5})) != hash(scene)


def test_nested_scene_tables_are_frozen_too():
    scene = load_scene("tile_eq5")
    parts, material_table = scene.params["parts"], scene.materials["eq5"]
    assert isinstance(parts, tuple) and isinstance(parts[0], FrozenMap)
    assert isinstance(parts[0]["size"], tuple)
    with pytest.raises(TypeError):
        material_table["nu"] = 0.3
    # what consumers do with the tables still works
    assert dict(scene.clamps) == {"side_x": "yz", "side_y": "xz"}
    assert {**scene.clamps, **scene.symmetry_clamps}["symmetry_x"] == "x"
    assert json.loads(json.dumps(scene.params.to_dict()))["parts"][0]["size"] == [0.304, 0.304, 0.025]
    assert scene.params == {"parts": scene.params["parts"], "faces": scene.params["faces"]}
    changed = scene.with_overrides(**{"materials.eq5.nu": 0.1})
    assert changed.materials["eq5"]["nu"] == 0.1 and scene.materials["eq5"]["nu"] == 0.0


def test_overrides_from_lists_are_frozen_and_hash_like_tuples():
    as_list = load_scene("honeycomb_tile", **{"springs.mount_1": [1.0, 2.0, 3.0]})
    as_tuple = load_scene("honeycomb_tile", **{"springs.mount_1": (1.0, 2.0, 3.0)})
    assert as_list.springs["mount_1"] == (1.0, 2.0, 3.0)
    assert as_list == as_tuple and hash(as_list) == hash(as_tuple)
    feet = load_scene("cube_plate", feet=[[20.35e-3, 6e-3], [43.65e-3, 6e-3]], symmetry=[])
    assert feet.params["feet"] == ((20.35e-3, 6e-3), (43.65e-3, 6e-3))
    assert len(feet.assembly().faces) == 4  # two electrodes, two feet


def test_a_default_value_is_always_accepted():
    # bond_thickness >= 0, and 0.0 is its default: refused by the old name-suffix rule
    assert load_scene("cube_plate", bond_thickness=0.0).params["bond_thickness"] == 0.0
    assert load_scene("cube_plate", bond_thickness=0.05e-3).assembly().part("bond_1").size[2] == pytest.approx(5e-5)


def test_an_int_is_a_valid_float_parameter():
    scene = load_scene("ciliary_beam", length=1)
    assert scene.assembly().bounds[1][0] == 1


@pytest.mark.parametrize("key,value,message", [
    ("length", -3e-3, "length: must be positive, got -0.003 m"),
    ("bond_thickness", -1e-6, "bond_thickness: must be >= 0, got -1e-06 m"),
    ("thickness", True, "thickness: must be a number, got True"),
    ("thickness", "3e-3", "thickness: must be a number, got '3e-3'"),
    ("ceramic_columns", 2.5, "ceramic_columns: must be an integer, got 2.5"),
    ("ceramic_columns", True, "ceramic_columns: must be an integer, got True"),
    ("ceramic_columns", 0, "ceramic_columns: must be >= 1, got 0"),
    ("plate_material", 3, "plate_material: must be a string, got 3"),
    ("poled", 1, "poled: must be true or false, got 1"),
    ("length", float("inf"), "length: must be finite, got inf m"),
])
def test_bad_parameters_are_refused_from_the_builder_signature(key, value, message):
    assert_one_line_error(lambda: load_scene("cube_plate", **{key: value}), key, SceneError)
    with pytest.raises(SceneError) as info:
        load_scene("cube_plate", **{key: value})
    assert str(info.value) == message


def test_unknown_parameter_keeps_its_one_line_error():
    assert_one_line_error(lambda: load_scene("glass_plate", glass_colour="green"), "glass_colour", SceneError)
    with pytest.raises(SceneError) as info:
        load_scene("glass_plate", glass_colour="green")
    assert "not a parameter of glass_plate; known: [" in str(info.value)


def test_builder_parameters_are_data():
    p = builder_parameters("cube_plate")
    assert (p["length"].default, p["length"].unit, p["length"].constraint.text) == (64e-3, "m", "positive")
    assert p["bond_thickness"].constraint.text == ">= 0" and p["bond_thickness"].default == 0.0
    assert p["ceramic_columns"].type_name == "int" and p["ceramic_columns"].constraint.text == ">= 1"
    assert p["sensor"].type_name == "tuple[float, float] | None"
    assert_one_line_error(lambda: builder_parameters("no_such_builder"), "device", SceneError)


def test_a_mode_named_by_label_is_sought_near_that_working_mode():
    """issue 35: ``show honeycomb_tile --mode "(1,1)"`` was sought near the heave's 45 Hz, not the twist's 896 Hz."""
    from modalfe.solve.api import seek

    tile = load_scene("honeycomb_tile")
    assert seek(tile) == ("heave", 45.0)
    assert seek(tile, "(1,1)") == ("(1,1)", 896.0)
    assert seek(tile, "(1,1)#2") == ("(1,1)#2", 896.0)  # the pattern's working mode
    assert seek(tile, "(2,2)") == ("(2,2)", 45.0)  # no working mode of that label: the first's
    assert seek(tile, "(1,1)", 700.0) == ("(1,1)", 700.0)  # --near wins
