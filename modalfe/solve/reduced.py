"""The reduced models' rung of the fidelity ladder (``modalfe.solve.fidelity``): a beam or plate model's levels, the
family the 3-D solid's reduced domain returns, the Richardson estimate of its discretization and its model error
against the solid's two estimate levels (the cross-check)."""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np
from scipy.spatial import cKDTree

from modalfe.results.modes import Modes
from modalfe.solve.estimates import (
    COARSE_FACTOR,
    CONVERGENCE_ORDER,
    MIN_P_RATE,
    MIN_RATIO,
    OBSERVED_ORDERS,
    level_ratio,
    refinement_ratio,
    richardson,
    sample_points,
    shape_partners,
)
from modalfe.solve.levels import solve_level
from modalfe.solve.rung import coarser

SOLVES_SYMMETRIC_PART = {"beam": False, "plate": True}  # else the whole device is solved


def solve_reduced_level(scene, analysis, fidelity: str, *, solver: str = "auto", **level) -> Modes:
    """One level of reduced model ``fidelity`` (``level``: ``solve_level``'s size_factor, labels): the plate solves
    the scene's symmetric part as the solid does; the beam the whole beam, the modes of the other parity dropped."""
    if SOLVES_SYMMETRIC_PART[fidelity]:
        return solve_level(scene, analysis, fidelity=fidelity, solver=solver, **level)
    whole = solve_level(scene, _widened(analysis, scene), fidelity=fidelity, solver=solver, **level)
    return _same_family(whole, scene, analysis)


def reduced_estimates(fine: Modes, scene, analysis, *, size_factor: float = 1.0, solver: str = "auto") -> Modes:
    """``fine`` (a reduced model's level at ``size_factor``) with Richardson estimates from levels 1.5x and 2.25x
    coarser (``modalfe.solve.estimates.richardson``, which pairs them by shape: solved unlabelled); no model error
    (``with_model_errors`` adds it)."""
    start = time.perf_counter()
    coarse = solve_reduced_level(scene, coarser(analysis), fine.fidelity, solver=solver,
                                 size_factor=size_factor * COARSE_FACTOR, labels=False)
    coarsest = solve_reduced_level(scene, coarser(coarser(analysis)), fine.fidelity, solver=solver,
                                   size_factor=size_factor * COARSE_FACTOR**2, labels=False)
    result = fine.with_error_estimates(richardson(fine, coarse, COARSE_FACTOR, coarsest, COARSE_FACTOR**2))
    method = f"h-refinement: Richardson through three {fine.fidelity} meshes (elements x1, x1.5, x2.25)"
    seconds = time.perf_counter() - start
    return replace(result, estimate_method=method, timings=dict(fine.timings, error_estimate=seconds))


def model_errors(reduced: Modes, levels: list[Modes], scene, *, orders: bool) -> dict[int, float]:
    """{mode index: relative model error} of ``reduced`` against the solid extrapolated from its two estimate levels
    (``modalfe.solve.fidelity.solid_levels``: two orders on one grid where ``orders``, else two grids), with that
    extrapolation's uncertainty; inf where the solid has no partner mode, 0 for a rigid-body mode."""
    solid_1, solid_2 = levels
    extrapolate = _order_extrapolation(scene) if orders else _grid_extrapolation(solid_1, solid_2, scene)
    # paired by shape at the reduced model's own sample points (inside the solid too)
    to_solid = shape_partners(reduced, solid_1, sample_points(reduced))
    within_solid = shape_partners(solid_1, solid_2)
    errors, rigid = {}, reduced.rigid_indices()
    for mode in reduced:
        near = to_solid.get(mode.index)
        far = within_solid.get(near[0].index) if near is not None else None
        if mode.index in rigid:
            errors[mode.index] = 0.0
        elif far is None:
            errors[mode.index] = math.inf
        else:
            extrapolated, uncertainty = extrapolate(near[1], far[1])
            errors[mode.index] = (abs(mode.frequency - extrapolated) + uncertainty) / extrapolated
    return errors


