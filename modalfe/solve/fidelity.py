"""The fidelity ladder: a 1-D beam, a 2-D plate or the 3-D solid, and ``auto``, the cheapest that
meets a tolerance.

Every frequency of a reduced model (``modalfe.models.beam``, ``modalfe.models.plate``) carries two errors:
- discretization: Richardson from three mesh levels (element sizes x1, x1.5 and x2.25), as for the solid, at
  the order observed within [1, 2] (``modalfe.solve.estimates``), modes paired by shape;
- model: distance from the 3-D solid, found by a cheap cross-check, the solid's own two estimate levels
  (``solid_levels``): hexahedra of ``mesh.order`` >= 4 at the two lower orders on the default grid,
  extrapolated in the order (e_p ~ p^-q), else two coarse grids (element sizes x1.5 and x2.25 of the default,
  thickness layers scaled alike) extrapolated to zero element size at the assumed convergence order; the
  extrapolation's own uncertainty is added: half the order tail at the slowest rate ``MIN_P_RATE`` (the exact
  value lies between the level and its extrapolation at that rate), or how far the extrapolated value moves
  over the h-orders ``OBSERVED_ORDERS``.
A mode's ``error_estimate`` is the sum of the two, ``model_error`` the second, with ``fidelity="auto"`` and
with ``fidelity="beam"|"plate"`` asked directly alike (a reduced model's figure always includes its model error).

``auto`` tries the reduced model that suits the scene's kind (beam or plate; the axisymmetric model where every part
is round, ``modalfe.models.axisymmetric.meridian_section`` refusing a scene that is no body of revolution, with the
field at fault in the note: its discretization error is its own p-refinement's, ``modalfe.solve.axisymmetric``, its
model error the same cross-check) and answers with it when
the estimated error of the modes asked about is within ``tol`` (the model error is read first: where it alone
misses ``tol``, the reduced model's own estimate levels are not solved); otherwise the 3-D solid answers,
reusing the cross-check's levels for its own error estimate (nothing is solved twice or for nothing), and refined
while its own estimate exceeds ``tol`` (``refined_to_tol``): quadratic box hexahedra by the order first (quartic on
a coarser grid, ``Rung.step``), other meshes by the grid; where the cross-check's levels forecast that the
scene's own grid would miss ``tol`` by far, auto starts past it (``first_step``).
``Modes.fidelity_note`` says which fidelity answered and why, ``Modes.estimate_method`` how errors were estimated,
``Modes.estimate`` the plan that made them (levels and rule, ``modalfe.solve.estimates.EstimatePlan``). Each solid
discretization on the way is one value, a ``modalfe.solve.rung.Rung`` (scene, element size, layers, solver, frame),
which decides once how it is estimated and refined.

Where the scene declares mirror symmetry the plate model solves the symmetric part, as the solid does;
the beam model solves the whole beam and the modes antisymmetric about those planes are dropped, so that
every fidelity returns the same family.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import replace

import numpy as np

from modalfe.errors import SceneError, SolverError
from modalfe.results.modes import Modes, select
from modalfe.solve.axisymmetric import solve_axisymmetric
from modalfe.solve.checked import NOT_ESTIMATED, checked_modes, percent, worst_checked
from modalfe.solve.estimates import (
    COARSE_FACTOR,
    CONVERGENCE_ORDER,
    MIN_ORDER,
    MIN_P_RATE,
    MIN_RATIO,
    UNRESOLVED_P_RATE,
    EstimatePlan,
    level_ratio,
    partner,
    shape_partners,
    singular_field,
    uncoarsened,
    unresolved_edges,
)
from modalfe.solve.reduced import (
    cross_check_gap,
    model_errors,
    reduced_estimates,
    solve_reduced_level,
    with_model_errors,
)
from modalfe.solve.rung import CHECK_FACTORS, UNCOARSENED, Rung, coarser

log = logging.getLogger(__name__)

MAX_REFINE_STEPS = 3  # at most 1.5^3 = 3.4x smaller elements (~40x the DOFs) than the scene's mesh
# auto starts where even an optimistic reading of ``scene_grid_forecast`` says the grids before would miss tol: the
# least ratio over studies/forecast_calibration.py's plates and beams (none a window the report solves) of what the
# scene's quadratic grid then stated to its forecast (0.397; 0.42-2.45 the rest), and of what the first quartic step
# stated (0.122; 0.19-0.65), rounded down. A wrong start costs time, never accuracy; on the report's windows (not
# used to set them) none skips a grid that met tol (Cu-Be (0,6): 7.40 % stated, 1.44 forecast; glass (0,8) 0.71, 1.68)
FORECAST_GRID = 0.39
FORECAST_FIRST_STEP = 0.12


def reduced_fidelities(scene) -> list[str]:
    """Reduced models that can stand for ``scene``, cheapest first: the beam or plate model of its kind; the
    axisymmetric model where every part is round (``modalfe.models.axisymmetric.round_parts``: whether it is a body
    of revolution, ``meridian_section`` decides when it is tried)."""
    from modalfe.models.axisymmetric import round_parts

    return {"beam": ["beam"], "plate": ["plate"]}.get(scene.kind, []) + (["axisymmetric"] if round_parts(scene) else [])


def solve_at_fidelity(scene, analysis, *, fidelity: str, tol: float, check, size_factor: float = 1.0,
                      solver: str = "auto", error_estimate: bool = True, frame=None) -> Modes:
    """Modes at ``fidelity`` (``beam``, ``plate``, ``solid`` or ``auto``) whose stated error of the ``check``ed modes
    meets ``tol``: ``auto`` the cheapest fidelity (``solve_auto``), ``solid`` the solid refined to ``tol``
    (``refined_to_tol``), a reduced model on its own mesh with its discretization and model error. Without
    ``error_estimate``: the scene's own mesh once (``auto``: the solid), every error unknown (NaN,
    ``NOT_ESTIMATED``). The solid's rungs are ``Rung`` values from here on."""
    rung = Rung(scene, size_factor, solver=solver, frame=frame)
    if not error_estimate:
        fine = solve_estimated(rung, analysis, "solid" if fidelity == "auto" else fidelity, error_estimate=False)
        return replace(fine, estimate_method=NOT_ESTIMATED)
    if fidelity == "auto":
        if frame is not None:
            raise SolverError("frame: rotating the device is supported at solid fidelity only")
        return solve_auto(rung, analysis, tol=tol, check=check)
    if fidelity == "solid" and frame is None:
        solid = solve_auto(rung, analysis, tol=tol, check=check, fidelities=())
        return replace(solid, fidelity_note=solid.fidelity_note.replace("auto: solid answered", "solid asked", 1))
    modes = solve_estimated(rung, analysis, fidelity)
    if fidelity == "solid":  # a rotated device: its own mesh, estimated (``solid_levels`` rotated alike)
        return modes
    # a reduced model asked directly states its model error too: the same cross-check as ``auto``
    start = time.perf_counter()
    levels = solid_levels(rung, analysis)
    checked = with_model_errors(modes, model_errors(modes, levels, scene, orders=rung.uses_orders))
    note = (f"{fidelity} model: error estimates are discretization (three levels) plus model error against a "
            f"3-D solid cross-check")
    return replace(checked, fidelity_note=note, cross_check=tuple(levels),
                   timings=dict(checked.timings, cross_check=time.perf_counter() - start))


