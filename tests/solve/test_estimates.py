"""Error-estimate levels and the API's refusals of ambiguous requests (issue 16, items 3 and 5)."""

import pytest

from modalfe.errors import SolverError
from modalfe.solve.api import solve_modes
from modalfe.solve.rung import level_layers
from tests.oracles.cases import free_plate_scene


@pytest.mark.parametrize(("layers", "expected"), [(1, (1, 1)), (2, (2, 1)), (3, (2, 1)), (4, (3, 2)), (6, (4, 3))])
def test_coarse_levels_refine_the_thickness_between_them(layers, expected):
    # the two coarse levels (x1.5, x2.25) differ in thickness layers wherever the fine level has >= 2, so the
    # cross-check's extrapolation sees the through-thickness error; 3 -> (2, 1) is the seed devices' (unchanged)
    assert (level_layers(layers, 1.5), level_layers(layers, 2.25)) == expected


@pytest.mark.parametrize(("kwargs", "field"), [
    ({"near": 5e3, "count": 0}, "count:"),
    ({"near": 5e3, "count": -3}, "count:"),
    ({"near": 5e3, "count": 2.5}, "count:"),
    ({"near": 5e3, "band": (1e3, 9e3)}, "near:"),
])
def test_ambiguous_requests_are_refused_naming_the_field(kwargs, field):
    # before: count=0 silently used the scene's count, near with band silently dropped near
    with pytest.raises(SolverError) as info:
        solve_modes(free_plate_scene(), **kwargs)
    message = str(info.value)
    assert message.startswith(field) and "\n" not in message


def test_a_level_solved_without_labels_has_the_labelled_frequencies_and_says_so():
    # the reduced models' coarser Richardson levels are solved unlabelled (paired by shape, then dropped)
    import numpy as np

    from modalfe.scene import Analysis, load_scene
    from modalfe.solve.levels import UNLABELLED, solve_level

    scene = load_scene("tile_eq5")
    analysis = Analysis(near=845.0, count=6)
    labelled = solve_level(scene, analysis, fidelity="plate", size_factor=1.5)
    bare = solve_level(scene, analysis, fidelity="plate", size_factor=1.5, labels=False)
    assert np.allclose(bare.frequencies, labelled.frequencies, rtol=1e-8, atol=0)
    assert {m.label for m in bare} == {UNLABELLED} and UNLABELLED not in {m.label for m in labelled}
    assert all(np.isnan(m.wavelength) for m in bare)
