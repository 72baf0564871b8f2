"""Brute-force references for the contact simulators (verification oracles, not part of the library).

``brute_force_steady_state``: seed 000's foot model integrated in the seed's manner (scipy ``solve_ivp``
with Bogacki-Shampine RK23, the seed's ode23, max step 1e-7 s, terminal events at the switches).
``brute_force_finger``: seed 004's bed-spring finger integrated with tight tolerances (RK45 or DOP853,
rtol 1e-10, terminal events at separation and landing), both readings of eq. (1).
Only tests and studies import this module.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from modalfe.contact.foot import FN, SPEED, FootParameters, quasi_static_offset
from modalfe.contact.validation import require
from modalfe.errors import ContactError


@dataclass(frozen=True)
class BruteForceResult:
    """Steady state from time integration (seed 000 section 4.3.1.2: ode23, max step 1e-7 s).

    flight_ratio [%], normal_mean [N], friction_mean [N] per foot, over the last period;
    periods : periods integrated; converged : the period averages settled before ``max_periods``.
    """

    amplitude: float
    flight_ratio: float
    normal_mean: float
    friction_mean: float
    periods: int
    converged: bool


def brute_force_steady_state(amplitude: float, *, preload: float = FN, speed: float = SPEED,
                             parameters: FootParameters | None = None, max_step: float = 1e-7,
                             rtol: float = 1e-6, window: int = 20, settle: float = 1e-5,
                             max_periods: int = 20_000, start: str = "rest") -> BruteForceResult:
    """Reference steady state by scipy ``solve_ivp`` (RK23 = Bogacki-Shampine, the seed's ode23).

    Integrates seed 000 eqs 10-12 with the contact switch as a terminal event (Stateflow's role in the
    seed), the tangential displacement delta (eq. 17, reset at each touchdown) and the integrals of
    Rn and of Rt = mu Rn (eqs 14-16, written with delta_crit as printed) as extra states, and stops
    when beta, <Rn> and <Rt> over the last ``window`` periods spread less than ``settle`` (relative;
    beta in percentage points).  ``start``: ``rest`` (the plate at rest under its load when the
    vibration starts, as in the seed's simulations) or ``quasi-static`` (the first guess that
    ``steady_state`` shoots from, which shortens the transient).
    """
    from scipy.integrate import solve_ivp

    p = parameters if parameters is not None else FootParameters()
    W = require("amplitude", amplitude, nonnegative=True)
    Fn = require("preload", preload, nonnegative=True)
    V = require("speed", speed, nonnegative=True)
    M, P = p.mass / p.n, p.total_load(Fn) / p.n
    w, T = p.omega, p.period

    def contact_rhs(t, y):
        u, v, delta = y[0], y[1], y[2]
        Rn = -p.kn * (u + W * math.sin(w * t)) - p.dn * v  # eq. 3 with z_A = z_G + w_A
        delta_crit = p.mu0 * Rn / p.kt  # eq. 14
        mu = p.mu0 * delta / delta_crit if 0 < delta < delta_crit else p.mu0  # eqs 15, 16
        return [v, (Rn - P) / M, V, Rn, mu * Rn]

    def flight_rhs(t, y):
        return [y[1], -P / M, 0.0, 0.0, 0.0]

    def gap(t, y):
        return y[0] + W * math.sin(w * t)

    rising, falling = (lambda t, y: gap(t, y)), (lambda t, y: gap(t, y))
    rising.terminal = falling.terminal = True
    rising.direction, falling.direction = 1, -1
    su = max(W, P / p.kn)
    atol = 1e-3 * rtol * np.array([su, su * w, V * T + su, P * T, P * T])
    if start not in ("rest", "quasi-static"):
        raise ContactError(f"start: expected 'rest' or 'quasi-static', got {start!r}")
    u0 = -P / p.kn if start == "rest" else quasi_static_offset(W, P, p.kn)
    y = np.array([u0, 0.0, 0.0, 0.0, 0.0])
    contact = u0 <= 0
    history: list[tuple[float, float, float]] = []
    for k in range(max_periods):
        t, t_end, flight = k * T, (k + 1) * T, 0.0
        y[3:] = 0.0
        while t < t_end:
            sol = solve_ivp(contact_rhs if contact else flight_rhs, (t, t_end), y, method="RK23",
                            max_step=max_step, rtol=rtol, atol=atol, events=rising if contact else falling)
            if not contact:
                flight += sol.t[-1] - t
            t, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1:
                t, y = sol.t_events[0][0], sol.y_events[0][0].copy()
                contact = not contact
                if contact:
                    y[2] = 0.0  # eq. 17: the tangential displacement restarts at each touchdown
        history.append((100 * flight / T, y[3] / T, y[4] / T))
        if len(history) >= window:
            last = np.array(history[-window:])
            spread = last.max(axis=0) - last.min(axis=0)
            scale_ = np.array([1.0, abs(last[-1, 1]) or 1.0, abs(last[-1, 2]) or 1.0])
            if np.all(spread <= settle * scale_):
                return BruteForceResult(W, *history[-1], k + 1, True)
    return BruteForceResult(W, *history[-1], max_periods, False)