def solid_levels(rung: Rung, analysis) -> list[Modes]:
    """The solid's two estimate levels (``Rung.level``), each asked a little wider. They estimate the solid's own
    error and are the reduced models' 3-D cross-check."""
    if rung.no_estimate_reason == UNCOARSENED:
        raise SolverError(f"error estimate: {UNCOARSENED[len('none: '):]}")
    levels, a = [], analysis
    for index in range(2):
        a = coarser(a)
        level = rung.level(index)
        try:
            levels.append(level.solve(a))
        except SolverError as exc:
            which = f"order {level.scene.mesh.order}" if rung.uses_orders else f"elements x{CHECK_FACTORS[index]:g}"
            raise SolverError(f"error estimate: its level with {which} cannot be solved ({exc}); refine the mesh "
                              f"(mesh.elements_per_wavelength, mesh.max_size) or skip the estimate") from None
    return levels


def level_meshes(rung: Rung) -> list:
    """The ``DeviceMesh``es of the solid's two estimate levels (``solid_levels``), meshed but not solved; [] where
    they are two orders on one grid (``Rung.uses_orders``: nothing to judge by the grids)."""
    from modalfe.models.build import solid_mesh

    if rung.uses_orders:
        return []
    return [solid_mesh(level.scene, size_factor=level.size_factor, min_layers=level.min_layers)
            for level in (rung.level(0), rung.level(1))]


