"""Stated >= actual where an estimate level leaves part of the device uncoarsened (issue 34, item 4): the scenes of
studies/level_coverage.py against references of their own, each with its uncertainty (the change of the reference's
last refinement), which the comparison allows: the stated error must cover the actual one to within what the
reference itself may be off. The stack (~45 s) and the cantilever refined to tol are slow; the strip (~7 s) and the
cantilever on its grid (~2 s) run by default."""

from dataclasses import replace

import pytest

from modalfe.models.build import build_model
from modalfe.solve.api import solve_modes
from modalfe.solve.estimates import unresolved_edges
from modalfe.solve.fidelity import solve_estimated
from modalfe.solve.rung import Rung
from tests.oracles.cases import cantilever_plate_scene, stack_scene, strip_scene

# T2 of the disc stack: Lagrange order 4 on the scene's 0.75 mm swept grid (218,070 DOFs); order 3 there 191,610.204 Hz
STACK_T2 = 191_589.041
STACK_T2_UNCERTAINTY = 1.1e-4
# the strip-supported plate's modes: order 4 on the scene's 1.2 mm grid (151,524 DOFs); from x1.5 that grid they moved
# by 6.2e-3, 1.6e-3, 3.9e-3 and 1.3e-3 (the clamped strip's edges are singular: convergence is slow)
STRIP = {"(1,0)": (16_594.7333, 6.2e-3), "(0,0)": (21_956.3702, 1.7e-3), "(1,1)": (23_092.152, 3.9e-3),
         "(0,1)": (27_745.2812, 1.4e-3)}
# the thin cantilever plate: order 4 on the scene's 2.5 mm grid halved (123,552 DOFs); moved from the 2.5 mm grid by
# 7.0e-4, 1.8e-3, 7.1e-4 and 7.6e-4
CANTILEVER = {"(0,0)": (353.0582, 7.0e-4), "(1,0)": (2_147.1619, 1.8e-3), "(0,1)": (2_203.3542, 7.1e-4),
              "(0,2)": (6_175.3236, 7.6e-4)}


def _covered(mode, reference: float, uncertainty: float) -> bool:
    return mode.error_estimate + uncertainty >= abs(mode.frequency / reference - 1)


@pytest.mark.slow
def test_the_stacked_disc_torsion_mode_is_covered_on_its_grid_and_where_the_solid_refines_to_tol():
    # the ceramic is 2 layers on the scene's grid and on the x1.5 level (ceil(1.2 / 0.75) = ceil(1.2 / 1.125)):
    # that level is not a step; after one refinement the reused x2.25 level keeps the x1.5 one's 2 layers
    scene = stack_scene()
    grid = solve_estimated(Rung(scene), scene.analysis, "solid")
    assert "x1.5 (its part 'ceramic' along z" in grid.estimate_method
    t2 = grid.labelled("T2", near=STACK_T2)
    assert _covered(t2, STACK_T2, STACK_T2_UNCERTAINTY)
    solid = solve_modes(scene, fidelity="solid")
    assert "no order observed" in solid.estimate_method
    assert _covered(solid.labelled("T2", near=STACK_T2), STACK_T2, STACK_T2_UNCERTAINTY)


def test_a_strip_supported_plate_states_at_least_its_error():
    scene = strip_scene()
    grid = solve_estimated(Rung(scene), scene.analysis, "solid")
    assert "x1.5 (its part 'plate' along y" in grid.estimate_method  # the 2 mm strip: 2 elements on both
    for label, (reference, uncertainty) in STRIP.items():
        assert _covered(grid.labelled(label, near=reference), reference, uncertainty), label


def test_a_thin_cantilever_plate_states_at_least_its_error_on_its_grid():
    scene = cantilever_plate_scene()
    grid = solve_estimated(Rung(scene), scene.analysis, "solid")
    for label, (reference, uncertainty) in CANTILEVER.items():
        assert _covered(grid.labelled(label, near=reference), reference, uncertainty), label


@pytest.mark.slow
def test_a_thin_cantilever_plate_refined_to_tol_states_at_least_its_error():
    # its quartic grids are 3.3-7.5 mm wide over 0.5 mm: the edge zones lie inside the elements, and the p-estimate
    # takes the rate floor 1 (estimates.UNRESOLVED_P_RATE); at the floor 2 the twisting mode (1,0) stated 0.55 % against
    # at least 0.65 %. No allowance: the conforming order-4 reference bounds the exact value from above
    solid = solve_modes(cantilever_plate_scene(), fidelity="solid")
    assert "edge zones inside the elements" in solid.estimate_method
    for label, (reference, _) in CANTILEVER.items():
        mode = solid.labelled(label, near=reference)
        assert mode.error_estimate >= mode.frequency / reference - 1, label


@pytest.mark.parametrize(("thickness", "unresolved"), [(0.5, True), (1.5, False)])
def test_a_quartic_grid_wider_than_four_thicknesses_leaves_the_edge_zones_unresolved(thickness, unresolved):
    # auto's second quartic step of the cantilever: 5 mm elements (x2 of the 2.5 mm grid), one layer; 5 > 4 x 0.5 mm,
    # 5 < 4 x 1.5 mm
    scene = cantilever_plate_scene(thickness=thickness)
    quartic = replace(scene, mesh=replace(scene.mesh, order=4, family="lagrange", min_layers=1))
    model, _ = build_model(quartic, size_factor=2.0)
    assert bool(unresolved_edges(model.mesh, quartic)) is unresolved
