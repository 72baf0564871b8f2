"""Discretization error estimates: a second solve on a coarser level, paired mode by mode, and Richardson
extrapolation at an assumed convergence order."""

from __future__ import annotations

import logging

from modalfe.results.modes import Mode, Modes

log = logging.getLogger(__name__)

COARSE_FACTOR = 1.5  # coarse level of the Richardson estimate: elements 1.5x larger
# Eigenvalue error of quadratic elements is ~h^(2p) = h^4 for smooth modes (Strang & Fix 1973), but
# clamped faces, bonded patches and feet make re-entrant edges whose singular fields slow it down:
# studies/convergence.py observes orders 1.5-2.1 on the seed devices' working modes. The estimate
# assumes order 2, which keeps it at or above the error found by four-level refinement there.
CONVERGENCE_ORDER = 2.0
OBSERVED_ORDERS = (1.5, 2.1)  # that range: 1.55 / 2.13 / 1.58 for the three devices (docs/benchmarks.md)


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


def refinement_ratio(fine_mesh, coarse_mesh, scene) -> float:
    """Mean element-size ratio between two meshes of the main part: (n_fine / n_coarse)^(1/3)."""
    main = scene.assembly().main_part.name
    return float((len(fine_mesh.parts[main]) / len(coarse_mesh.parts[main])) ** (1 / 3))