def order_step_level(rung: Rung, analysis) -> Modes | None:
    """Order 2 on the solid's own grid, asked a little wider, where ``Rung.checks_order_step`` (else None): solved only
    when the solid answers, since the reduced models' cross-check does not use it."""
    step = rung.order_step()
    return None if step is None else step.solve(coarser(analysis))


def without_estimates(fine: Modes, reason: str) -> Modes:
    """``fine`` stating no error estimate (infinite), ``reason`` (``Rung.no_estimate_reason``) as its method."""
    return replace(fine.with_error_estimates({m.index: math.inf for m in fine}), estimate_method=reason)


def solid_estimates(fine: Modes, levels: list[Modes], rung: Rung, step_level: Modes | None = None) -> Modes:
    """``fine`` (the solid on ``rung``) with its error estimates by ``solid_plan`` and the plan itself
    (``Modes.estimate``: a number derived from a mode is estimated alike); for a rung whose ``no_estimate_reason`` is
    None (else ``without_estimates``)."""
    plan = solid_plan(fine, levels, rung, step_level)
    estimates, rates = plan.frequency_errors(fine)
    if rates:  # the orders' rates, observed in the same pass
        plan = replace(plan, method=plan.method.replace(")", f"; observed {min(rates):.1f}-{max(rates):.1f})", 1))
    if plan.rule == "orders":
        estimates, plan = _with_walls(fine, estimates, plan)
    return replace(fine.with_error_estimates(estimates), estimate_method=plan.method, estimate=plan)


def _with_walls(fine: Modes, estimates: dict[int, float], plan):
    """``estimates`` from the orders on one swept grid plus the bound on its round walls' geometry, which every
    order shares (``modalfe.models.wall_geometry``), and the plan's method saying so; as given on other meshes."""
    from modalfe.models.wall_geometry import wall_errors

    if not fine.model.scene.assembly().shaped:  # boxes alone: no round wall
        return estimates, plan
    modes = list(fine)
    walls, deviations = wall_errors(fine.model, np.column_stack([m.shape for m in modes]),
                                    np.array([m.omega**2 for m in modes]))
    if not deviations:
        return estimates, plan
    worst = max(deviations, key=deviations.get)
    method = (f"{plan.method}; plus the round walls' geometry (quadratic arcs, up to {100 * deviations[worst]:.2g} % "
              f"of the radius off on '{worst}': Hadamard bound)")
    row = {m.index: k for k, m in enumerate(modes)}
    return {i: e + walls[row[i]] for i, e in estimates.items()}, replace(plan, method=method)


def solid_plan(fine: Modes, levels: list[Modes], rung: Rung, step_level: Modes | None = None) -> EstimatePlan:
    """How the solid ``fine``'s errors are estimated from its ``solid_levels`` (and, where ``Rung.checks_order_step``,
    at least the step to ``step_level``, ``order_step_level``): the orders on one grid (``Rung.uses_orders``), else
    ``h_plan``."""
    if rung.uses_orders:
        orders = "-".join(str(m.model.scene.mesh.order) for m in (*reversed(levels), fine))
        unresolved = unresolved_edges(fine.model.mesh, rung.scene)
        rate = UNRESOLVED_P_RATE if unresolved else MIN_P_RATE
        return EstimatePlan("orders", tuple(levels), method=f"p-refinement: orders {orders} on one grid (error ~ "
                            f"p^-q, q = {rate:g} or slower{f': {unresolved}' if unresolved else ''})", rate=rate)
    plan = h_plan(fine, levels, rung.scene)
    if rung.checks_order_step:
        plan = replace(plan, floor=step_level,
                       method=plan.method + ", at least the order 2-3 step on the grid at the rate p^-2")
    return plan


