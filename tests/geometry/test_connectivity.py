"""Device-level checks: parts bonded into one body through face patches, electrodes that can be driven.

Each refused scene used to be accepted and solved (0.2 Hz "bending" of loose parts, zero or wrong
amplitudes); each now gives one SceneError line starting with the field or group at fault."""

import pytest

from modalfe.errors import SceneError
from modalfe.geometry.parts import Box, contact_area
from modalfe.scene import load_scene, scene_from_dict
from modalfe.scene.builtin import BUILTIN

PLATE = {"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [40, 10, 1]}
PATCH = {"name": "patch", "region": "piezo", "material": "PZT-5A", "origin": [10, 0, 1], "size": [10, 10, 0.2],
         "poling": 1}


def _scene(parts, faces=None, **extra):
    return scene_from_dict({"name": "t", "units": "mm", "kind": "plate", "parts": parts, "faces": faces or {},
                            "analysis": {"near": 5000.0, "count": 4}, **extra})


def _refused(prefix, *args, **kwargs):
    with pytest.raises(SceneError) as info:
        _scene(*args, **kwargs)
    message = str(info.value)
    assert message.startswith(prefix) and "\n" not in message, message
    return message


def _box(name, origin, size):
    return {"name": name, "material": "CuBe", "origin": origin, "size": size}


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_the_builtin_scenes_stay_valid(name):
    assert len(load_scene(name).full_assembly().components()) == 1


def test_contact_area_is_positive_only_for_a_shared_face_patch():
    a = Box("a", "a", "CuBe", (0, 0, 0), (1, 1, 1))
    assert contact_area(a, Box("b", "b", "CuBe", (1, 0.5, 0.5), (2, 2, 2))) == pytest.approx(0.25)
    assert contact_area(a, Box("c", "c", "CuBe", (1, 1, 0), (2, 2, 1))) == 0.0  # along an edge
    assert contact_area(a, Box("d", "d", "CuBe", (1, 1, 1), (2, 2, 2))) == 0.0  # at a corner
    assert contact_area(a, Box("e", "e", "CuBe", (1.1, 0, 0), (2, 1, 1))) == 0.0  # a gap


def test_a_disconnected_part_is_refused_naming_it():
    message = _refused("parts:", [PLATE, _box("loose", [50, 0, 0], [5, 5, 1])])
    assert "'loose'" in message and "touches no part" in message


@pytest.mark.parametrize("origin", [[40, 10, 0], [40, 10, 1], [10, 10, 1]], ids=["edge", "corner", "edge-on-top"])
def test_parts_touching_along_an_edge_or_at_a_corner_are_not_bonded(origin):
    message = _refused("parts:", [PLATE, _box("block", origin, [5, 5, 5])])
    assert "'block'" in message and "edge or at a corner" in message


def test_a_spring_to_ground_does_not_connect_a_loose_part():
    _refused("parts:", [PLATE, _box("loose", [50, 0, 0], [5, 5, 1])], {"pad": ["loose.zmin"]},
             springs={"pad": [0, 0, 1e6]})


def test_bonded_parts_through_a_chain_of_face_patches_are_accepted():
    parts = [PLATE, _box("a", [40, 0, 0], [5, 10, 1]), _box("b", [45, 2, 0], [5, 5, 1])]
    assert len(_scene(parts).full_assembly().components()) == 1


def _electrodes(faces, roles):
    return _scene([PLATE, PATCH], faces, electrodes=roles)


def test_a_face_both_driven_and_grounded_is_refused():
    with pytest.raises(SceneError) as info:
        _electrodes({"top": ["patch.zmax"], "top2": ["patch.zmax"]}, {"top": "drive", "top2": "ground"})
    assert str(info.value).startswith("electrodes.top:") and "both driven and grounded" in str(info.value)
    # the same place under two part names: the plate's top under the patch's bottom
    with pytest.raises(SceneError) as info:
        _electrodes({"bottom": ["patch.zmin"], "metal": ["plate.zmax"]}, {"bottom": "drive", "metal": "ground"})
    assert str(info.value).startswith("electrodes.bottom:")


def test_a_drive_face_touching_a_ground_face_along_an_edge_is_a_short_circuit():
    with pytest.raises(SceneError) as info:
        _electrodes({"top": ["patch.zmax"], "side": ["patch.xmax"]}, {"top": "drive", "side": "ground"})
    assert str(info.value).startswith("electrodes.top:") and "short circuit" in str(info.value)


def test_an_electrode_on_no_poled_part_is_refused():
    with pytest.raises(SceneError) as info:
        _electrodes({"top": ["patch.zmax"], "under": ["plate.zmin"]}, {"top": "drive", "under": "ground"})
    assert str(info.value).startswith("electrodes.under:") and "'plate.zmin'" in str(info.value)
    with pytest.raises(SceneError) as info:  # a device without any poled part
        _scene([PLATE], {"top": ["plate.zmax"]}, electrodes={"top": "drive"})
    assert str(info.value).startswith("electrodes.top:") and "no poled part" in str(info.value)


def test_one_group_on_both_faces_of_a_poled_part_is_refused():
    with pytest.raises(SceneError) as info:
        _electrodes({"both": ["patch.zmax", "patch.zmin"]}, {"both": "drive"})
    assert str(info.value).startswith("electrodes.both:") and "'patch'" in str(info.value)


def test_a_ground_electrode_on_a_metal_part_bonded_to_the_piezo_is_legitimate():
    # the plate's whole top face is the ground electrode: it touches the patch's bottom face
    scene = _electrodes({"top": ["patch.zmax"], "metal": ["plate.zmax"]}, {"top": "drive", "metal": "ground"})
    assert dict(scene.electrodes) == {"top": "drive", "metal": "ground"}
