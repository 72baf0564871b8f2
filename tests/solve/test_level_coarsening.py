"""An estimate level that leaves a part or a face window's grid interval as finely meshed as the scene's grid is
detected (``modalfe.solve.estimates.uncoarsened``) and not used as a Richardson step (issue 34, item 4)."""

import math

import pytest

from modalfe.models.mesh import build_mesh
from modalfe.scene import scene_from_dict
from modalfe.solve.estimates import MIN_RATIO, axis_ratio, level_ratio, uncoarsened


def _layered():
    return scene_from_dict({
        "name": "layered", "units": "mm",
        "parts": [{"name": "plate", "material": "Al-5052", "origin": [0, 0, 0], "size": [12, 12, 2]},
                  {"name": "ceramic", "material": "PZT-5A", "origin": [4, 4, 2], "size": [4, 4, 0.5], "poling": 1}],
        "analysis": {"near": 10e3, "count": 4},
    })


def _mesh(scene, plate: float, ceramic: float, layers: int = 3):
    return build_mesh(scene.assembly(), size={"plate": plate, "ceramic": ceramic}, element="hex", min_layers=layers,
                      use_cache=False)


def test_a_part_whose_layers_round_to_the_same_count_is_not_coarsened():
    # 0.5 mm of ceramic: ceil(0.5 / 0.30) = ceil(0.5 / 0.45) = 2 layers on the scene's grid and the x1.5 level, while
    # the main plate coarsens (3 layers -> 2, elements 1.5 -> 2.25 mm): its own ratio passes, the ceramic's is 1
    scene = _layered()
    fine, coarse = _mesh(scene, 1.5e-3, 0.3e-3), _mesh(scene, 2.25e-3, 0.45e-3, 2)
    ratio, where = uncoarsened(fine, coarse, scene)
    assert ratio == pytest.approx(1.0)
    assert "'ceramic' along z" in where
    assert axis_ratio(fine, coarse, scene) >= MIN_RATIO  # the main part alone would have passed the level
    assert level_ratio(fine, coarse, scene) == (ratio, where)
    # the x2.25 level: 1 layer (ceil(0.5 / 0.675)), coarser by 2 through the ceramic
    coarsest = _mesh(scene, 3.375e-3, 0.675e-3, 1)
    ratio, _ = uncoarsened(fine, coarsest, scene)
    assert ratio >= MIN_RATIO


def test_a_window_strip_whose_element_count_does_not_change_is_not_coarsened():
    # a 3 mm strip clamped on the lower face: 2 elements across it at 1.6 mm and at 2.4 mm (ceil 1.88, 1.25)
    scene = scene_from_dict({
        "name": "strip", "units": "mm",
        "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [16, 16, 2]}],
        "faces": {"strip": [{"face": "plate.zmin", "window": [[0, 7], [16, 10]]}]}, "clamps": {"strip": "xyz"},
        "analysis": {"near": 10e3, "count": 4},
    })
    fine = build_mesh(scene.assembly(), size=1.6e-3, element="hex", min_layers=3, use_cache=False)
    coarse = build_mesh(scene.assembly(), size=2.4e-3, element="hex", min_layers=2, use_cache=False)
    ratio, where = uncoarsened(fine, coarse, scene)
    assert ratio == pytest.approx(1.0) and "along y" in where
    assert axis_ratio(fine, coarse, scene) >= MIN_RATIO


def test_one_element_across_is_not_a_failure_to_coarsen_and_tetrahedra_are_not_judged():
    scene = _layered()
    fine, coarse = _mesh(scene, 1.5e-3, 0.6e-3), _mesh(scene, 2.25e-3, 0.9e-3, 2)  # the ceramic: 1 layer on both
    ratio, where = uncoarsened(fine, coarse, scene)
    assert ratio >= MIN_RATIO or (math.isinf(ratio) and where == "")
    tet = build_mesh(scene.assembly(), size=2e-3, element="tet", min_layers=3, use_cache=False)
    assert uncoarsened(tet, tet, scene) == (math.inf, "")
