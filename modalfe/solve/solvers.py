"""Band-targeted eigen solves: shift-invert around a frequency, one factorization for all modes.

The coupled piezoelectric problem K x = omega^2 M x has a singular M (no inertia on the potential);
ARPACK's shift-invert mode accepts a positive semi-definite M, and the potential unknowns only
add eigenvalues at infinity, which shift-invert maps to zero and never returns.
"""

from __future__ import annotations

import logging
import math
import time
from collections import OrderedDict
from dataclasses import replace

import numpy as np
from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, LinearOperator, eigsh

from modalfe.errors import SolverError
from modalfe.results.labels import label_mode
from modalfe.solve.linalg import factorize
from modalfe.results.modes import Mode, Modes

log = logging.getLogger(__name__)

COARSE_FACTOR = 1.5  # coarse level of the Richardson estimate: elements 1.5x larger
# Eigenvalue error of quadratic elements is ~h^(2p) = h^4 for smooth modes (Strang & Fix 1973), but
# clamped faces, bonded patches and feet make re-entrant edges whose singular fields slow it down:
# studies/convergence.py observes orders 1.5-2.1 on the seed devices' working modes. The estimate
# assumes order 2, which keeps it at or above the error found by four-level refinement there.
CONVERGENCE_ORDER = 2.0
OBSERVED_ORDERS = (1.5, 2.1)  # that range: 1.55 / 2.13 / 1.58 for the three devices (docs/benchmarks.md)


FIDELITIES = ("auto", "beam", "plate", "solid")
# relative frequency error asked of ``fidelity="auto"``: below the seeds' 2-7 % model-to-measurement gaps
DEFAULT_TOL = 0.02


def solve_modes(
    scene,
    *,
    near: float | None = None,
    count: int | None = None,
    band: tuple[float, float] | None = None,
    circuit: str | None = None,
    error_estimate: bool = True,
    size_factor: float = 1.0,
    solver: str = "auto",
    frame=None,
    fidelity: str = "solid",
    tol: float = DEFAULT_TOL,
    check: tuple[tuple[str, float], ...] | None = None,
) -> Modes:
    """Modes of ``scene``: ``count`` nearest ``near`` [Hz], or all in ``band`` [Hz].

    Defaults come from ``scene.analysis``. With ``error_estimate`` the scene is solved again on a
    mesh 1.5x coarser in every direction (thickness layers too: 3 -> 2 by default) and each
    frequency gets a Richardson estimate of its relative error.
    ``fidelity``: ``solid`` (3-D), ``beam`` or ``plate`` (reduced models), or ``auto``: the cheapest
    whose estimated error meets ``tol`` on the modes ``check`` names as (selector, near Hz) pairs
    (all modes when None); see ``modalfe.solve.fidelity``.
    ``frame`` (3, 3) rotates the whole device (mesh and materials), for invariance checks.
    """
    from modalfe.scene import Analysis

    if fidelity not in FIDELITIES:
        raise SolverError(f"fidelity: must be one of {FIDELITIES}, got '{fidelity}'")
    if not (math.isfinite(tol) and tol > 0):
        raise SolverError(f"tol: must be a positive relative error, got {tol}")
    a = scene.analysis
    if near is not None or band is not None:
        a = Analysis(near=near, count=count or a.count, band=band, circuit=circuit or a.circuit)
    else:
        a = Analysis(near=a.near, count=count or a.count, band=a.band, circuit=circuit or a.circuit)
    if a.band is None and a.near is None:
        raise SolverError("give near (and count) or band")
    # the mesh resolves the frequencies asked for, whichever is higher: the scene's or this call's
    scene = replace(scene, analysis=a) if a.band != scene.analysis.band or (a.near or 0) > (scene.analysis.near or 0) \
        else scene
    if fidelity != "solid":
        if frame is not None:
            raise SolverError("frame: rotating the device is supported at solid fidelity only")
        from modalfe.solve.fidelity import solve_at_fidelity

        return solve_at_fidelity(scene, a, fidelity=fidelity, tol=tol, check=check, size_factor=size_factor,
                                 solver=solver, error_estimate=error_estimate)
    fine = solve_level(scene, a, size_factor=size_factor, solver=solver, frame=frame)
    if not error_estimate:
        return fine
    start = time.perf_counter()
    coarse = solve_level(scene, coarser(a), solver=solver, frame=frame,
                         **coarse_level(scene, COARSE_FACTOR, size_factor))
    ratio = refinement_ratio(fine.model.mesh, coarse.model.mesh, scene)
    result = fine.with_error_estimates(richardson(fine, coarse, ratio))
    return replace(result, timings=dict(fine.timings, error_estimate=time.perf_counter() - start))