def h_plan(fine: Modes, levels: list[Modes], scene) -> EstimatePlan:
    """The h-refinement plan of ``fine`` from its two coarser grids ``levels`` (elements x1.5 and x2.25): Richardson
    through the three (``grids``) where each grid coarsens every part of the one before it by at least ``MIN_RATIO``
    along every axis (``level_ratio``: a part or face window whose element count rounds to the same on two grids is
    not coarsened there, and the step between them misses its error); else no order is observed, and each grid that
    coarsens every part of ``fine`` gives a two-level estimate at ``MIN_ORDER``, the larger used (``grid``); with none,
    ``none`` (no level measures the error)."""
    coarse, coarsest = levels
    singular = singular_field(scene)
    ceiling = MIN_ORDER if singular else CONVERGENCE_ORDER
    ratios = [level_ratio(fine.model.mesh, level.model.mesh, scene) for level in levels]
    chain = uncoarsened(coarse.model.mesh, coarsest.model.mesh, scene)  # a part the x2.25 grid leaves as x1.5 has it
    usable = [ratio >= MIN_RATIO for ratio, _ in ratios]
    unused = [f"x{factor:g} (its {where or 'main part'} is coarser than the solid's by {ratio:.2f} only)"
              for factor, (ratio, where), ok in zip(CHECK_FACTORS, ratios, usable) if not ok]
    if all(usable) and chain[0] >= MIN_RATIO:
        method = "h-refinement: Richardson through three grids (elements x1, x1.5, x2.25)"
        if singular:
            method += f" at order {MIN_ORDER:g}, the least a singular field converges at ({singular})"
        return EstimatePlan("grids", tuple(levels), tuple(r for r, _ in ratios), ceiling, method=method)
    if all(usable):
        unused.append(f"x{CHECK_FACTORS[1]:g} as a third grid (its {chain[1]} is coarser than the "
                      f"x{CHECK_FACTORS[0]:g} level's by {chain[0]:.2f} only: no order observed)")
    found = [(factor, level, ratio) for factor, level, (ratio, _), ok in zip(CHECK_FACTORS, levels, ratios, usable)
             if ok]
    if not found:
        return EstimatePlan("none", method=f"h-refinement: no coarser grid coarsens every part: error unknown; levels "
                                           f"not used: {'; '.join(unused)}")
    grids = " and ".join(f"x{factor:g}" for factor, _, _ in found)
    method = (f"h-refinement: Richardson from two grids (elements x1 against {grids}"
              f"{', the larger' if len(found) > 1 else ''}) at order "
              f"{MIN_ORDER:g}" + (f" ({singular})" if singular else "")
              + (f"; not used as a step: {'; '.join(unused)}" if unused else ""))
    return EstimatePlan("grid", tuple(level for _, level, _ in found), tuple(ratio for _, _, ratio in found),
                        MIN_ORDER, method=method)


def solve_estimated(rung: Rung, analysis, fidelity: str, *, error_estimate: bool = True,
                    levels: list[Modes] | None = None) -> Modes:
    """Modes of one fidelity on ``rung`` with discretization estimates: the solid's from ``solid_levels`` (lower
    orders or coarser grids; ``levels``: those grids solved already, used unless they leave a mode without a partner),
    a reduced model's Richardson from levels 1.5x and 2.25x coarser (``modalfe.solve.estimates.richardson``, which
    pairs them by shape: solved unlabelled; no model error: ``with_model_errors`` adds it)."""
    scene = rung.scene
    if fidelity != "solid" and fidelity not in reduced_fidelities(scene):
        raise SceneError(f"fidelity: '{fidelity}' does not apply to a {scene.kind} scene "
                         f"(use {[*reduced_fidelities(scene), 'solid', 'auto']})")
    if rung.frame is not None and fidelity != "solid":
        raise SolverError("frame: rotating the device is supported at solid fidelity only")
    if fidelity == "solid":
        fine = rung.solve(analysis)
        if not error_estimate:
            return fine
        start = time.perf_counter()
        if rung.no_estimate_reason is not None:
            return without_estimates(fine, rung.no_estimate_reason)
        step = order_step_level(rung, analysis)
        result = solid_estimates(fine, levels, rung, step) if levels else None
        if result is None or any(math.isinf(m.error_estimate) for m in result):
            # the grids solved before asked fewer modes around the target than a level does: one lacked a partner
            result = solid_estimates(fine, solid_levels(rung, analysis), rung, step)
        return replace(result, timings=dict(fine.timings, error_estimate=time.perf_counter() - start))

    fine = solve_reduced_level(scene, analysis, fidelity, solver=rung.solver, size_factor=rung.size_factor)
    if not error_estimate:
        return fine
    return reduced_estimates(fine, scene, analysis, size_factor=rung.size_factor, solver=rung.solver)


