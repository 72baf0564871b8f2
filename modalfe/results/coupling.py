"""Electromechanical coupling of a mode from its short-circuit (fr) and open-circuit (fa) frequencies."""

from __future__ import annotations

import math

from modalfe.errors import SolverError


def k_eff(fr: float, fa: float) -> float:
    """Effective coupling factor k_eff = sqrt((fa^2 - fr^2) / fa^2) (IEEE Std 176-1987, eq. 100)."""
    if not (fr > 0 and fa > 0):
        raise SolverError(f"k_eff: frequencies must be positive, got fr = {fr}, fa = {fa}")
    return math.sqrt(max(fa**2 - fr**2, 0.0) / fa**2)


def antiresonance(short_mode, open_modes):
    """The open-circuit partner of ``short_mode``: same label, nearest frequency above it."""
    same = [m for m in open_modes if m.label == short_mode.label]
    if not same:
        raise SolverError(f"no open-circuit mode labelled '{short_mode.label}'")
    return min(same, key=lambda m: abs(m.frequency - short_mode.frequency))