def coarse_level(scene, factor: float, size_factor: float = 1.0) -> dict:
    """Mesh of a coarser level: elements ``factor`` times larger, thickness layers scaled alike."""
    return {"size_factor": size_factor * factor, "min_layers": max(1, round(scene.mesh.min_layers / factor))}


def coarser(a):
    """The analysis of a coarser level: a few more modes (or a wider band) so that every mode of the
    fine level finds its partner."""
    from modalfe.scene import Analysis

    if a.band is None:
        return Analysis(near=a.near, count=a.count + 4, circuit=a.circuit)
    return Analysis(band=(a.band[0] * 0.9, a.band[1] * 1.1), circuit=a.circuit)


def partner(mode: Mode, candidates: Modes) -> Mode | None:
    """The mode of ``candidates`` with the same label nearest in frequency, if within 10 %."""
    same = [m for m in candidates if m.label == mode.label]
    if not same:
        return None
    best = min(same, key=lambda m: abs(m.frequency - mode.frequency))
    return best if abs(best.frequency - mode.frequency) <= 0.1 * mode.frequency else None


def richardson(fine: Modes, coarse: Modes, ratio: float) -> dict[int, float]:
    """Relative error estimate of each fine mode from its coarse partner, for an error ~ h^order
    (order CONVERGENCE_ORDER): |f_h - f_coarse| / ((ratio^order - 1) f_h); inf where a mode has no
    partner (the coarse level does not resolve it, so the fine one is not converged either)."""
    estimates = {}
    top = max(m.frequency for m in fine)
    for mode in fine:
        if mode.frequency < 1e-6 * top:
            continue  # a rigid-body mode: no relative error to speak of
        other = partner(mode, coarse)
        if other is None:
            log.info("mode %s at %.6g Hz has no partner on the coarse mesh: error unknown, refine the mesh",
                        mode.label, mode.frequency)
            estimates[mode.index] = float("inf")
            continue
        estimates[mode.index] = abs(other.frequency - mode.frequency) / (
            (ratio**CONVERGENCE_ORDER - 1) * mode.frequency)
    return estimates


def static_response(scene, volts: float, *, solver: str = "auto") -> np.ndarray:
    """Static full DOF vector (u then phi) under ``volts`` [V] on the driven electrodes, the other
    electrodes grounded: solve T^T K T x = -T^T K x_volts (the scene's supports must remove the
    rigid-body motions)."""
    model, _, _ = assembled_model(scene)
    T = model.constraints("short").T
    x_volts = model.prescribed_potential(volts)
    A = (T.T @ model.K @ T).tocsr()
    solve, _ = factorize(A, solver=solver)
    return T @ solve(-(T.T @ (model.K @ x_volts))) + x_volts


def refinement_ratio(fine_mesh, coarse_mesh, scene) -> float:
    """Mean element-size ratio between two meshes of the main part: (n_fine / n_coarse)^(1/3)."""
    main = max(scene.assembly().parts, key=lambda p: p.volume).name
    return float((len(fine_mesh.parts[main]) / len(coarse_mesh.parts[main])) ** (1 / 3))


def assembled_model(scene, *, size_factor: float = 1.0, frame=None, min_layers: int | None = None):
    """The scene's mesh and assembled model; reused while the scene's physics and mesh are unchanged
    (a second window, the other circuit, a forced response), so nothing is assembled twice.
    Returns (model, mesh seconds, assembly seconds), zero seconds for reused work."""
    from modalfe.models.mesh import build_mesh, element_sizes
    from modalfe.models.solid import assemble

    t0 = time.perf_counter()
    sizes = {k: v * size_factor for k, v in element_sizes(scene).items()}
    layers = scene.mesh.min_layers if min_layers is None else min_layers
    fully_clamped = tuple(sorted(g for g, components in scene.clamps.items() if set(components) == set("xyz")))
    dm = build_mesh(scene.assembly(), size=sizes, element=scene.mesh.element, min_layers=layers,
                    graded_faces=fully_clamped, grading_layers=scene.mesh.clamp_grading)
    t_mesh = (time.perf_counter() - t0) if dm.seconds else 0.0
    key = repr((dm.key, scene.params, scene.materials, scene.springs, scene.masses, scene.electrodes,
                scene.clamps, scene.mesh.order, None if frame is None else np.asarray(frame).tobytes()))
    if key in _MODELS:
        _MODELS.move_to_end(key)
        return _MODELS[key], t_mesh, 0.0
    model = assemble(scene, dm, frame=frame)
    _MODELS[key] = model
    while len(_MODELS) > _MODELS_KEPT:
        _MODELS.popitem(last=False)
    return model, t_mesh, model.timings["assembly"]