def solve_auto(rung: Rung, analysis, *, tol: float, check=None, fidelities: tuple[str, ...] | None = None) -> Modes:
    """The cheapest fidelity of the reduced ``fidelities`` (default ``reduced_fidelities``; () for the solid alone)
    and the solid whose estimated error on the checked modes is within
    ``tol``; the solid's estimate levels are solved once, as the reduced models' cross-check, for the forecast of
    where the solid starts and, if the solid answers, for its own estimate. The solid's ladder (start, steps) is the
    same whichever reduced models were tried, so that ``auto`` and ``solid`` answer a question the solid answers on
    the same discretization."""
    scene = rung.scene
    reasons = []
    levels = []  # the solid's estimate levels, solved at most once

    def solid_check():
        if not levels:
            levels.extend(solid_levels(rung, analysis))
        return levels

    tried = reduced_fidelities(scene) if fidelities is None else fidelities
    for fidelity in tried:
        try:
            fine = (solve_revolved(rung, analysis, tol=tol, check=check) if fidelity == "axisymmetric"
                    else solve_estimated(rung, analysis, fidelity, error_estimate=False))
        except (SceneError, SolverError, ImportError) as exc:
            reasons.append(f"{fidelity} model not applicable: {exc}")
            continue
        start = time.perf_counter()
        # the axisymmetric model is exact for a body of revolution up to its harmonics: where the solid's levels
        # cannot measure a model error, its discretization's estimate stands alone (NaN: not measured); judged on
        # the levels' meshes, so that levels which cannot measure are not solved (a 100 mm steel tube's: 90 s)
        gap = cross_check_gap(level_meshes(rung), scene, orders=rung.uses_orders) if fidelity == "axisymmetric" \
            else ""
        if fidelity == "axisymmetric" and not gap:
            try:  # nor where they cannot be solved (too large for the machine: a thin disc's thickness mode)
                solid_check()
            except (SceneError, SolverError) as exc:
                gap = f"the 3-D cross-check's levels cannot be solved ({exc})"
        # the model error alone first: where it misses tol, the discretization's levels would change nothing
        errors = (dict.fromkeys((m.index for m in fine), math.nan) if gap
                  else model_errors(fine, solid_check(), scene, orders=rung.uses_orders))
        cross_check = time.perf_counter() - start
        alone, why = worst_checked(with_model_errors(fine, errors), check, what="model error")
        if alone > tol:
            reasons.append(f"{fidelity} model: {why} > tol {percent(tol)}")
            continue
        try:  # the axisymmetric answer states its discretization error already
            reduced = fine if fidelity == "axisymmetric" else \
                reduced_estimates(fine, scene, analysis, size_factor=rung.size_factor, solver=rung.solver)
        except (SceneError, SolverError) as exc:
            reasons.append(f"{fidelity} model not applicable: {exc}")
            continue
        checked = replace(with_model_errors(reduced, errors), timings=dict(reduced.timings, cross_check=cross_check))
        worst, why = worst_checked(checked, check)
        if worst <= tol:
            model = max((m.model_error for m in checked_modes(checked, check)), default=0.0)
            measured = (f"discretization; model error not measured: {gap}, the model exact for a body of "
                        f"revolution" if gap else f"model error {percent(model)} from a 3-D solid cross-check, plus "
                        f"discretization")
            note = (f"auto: {fidelity} answered, estimated error {percent(worst)} <= tol {percent(tol)} ({measured})"
                    + (f"; {reduced.fidelity_note}" if reduced.fidelity_note else ""))  # the axisymmetric model's
            return replace(checked, fidelity_note=note, cross_check=tuple(levels))
        reasons.append(f"{fidelity} model: {why} > tol {percent(tol)}")
    reason = rung.no_estimate_reason
    forecast = 0.0
    if reason is None and rung.raises_order and rung.reuses_grids:  # else no forecast (``scene_grid_forecast``)
        forecast = scene_grid_forecast(rung, solid_check(), check)
    start = first_step(rung, forecast, tol)
    skipped = ""
    if start:  # the scene's own grid (and maybe the first step) would miss tol
        solid = None
        skipped = (f"; the scene's own grid not solved (its estimate levels forecast {percent(forecast)} there: "
                   f"started at refinement step {start}, first_step)")
        log.info("auto: the scene's grid is forecast to state %s against tol %s: starting at refinement step %d",
                 percent(forecast), percent(tol), start)
    else:
        fine = rung.solve(analysis)
        start_time = time.perf_counter()
        if reason is None:  # the levels are reused if the cross-check solved them
            solid = solid_estimates(fine, solid_check(), rung, order_step_level(rung, analysis))
        else:
            solid = without_estimates(fine, reason)
        solid = replace(solid, timings=dict(fine.timings, error_estimate=time.perf_counter() - start_time))
    solid, refined = refined_to_tol(rung, analysis, solid, tol=tol, check=check, levels=levels, start=max(start, 1))
    note = "auto: solid answered" + (f" ({'; '.join(reasons)})" if reasons else " (no reduced model for a "
                                     f"{scene.kind} scene)" if fidelities is None else "")
    return replace(solid, fidelity_note=note + skipped + refined)


