"""Electromechanical coupling of a mode from its short-circuit (fr) and open-circuit (fa) frequencies."""

from __future__ import annotations

import math

import numpy as np

from modalfe.errors import SolverError


def k_eff(fr: float, fa: float) -> float:
    """Effective coupling factor k_eff = sqrt((fa^2 - fr^2) / fa^2) (IEEE Std 176-1987, eq. 100)."""
    if not (fr > 0 and fa > 0):
        raise SolverError(f"k_eff: frequencies must be positive, got fr = {fr}, fa = {fa}")
    return math.sqrt(max(fa**2 - fr**2, 0.0) / fa**2)


PARTNER_MAC = 0.5  # least shape likeness (mass-weighted MAC) of an open-circuit partner on the same model


def antiresonance(short_mode, open_modes):
    """The open-circuit partner of ``short_mode``. Solved on the same model: the open mode whose shape is most like
    it, (x_o^T M x_s)^2 / (x_o^T M x_o x_s^T M x_s) (the open circuit only adds the floating potentials' stiffening:
    ~1 for the partner, ~0 for the others, M-orthogonal partners of other modes); SolverError where none reaches
    ``PARTNER_MAC`` (the partner was not among the modes solved). On another model: the same label, nearest in
    frequency."""
    if open_modes.model is short_mode.model:
        weighted = short_mode.model.M @ short_mode.shape
        mass = float(short_mode.shape @ weighted)  # short_mode.modal_mass, from the product at hand
        X = np.column_stack([m.shape for m in open_modes]) if len(open_modes) else np.zeros((len(weighted), 0))
        masses = np.einsum("ij,ij->j", X, short_mode.model.M @ X)  # the open modes' modal masses, one product
        likeness = list((X.T @ weighted) ** 2 / (masses * mass))
        best = max(range(len(likeness)), key=likeness.__getitem__, default=None)
        if best is None or likeness[best] < PARTNER_MAC:
            raise SolverError(f"no open-circuit mode with the shape of {short_mode.label} at "
                              f"{short_mode.frequency:.6g} Hz among the {len(likeness)} solved")
        return open_modes[best]
    same = [m for m in open_modes if m.label == short_mode.label]
    if not same:
        raise SolverError(f"no open-circuit mode labelled '{short_mode.label}'")
    return min(same, key=lambda m: abs(m.frequency - short_mode.frequency))
