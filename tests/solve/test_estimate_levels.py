"""The solid's error-estimate levels fail with a one-line reason naming the level, not the eigen solver's."""

import pytest

from modalfe.errors import SolverError
from modalfe.scene import scene_from_dict
from modalfe.solve import rung
from modalfe.solve.api import OWN_MESH, solve_modes


def test_an_estimate_level_without_unknowns_names_itself():
    """A plate clamped on its four edges, 20 mm quadratic serendipity elements over 40 x 30 mm: solvable, but its
    level with elements 1.5x larger keeps one element across the width and 6 free unknowns, fewer than the modes
    that level is asked for."""
    scene = scene_from_dict({
        "name": "clamped-plate", "units": "mm", "kind": "plate",
        "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [40, 30, 0.5]}],
        "faces": {"edges": ["plate.xmin", "plate.xmax", "plate.ymin", "plate.ymax"]},
        "clamps": {"edges": "xyz"}, "analysis": {"near": 5e3, "count": 6},
        "mesh": {"max_size": 0.02, "elements_per_wavelength": 1, "min_layers": 1},
    })
    assert len(solve_modes(scene, fidelity="solid", error_estimate=False)) == 6  # the level asked is fine
    with pytest.raises(SolverError, match=r"^error estimate: its level with elements x1\.5 cannot be solved") as info:
        solve_modes(scene, fidelity="solid", tol=OWN_MESH)
    assert "\n" not in str(info.value)


def test_the_order_step_level_is_solved_only_for_the_solids_own_estimate(monkeypatch):
    """At order 3 (Lagrange) the solid's stated error is at least the order 2-3 step on its grid; a reduced model
    asked directly uses only the two cross-check levels, so that extra solve must not happen for it."""
    from modalfe.solve import fidelity
    from tests.oracles.cases import free_plate_scene

    calls = []
    real = fidelity.order_step_level

    def counted(*args, **kwargs):
        calls.append(args[0].scene.mesh.order)
        return real(*args, **kwargs)

    monkeypatch.setattr(fidelity, "order_step_level", counted)
    scene = free_plate_scene().with_overrides(**{"mesh.order": 3, "mesh.min_layers": 1})
    plate = solve_modes(scene, fidelity="plate", count=4)
    assert plate.cross_check and not calls
    solid = solve_modes(scene, fidelity="solid", count=4, tol=OWN_MESH)
    assert calls == [3] and "at least the order 2-3 step" in solid.estimate_method


def test_tetrahedra_one_layer_thick_state_no_estimate_without_solving_levels(monkeypatch):
    # one tetrahedron across the thickness: the estimate levels would mesh exactly as the solid (the thickness caps
    # the size), so they are not solved and the modes say why; with two layers the levels coarsen and estimate
    from modalfe.scene import scene_from_dict

    data = {"units": "mm", "name": "disc", "analysis": {"near": 20e3, "count": 2},
            "mesh": {"element": "tet", "max_size": 6, "min_layers": 1},
            "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [30, 30, 1]},
                      {"name": "disc", "shape": "cylinder", "material": "CuBe", "centre": [15, 15, 1], "axis": "z",
                       "radius": 6, "height": 0.5}]}
    one = scene_from_dict(data)
    solved = []
    real = rung.solve_level
    monkeypatch.setattr(rung, "solve_level", lambda *a, **k: solved.append(k) or real(*a, **k))
    modes = solve_modes(one, fidelity="solid", tol=OWN_MESH)
    assert len(solved) == 1  # the solid only
    assert modes.estimate_method == rung.UNCOARSENED
    assert all(m.error_estimate == float("inf") for m in modes)
    # two layers: the first level keeps two (``level_layers``), so it meshes as the solid and Richardson would state
    # a zero error (it did: 0.000 % on a thin disc); three layers coarsen at every level
    for layers, reason in ((2, rung.UNCOARSENED), (3, None)):
        scene = scene_from_dict({**data, "mesh": {"element": "tet", "max_size": 6, "min_layers": layers}})
        assert rung.Rung(scene).no_estimate_reason == reason