def solve_revolved(rung: Rung, analysis, *, tol: float, check) -> Modes:
    """The axisymmetric model's answer on ``rung``'s element sizes, refined until the ``check``ed modes' stated
    discretization error meets ``tol`` (``modalfe.solve.axisymmetric``); its model error is auto's to add."""
    return solve_axisymmetric(rung.scene, analysis, tol=tol, check=check, size_factor=rung.size_factor,
                              solver=rung.solver)


def scene_grid_forecast(rung: Rung, levels: list[Modes], check) -> float:
    """The largest error the solid's own grid would state on the checked modes, forecast from its two estimate levels
    where a reduced model's cross-check solved them (else 0: nothing to go by): their step, shrunk to the scene's
    grid at ``CONVERGENCE_ORDER``, at the order the grid's own estimate would use (``singular_field``). Only where
    ``raises_order``. A rough figure (0.2-5x what the grid then states, ``FORECAST_GRID``) that chooses where auto
    starts (``first_step``), never a stated error."""
    if len(levels) != 2 or not rung.raises_order or not rung.reuses_grids:
        return 0.0
    coarse, coarsest = levels
    pairs = shape_partners(coarse, coarsest)
    order = MIN_ORDER if singular_field(rung.scene) else CONVERGENCE_ORDER
    shrink = 1 / (COARSE_FACTOR**CONVERGENCE_ORDER * (COARSE_FACTOR**order - 1))
    steps = {m.index: abs(pairs[m.index][1] - m.frequency) / m.frequency * shrink if m.index in pairs else 0.0
             for m in coarse if m.frequency > 0}
    worst, _ = worst_checked(coarse.with_error_estimates(steps), check)
    return worst if math.isfinite(worst) else 0.0  # inf: a checked mode the coarse level does not hold


def first_step(rung: Rung, forecast: float, tol: float) -> int:
    """Where auto's solid starts: 0, ``rung`` itself; 1 or 2, that refinement step (``Rung.step``), where
    ``forecast`` (``scene_grid_forecast``) times the least ratio seen (``FORECAST_GRID``, ``FORECAST_FIRST_STEP``)
    still exceeds ``tol`` for the grids before it, and the step fits in memory."""
    from modalfe.models.estimate import check_size

    wanted = 2 if forecast * FORECAST_FIRST_STEP > tol else 1 if forecast * FORECAST_GRID > tol else 0
    wanted = min(wanted, MAX_REFINE_STEPS)
    for step in range(wanted, 0, -1):
        finer = rung.step(step)
        try:
            check_size(finer.scene, size_factor=finer.size_factor)
        except SceneError:
            continue
        return step
    return 0


