"""Harmonic response by modal superposition with modal damping and the static residual of the modes
left out (the mode-acceleration method), for any load vector: a force on a face (the tile's actuator,
seed 002 eq. (9)) or a drive voltage (the ciliary beam's bimorph, seed 003 eq. (21)).

    x(omega) = sum_r phi_r (phi_r . f) / (omega_r^2 - omega^2 + 2 i zeta_r omega_r omega) + R,
    R = K_c^-1 f - sum_r phi_r (phi_r . f) / omega_r^2

with mass-normalised full DOF shapes phi_r and K_c the stiffness on the free unknowns (short
circuit). R is exact at omega = 0 and carries the modes above the computed band quasi-statically;
it also carries the massless electrical unknowns of a piezoelectric model.
"""

from __future__ import annotations

import numpy as np

from modalfe.errors import SceneError


def static_response(model, load: np.ndarray) -> np.ndarray:
    """Full DOF vector K_c^-1 f on the short-circuit free unknowns (supports must hold the body)."""
    from modalfe.solve.linalg import factorize

    T = model.constraints("short").T
    solve, _ = factorize((T.T @ model.K @ T).tocsr())
    return T @ solve(T.T @ load)


def static_voltage_response(model, volts: float) -> np.ndarray:
    """Full DOF vector (u then phi) under ``volts`` [V] on the driven electrodes, the others grounded:
    the static response to ``model.voltage_load(volts)`` plus the prescribed potential itself."""
    return static_response(model, model.voltage_load(volts)) + model.prescribed_potential(volts)


def modal_receptance(modes, load: np.ndarray, P, frequency, zeta, *, residual: bool = True,
                     static: np.ndarray | None = None) -> np.ndarray:
    """(n_f, n_out) complex response P x(omega) [output units per load unit] at ``frequency`` [Hz].

    ``modes``: a ``Modes`` whose shapes are full DOF vectors of ``modes.model``; ``load`` (ndofs,);
    ``P`` (n_out, ndofs) output rows (e.g. ``modalfe.response.forced.probes``); ``zeta`` a modal damping ratio,
    scalar or one per mode; ``residual`` adds R (see the module docstring); ``static``: K_c^-1 f of this
    ``load`` from ``static_response(modes.model, load)``, to factorize K_c once for several calls
    (computed here when None).
    """
    Phi = np.column_stack([m.shape for m in modes])
    omega_r = np.array([m.omega for m in modes])
    zeta = np.broadcast_to(np.asarray(zeta, dtype=float), omega_r.shape)
    if np.any(omega_r <= 0):
        raise SceneError("modes: a zero-frequency mode has no modal receptance (support the body)")
    p = Phi.T @ load
    out = np.asarray(P @ Phi)
    w = 2 * np.pi * np.atleast_1d(np.asarray(frequency, dtype=float))
    denominator = omega_r[None, :] ** 2 - w[:, None] ** 2 + 2j * zeta[None, :] * omega_r[None, :] * w[:, None]
    response = (p[None, :] / denominator) @ out.T
    if residual:
        if static is None:
            static = static_response(modes.model, load)
        R = P @ static - out @ (p / omega_r**2)
        response = response + np.asarray(R)[None, :]
    return response