_MODELS: OrderedDict = OrderedDict()
_MODELS_KEPT = 3  # a fine and a coarse model of the scene in use, plus one


def solve_level(scene, analysis, *, size_factor: float, solver: str, frame=None, min_layers=None) -> Modes:
    model, t_mesh, t_assembly = assembled_model(scene, size_factor=size_factor, frame=frame, min_layers=min_layers)
    constraints = model.constraints(analysis.circuit)
    T = constraints.T
    A = (T.T @ model.K @ T).tocsr()
    B = (T.T @ model.M @ T).tocsr()
    values, vectors, t_fact, t_eig, used = eigenpairs(A, B, analysis, solver)
    shapes = T @ vectors
    modes = []
    for i in range(len(values)):
        lam = values[i]
        frequency = float(np.sqrt(max(lam, 0.0)) / (2 * np.pi))
        label, wavelength = label_mode(model, shapes[:, i], scene.kind)
        modes.append(Mode(i, frequency, label, shapes[:, i], wavelength=wavelength))
    timings = {"mesh": t_mesh, "assembly": t_assembly,
               "factorization": t_fact, "eigensolve": t_eig, "solver": used}
    return Modes(tuple(modes), model, analysis.circuit, "solid", A.shape[0], timings)


def eigenpairs(A, B, analysis, solver: str = "auto"):
    """Eigenpairs of A x = lam B x near the target; returns sorted (lam, X, t_fact, t_eig, solver)."""
    two_pi = 2 * np.pi
    if analysis.band is not None:
        f1, f2 = analysis.band
        centre = 0.5 * (f1 + f2)
        sigma = (two_pi * centre) ** 2
        count = 12
    else:
        sigma = (two_pi * analysis.near) ** 2
        count = analysis.count
    n = A.shape[0]
    t = time.perf_counter()
    solve, used = _factor_shifted(A, B, sigma, solver)
    t_fact = time.perf_counter() - t
    op = LinearOperator(A.shape, matvec=solve, dtype=float)
    t = time.perf_counter()
    while True:
        k = min(count, n - 2)
        try:
            lam, X = eigsh(A, k=k, M=B, sigma=sigma, which="LM", OPinv=op, tol=1e-8)
        except (ArpackNoConvergence, ArpackError) as exc:
            near_hz = np.sqrt(abs(sigma)) / two_pi
            raise SolverError(f"the eigen solve did not converge near {near_hz:.4g} Hz: {exc}") from None
        if not np.all(np.isfinite(lam)):
            raise SolverError("the eigen solve returned NaN eigenvalues")
        if analysis.band is None or k >= n - 2:
            break
        freqs = np.sqrt(np.abs(lam)) / two_pi
        # the returned set is the k nearest the centre: once it reaches past both band edges, all
        # modes inside are found (rigid-body modes sit at ~0 Hz, numerically a hair either side)
        low = max(analysis.band[0], 1e-6 * analysis.band[1])
        if freqs.min() <= low and freqs.max() >= analysis.band[1]:
            break
        if abs(freqs - centre).max() > max(centre - analysis.band[0], analysis.band[1] - centre):
            break
        count *= 2
    t_eig = time.perf_counter() - t
    order = np.argsort(lam)
    lam, X = lam[order], X[:, order]
    if analysis.band is not None:
        freqs = np.sqrt(np.clip(lam, 0, None)) / two_pi
        keep = (freqs >= analysis.band[0] - 1e-6 * analysis.band[1]) & (freqs <= analysis.band[1])
        lam, X = lam[keep], X[:, keep]
        if len(lam) == 0:
            raise SolverError(f"no modes in the band {analysis.band[0]:g}-{analysis.band[1]:g} Hz")
    return lam, X, t_fact, t_eig, used


def _factor_shifted(A, B, sigma, solver):
    """Factor A - sigma B; on a singular shift, move it by 1e-6 relative once and say so."""
    try:
        return factorize(A - sigma * B, solver=solver)
    except SolverError:
        moved = sigma * (1 + 1e-6) if sigma else 1e-6 * abs(A.diagonal()).mean() / abs(B.diagonal()).mean()
        log.warning("shift %.6g is singular (on an eigenvalue?); moved to %.6g", sigma, moved)
        return factorize(A - moved * B, solver=solver)