def refined_to_tol(rung: Rung, analysis, solid: Modes | None, *, tol: float, check,
                   levels: list[Modes] | tuple = (), start: int = 1) -> tuple[Modes, str]:
    """(``solid``, or the solid solved again on finer rungs until the estimated error of the checked modes is
    within ``tol``; a phrase for the note saying what was done); ``solid`` None: ``rung`` itself was skipped
    (``first_step``), start at step ``start``. The steps are ``Rung.step``'s: quartic elements on a coarser grid
    first where ``Rung.raises_order``, else elements ``REFINE_RATIO`` smaller a step and the thickness layers as many
    times more (the estimate levels' own ratio, ``COARSE_FACTOR``); one step at a time (a step costs ~1.5^3 = 3.4x
    the one before, so the steps before the last add at most ~40 %; jumping by the steps an h^2 fall predicts
    overshot), at most ``MAX_REFINE_STEPS``, and none whose model would not fit in memory
    (``modalfe.models.estimate.check_size``). Not where the solid states no estimate (nothing to steer by), but
    for the first step where it raises the order. On
    h-steps a step's estimate levels (elements x1.5 and x2.25 of its own, layers alike) are the grids of the steps
    before it (``solid`` and its ``levels`` for the first): they are reused (``solve_estimated``)."""
    from modalfe.models.estimate import check_size

    grids = None  # (thickness layers, element size factor) -> the solve on that grid, where levels are grids
    if rung.reuses_grids:
        grids = {} if solid is None else {rung.grid: solid}
        grids.update(zip(rung.level_grids(), levels))
    worst, why = ((math.inf, "own grid (not solved, first_step)") if solid is None
                  else worst_checked(solid, check))
    steps, stopped, finer = (0 if solid is not None else start - 1), "", rung
    # an unknown error steers nowhere, but where the first step raises the order it brings its own estimate (the
    # orders on its grid: a round sensor's plate, whose quadratic grids coarsen no part alike, states one there)
    while worst > tol and (math.isfinite(worst) or solid is None or (steps == 0 and rung.raises_order)) \
            and steps < MAX_REFINE_STEPS:
        finer = rung.step(steps + 1)
        try:
            size = check_size(finer.scene, size_factor=finer.size_factor)
        except SceneError as exc:
            stopped = f" (a finer grid would not fit: {exc})"
            break
        log.info("auto: the solid's %s exceeds tol %s: elements x%.3g, %d layers (%s)", why, percent(tol),
                 finer.size_factor, finer.scene.mesh.min_layers, size.describe())
        reused = None
        if grids is not None and finer.reuses_grids:
            keys = finer.level_grids()
            reused = [grids[k] for k in keys] if all(k in grids for k in keys) else None
        solid = solve_estimated(finer, analysis, "solid", levels=reused)
        if grids is not None:
            grids[finer.grid] = solid
        steps += 1
        worst, why = worst_checked(solid, check)
    if solid is None:
        raise SolverError(f"auto: no refinement step could be solved{stopped}")
    note = ""
    if steps:
        mesh = finer.scene.mesh
        order = f"order {mesh.order} on " if mesh.order != rung.scene.mesh.order else ""
        note = (f"; refined for tol {percent(tol)}: {order}elements x{finer.size_factor:.3g} of the scene's mesh, "
                f"{mesh.min_layers} thickness layer{'s' if mesh.min_layers != 1 else ''}, {solid.dofs} DOFs")
    if worst > tol:
        if not stopped and math.isfinite(worst) and steps == MAX_REFINE_STEPS:
            stopped = f" at the most refinement allowed (MAX_REFINE_STEPS = {MAX_REFINE_STEPS})"
        note += f"; its {why} exceeds tol {percent(tol)}{stopped}"
    return solid, note


def coupling_check_level(modes: Modes, mode, *, size_factor: float = 1.0, solver: str = "auto") -> tuple[float, float]:
    """(fr, fa) [Hz] of ``mode``'s partner in the 3-D solid at the cross-check's first level that
    ``modes`` (answered by a reduced model) was checked against: short circuit from that level, open circuit
    solved on the same mesh. A reduced model's piezo layers (uniform field, no shear lag at the patch edges)
    misplace k_eff by 10-15 % on the seed devices, while the solid's fa / fr at this level is within ~2.5 %
    in k_eff of the default mesh (both shift alike): the report takes k_eff from here. Where ``modes`` kept no
    cross-check (a reduced model asked directly; auto's axisymmetric answer where the levels cannot measure a model
    error, ``cross_check_gap``, and were not solved) that level is solved near ``mode`` now."""
    from modalfe.scene import Analysis

    level = Rung(modes.model.scene, size_factor, solver=solver).level(0)
    shorts = modes.cross_check[0] if modes.cross_check else level.solve(coarser(Analysis(near=mode.frequency,
                                                                                          count=6)))
    short = partner(mode, shorts)
    if short is None:
        raise SolverError(f"no 3-D partner of {mode.label} at {mode.frequency:.6g} Hz in the cross-check")
    open_ = level.solve(Analysis(near=short.frequency, count=6, circuit="open"))
    fa = partner(short, open_)
    if fa is None:  # the shape pairing failed: the label, as before
        fa = select(open_, short.label, short.frequency)
    return short.frequency, fa.frequency