def cross_check_gap(meshes: list, scene, *, orders: bool) -> str:
    """Why the solid's two estimate levels (their ``DeviceMesh``es: judged before they are solved) cannot measure a
    model error, "" where they can: two grids whose step
    coarsens some part along some axis by less than ``MIN_RATIO`` (``level_ratio``: a thin layer keeps its element
    count, a swept section its in-plane size) see too little of the solid's own discretization error to extrapolate
    it, as ``modalfe.solve.fidelity.h_plan`` judges the solid's own levels. A 0.42 mm buzzer disc's levels (PZT on
    brass, examples/buzzer_ft20t.toml) both read its (0,1) 2.3 % high, 2 Hz apart: extrapolated, a "model error" of
    2.7 % that was the solid's. Two orders on one grid always measure."""
    if orders:
        return ""
    ratio, where = level_ratio(meshes[0], meshes[1], scene)
    if ratio >= MIN_RATIO:
        return ""
    return (f"the 3-D cross-check's levels (elements x{COARSE_FACTOR:g} and x{COARSE_FACTOR**2:g}) coarsen "
            f"{where or 'the main part'} by {ratio:.2f} only (< {MIN_RATIO:g})")


def with_model_errors(reduced: Modes, errors: dict[int, float]) -> Modes:
    """``reduced`` with each mode's model error (``model_errors``) and, but for rigid-body modes, its error estimate
    raised by it (a NaN estimate, no discretization estimate, counts as none; a NaN model error, not measured
    (``cross_check_gap``), adds nothing)."""
    rigid = reduced.rigid_indices()
    modes = tuple(replace(m, model_error=errors[m.index]) if m.index in rigid or math.isnan(errors[m.index]) else
                  replace(m, model_error=errors[m.index], error_estimate=errors[m.index]
                          + (0.0 if math.isnan(m.error_estimate) else m.error_estimate)) for m in reduced)
    return replace(reduced, modes=modes)


def _grid_extrapolation(solid_1: Modes, solid_2: Modes, scene):
    """(f_1, f_2) -> (solid frequency extrapolated to zero element size at ``CONVERGENCE_ORDER``, its uncertainty
    [Hz]: how far it moves over the orders ``OBSERVED_ORDERS``) for levels of two grids."""
    ratio = refinement_ratio(solid_1.model.mesh, solid_2.model.mesh, scene)

    def extrapolate(f1: float, f2: float) -> tuple[float, float]:
        step = f1 - f2
        value = f1 + step / (ratio**CONVERGENCE_ORDER - 1)
        return value, max(abs(step / (ratio**q - 1) - step / (ratio**CONVERGENCE_ORDER - 1)) for q in OBSERVED_ORDERS)

    return extrapolate


def _order_extrapolation(scene):
    """(f_(p-1), f_(p-2)) -> (solid frequency, its uncertainty [Hz]) for levels of two orders on one grid: with
    e_k = C k^-q and q >= ``MIN_P_RATE`` the exact value lies between f_(p-1) and its extrapolation at that rate;
    the midpoint, and half the interval."""
    top = scene.mesh.order - 1

    def extrapolate(f1: float, f2: float) -> tuple[float, float]:
        tail = (f1 - f2) / ((top / (top - 1)) ** MIN_P_RATE - 1)
        return f1 + tail / 2, abs(tail) / 2

    return extrapolate


def _widened(analysis, scene):
    """Twice the modes per mirror plane of the scene: about half are dropped as of the other parity."""
    if not scene.mirror_axes or analysis.band is not None:
        return analysis
    return replace(analysis, count=analysis.count * 2 ** len(scene.mirror_axes))


def _same_family(modes: Modes, scene, analysis) -> Modes:
    """Keep the modes symmetric about every mirror plane of ``scene.symmetry`` and antisymmetric about every one of
    ``scene.antisymmetry`` (the family the 3-D solid's reduced domain returns), then the ``count`` nearest the
    target; renumbered from 0."""
    kept = [m for m in modes if all(_parity(modes.model, m.shape, "xyz".index(a), scene) > 0 for a in scene.symmetry)
            and all(_parity(modes.model, m.shape, "xyz".index(a), scene) < 0 for a in scene.antisymmetry)]
    if analysis.band is None:
        kept = sorted(sorted(kept, key=lambda m: abs(m.frequency - analysis.near))[: analysis.count],
                      key=lambda m: m.frequency)
    return replace(modes, modes=tuple(replace(m, index=i) for i, m in enumerate(kept)))


def _parity(model, shape: np.ndarray, axis: int, scene) -> float:
    """Correlation of a displacement field with its mirror image about the device's mid-plane normal
    to ``axis``: +1 symmetric, -1 antisymmetric."""
    points, u = model.label_field(shape)
    lo, hi = scene.full_assembly().bounds
    mirrored = points.copy()
    mirrored[axis] = lo[axis] + hi[axis] - points[axis]
    _, nearest = cKDTree(points.T).query(mirrored.T)
    image = u[:, nearest].copy()
    image[axis] *= -1
    norm = float(np.sum(u * u))
    return float(np.sum(u * image)) / norm if norm > 0 else 1.0
