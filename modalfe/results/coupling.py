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


def same_discretization(a, b) -> bool:
    """Whether the models ``a`` and ``b`` share one discretization (the same object, or the same mesh and DOFs: the
    circuits differ in the electrodes' unknowns only, the mass matrix is one), so shapes of one compare with the
    other's."""
    if a is b:
        return True
    key_a, key_b = getattr(getattr(a, "mesh", None), "key", None), getattr(getattr(b, "mesh", None), "key", None)
    return key_a is not None and key_a == key_b and getattr(a, "ndofs", None) == getattr(b, "ndofs", None)


def shape_likeness(model, short_shapes: np.ndarray, open_shapes: np.ndarray) -> np.ndarray:
    """Mass-weighted MAC (x_o^T M x_s)^2 / (x_o^T M x_o x_s^T M x_s) (n_short, n_open) of full DOF vectors (columns)
    on ``model``."""
    weighted = model.M @ short_shapes
    short_mass = np.einsum("ij,ij->j", short_shapes, weighted)
    open_mass = np.einsum("ij,ij->j", open_shapes, model.M @ open_shapes)
    return (weighted.T @ open_shapes) ** 2 / np.outer(short_mass, open_mass)


def antiresonance(short_mode, open_modes):
    """The open-circuit partner of ``short_mode`` by shape, never by label (a mode's label may differ between the
    circuits): on the same discretization (``same_discretization``) the open mode whose shape is most like it,
    ``shape_likeness`` (the open circuit only adds the floating potentials' stiffening: ~1 for the partner, ~0 for
    the others, M-orthogonal partners of other modes). SolverError where none reaches ``PARTNER_MAC`` (the partner
    was not among the modes solved) or where the open modes were solved on another discretization."""
    model = short_mode.model
    if not same_discretization(model, open_modes.model):
        raise SolverError("open-circuit modes of another discretization: their shapes do not compare with "
                          f"{short_mode.label}'s; solve them on its model (modalfe.solve.api.open_circuit_modes)")
    X = np.column_stack([m.shape for m in open_modes]) if len(open_modes) else np.zeros((len(short_mode.shape), 0))
    likeness = shape_likeness(model, short_mode.shape[:, None], X)[0]
    if not len(likeness) or likeness.max() < PARTNER_MAC:
        raise SolverError(f"no open-circuit mode with the shape of {short_mode.label} at "
                          f"{short_mode.frequency:.6g} Hz among the {len(likeness)} solved")
    return open_modes[int(np.argmax(likeness))]


def partner_labels(short_modes, open_modes):
    """``open_modes`` (a ``Modes`` of the same discretization as ``short_modes``) with each open mode paired one to one
    by shape with a short-circuit mode (``shape_likeness`` at least ``PARTNER_MAC``, the most alike pairs first)
    labelled as its partner, so that a mode keeps its label in both circuits; an unpaired open mode keeps its own
    label, suffixed ``#k`` where a partner took it."""
    from dataclasses import replace

    from scipy.optimize import linear_sum_assignment

    from modalfe.results.labels import SUFFIX, base_label

    if not len(short_modes) or not len(open_modes) or not same_discretization(short_modes.model, open_modes.model):
        return open_modes
    likeness = shape_likeness(short_modes.model, np.column_stack([m.shape for m in short_modes]),
                              np.column_stack([m.shape for m in open_modes]))
    rows, cols = linear_sum_assignment(-likeness)
    names = {int(c): short_modes[int(r)].label for r, c in zip(rows, cols) if likeness[r, c] >= PARTNER_MAC}
    taken = set(names.values())
    for k, m in enumerate(open_modes):
        if k in names:
            continue
        name, number = m.label, 1
        while name in taken:
            number += 1
            name = f"{base_label(m.label)}{SUFFIX}{number}"
        names[k] = name
        taken.add(name)
    return replace(open_modes, modes=tuple(replace(m, label=names[k]) for k, m in enumerate(open_modes)))
