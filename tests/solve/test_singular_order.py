"""Where the field is singular, the solid's Richardson estimate uses the floor order MIN_ORDER = 1: which scenes
(``singular_field``), what the ceiling does to the estimate, and the Cu-Be plate's (0,6) at tol 0.5 % against the
limit of nested uniform refinement (studies/singular_convergence.py)."""

from dataclasses import replace
from types import SimpleNamespace

import pytest

from modalfe.results.modes import Mode, Modes, select
from modalfe.scene import load_scene
from modalfe.solve import estimates
from modalfe.solve.estimates import CONVERGENCE_ORDER, MIN_ORDER, richardson, singular_field
from tests.oracles.cases import cantilever_scene, diaphragm_plate_scene, free_plate_scene


def test_singular_sources_are_named_and_mirror_type_supports_are_not():
    assert singular_field(free_plate_scene()) == ""
    # the diaphragm fixes u_y, u_z on its x faces and u_x, u_z on its y faces: on each face both tangential
    # components, a mirror (antisymmetry) condition under which the field continues smoothly; one tangential
    # component alone is not
    diaphragm = diaphragm_plate_scene(0.04, 0.03, 1e-3, 5e-3)
    assert singular_field(diaphragm) == ""
    one_tangential = replace(diaphragm, clamps={**diaphragm.clamps, "x_edges": "z"})
    assert singular_field(one_tangential) == "clamps (x_edges)"
    assert "clamps" in singular_field(cantilever_scene(5e-3))  # all three components fixed at the root
    assert singular_field(load_scene("cube_plate")) == "bonded parts"
    assert singular_field(load_scene("honeycomb_tile")) == "bonded parts, springs, attached masses"


def _modes(frequencies):
    model = SimpleNamespace(scene=None)
    return Modes(tuple(Mode(i, f, f"mode {i}", None, model) for i, f in enumerate(frequencies)), model, "short",
                 "solid", 0)


@pytest.mark.parametrize("ceiling", [CONVERGENCE_ORDER, MIN_ORDER])
def test_the_ceiling_bounds_the_order_used(monkeypatch, ceiling):
    monkeypatch.setattr(estimates, "shape_partners",
                        lambda fine, coarse, *_: {m.index: (c, c.frequency, 1.0) for m, c in zip(fine, coarse)})
    exact, q, r = 1000.0, 3.0, 1.5  # steps of an order-3 sequence: observed 3, above both ceilings
    fine, coarse, coarsest = (_modes([exact * (1 + 0.01 * h**q)]) for h in (1.0, r, r * r))
    (stated,) = richardson(fine, coarse, r, coarsest, r * r, ceiling=ceiling).values()
    step = (coarse[0].frequency - fine[0].frequency) / fine[0].frequency
    assert stated == pytest.approx(step / (r**ceiling - 1), rel=1e-12)
    assert stated >= fine[0].frequency / exact - 1  # an order below the sequence's own over-states


def test_the_cube_plates_refined_estimates_cover_the_limit_of_nested_refinement():
    # the reference: the limit of nested uniform refinement of the mode's grid (studies/singular_convergence.py, to
    # 307,966 DOFs, at the order 1.34 its last three grids show) and how far it moves if the order falls to 1 beyond
    # them, as report_tolerance takes it. Both estimates auto can answer with must cover it: the h-estimate of the
    # quadratic grid it used to refine to (x0.444, 7 layers: 34,547 DOFs; at the ceiling 2 it stated 0.199 % against
    # 0.282 %) and the p-estimate of the quartic grid it now refines to first (``Rung.step``)
    from modalfe.report.report import window_modes, working_windows
    from modalfe.scene import Analysis
    from modalfe.solve.fidelity import solve_estimated
    from modalfe.solve.rung import Rung
    from tests.helpers import load_study

    limit, uncertainty = load_study("report_tolerance").NESTED["cube_plate", "(0,6)"]
    window = working_windows(load_scene("cube_plate"))[0]

    quadratic = solve_estimated(Rung(window.scene).refined(2), Analysis(near=40.7e3, count=10), "solid")
    mode = select(quadratic, "(0,6)", 40.7e3)
    assert quadratic.dofs == 34547
    # its x1.5 level keeps foot_1's 3 mm at the grid's element count: a two-level estimate from x2.25 at order 1
    assert "at order 1 (bonded parts); not used as a step: x1.5 (its part 'foot_1'" in quadratic.estimate_method
    assert mode.error_estimate >= abs(mode.frequency / limit - 1) + uncertainty

    modes = window_modes(window, fidelity="auto", tol=0.005)
    mode = select(modes, "(0,6)", 40.7e3)
    assert "order 4 on elements x3" in modes.fidelity_note and modes.estimate_method.startswith("p-refinement")
    assert mode.error_estimate <= 0.005
    assert mode.error_estimate >= abs(mode.frequency / limit - 1) + uncertainty
