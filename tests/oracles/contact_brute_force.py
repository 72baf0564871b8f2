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
    clipped = p.friction_law == "clipped"
    w, T = p.omega, p.period

    def contact_rhs(t, y):
        u, v, delta = y[0], y[1], y[2]
        Rn = -p.kn * (u + W * math.sin(w * t)) - p.dn * v  # eq. 3 with z_A = z_G + w_A
        if clipped:  # Rt = min(kt delta, mu0 max(Rn, 0)), the library's default friction law
            Rt = min(p.kt * delta, p.mu0 * max(Rn, 0.0))
            return [v, (Rn - P) / M, V, Rn, Rt]
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


# ----------------------------------------------------------------------------------------------
# Brute-force reference for seed 004's finger
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class BruteForceFinger:
    """Time average of seed 004's finger from a direct integration.

    friction_ratio : sum int f_T / (mu sum int f_N) over the averaged periods; uncertainty : its
    standard error by batch means (10 batches); normal_mean [N]; contact_ratio [%];
    landings_per_period; per_period : (int f_T, int f_N) of every averaged period; state : the final state.
    """

    friction_ratio: float
    uncertainty: float
    normal_mean: float
    contact_ratio: float
    landings_per_period: float
    per_period: np.ndarray
    state: np.ndarray


def brute_force_finger(amplitude_pp: float, frequency: float, *, parameters=None, periods: int = 400,
                       skip: int = 200, rtol: float = 1e-10, method: str = "DOP853",
                       state: np.ndarray | None = None) -> BruteForceFinger:
    """Seed 004's bed-spring finger integrated with scipy ``solve_ivp`` (``method``, ``rtol``; max step
    T/100), independently of ``modalfe.contact.finger``: the three masses' equations (eqs 1, 2 in the
    model's reading, ``parameters.reading``), the stratum corneum's compression q as a state, the
    integrals of f_Nsc and f_Tsc as states, and three modes switched by terminal events - flight
    (f_T = 0) until landing, stick (f_T = K_Tsc V_F (t - t_c)) until K_Tsc V_F (t - t_c) = mu f_Nsc,
    slide (f_T = mu f_Nsc) until f_Nsc falls to zero.  Starts from rest under f_p in contact, sliding,
    or from ``state`` = (y, v, q) at t = 0 (flying if off the plate, else sliding: give ``skip`` >= 1
    so that the stick history is the integrator's own), integrates ``periods`` drive periods and
    averages over those after ``skip``.
    """
    from scipy.integrate import solve_ivp

    from modalfe.contact.finger import FingerParameters

    p = parameters if parameters is not None else FingerParameters()
    K, D, M = p.stiffness, p.damping, p.mass
    kv_ = p.reading == "kelvin-voigt"
    fp, w_, a = p.preload, 2 * math.pi * frequency, amplitude_pp / 2
    q0, T = fp / K[0], 1 / frequency
    kt_v = p.K_Tsc * p.speed

    def layer_forces(y):
        if kv_:
            fe = fp + K[1] * (y[0] - y[1]) + D[1] * (y[3] - y[4])
            fst = fp + K[2] * (y[1] - y[2]) + D[2] * (y[4] - y[5])
        else:  # eq. (1) as printed: dampers on the absolute velocities
            fe = fp + K[1] * (y[0] - y[1]) - D[1] * y[4]
            fst = fp + K[2] * (y[1] - y[2]) - D[2] * y[5]
        return fe, fst

    def contact_force(t, y):
        w, wd = a * math.sin(w_ * t), a * w_ * math.cos(w_ * t)
        return fp + K[0] * (w - y[0]) + (D[0] * (wd - y[3]) if kv_ else -D[0] * y[3])

    def force_rate(t, y):
        """d f_Nsc / dt in contact."""
        wd, wdd = a * w_ * math.cos(w_ * t), -a * w_ * w_ * math.sin(w_ * t)
        fe, _ = layer_forces(y)
        acc = (contact_force(t, y) - fe) / M[0]
        return K[0] * (wd - y[3]) + (D[0] * (wdd - acc) if kv_ else -D[0] * acc)

    def rhs(mode, tc):
        def f(t, y):
            fe, fst = layer_forces(y)
            wd = a * w_ * math.cos(w_ * t)
            if mode == "flight":
                fsc, ft = 0.0, 0.0
                qd = -K[0] / D[0] * y[6] if kv_ else 0.0
            else:
                fsc = contact_force(t, y)
                qd = wd - y[3]
                ft = kt_v * (t - tc) if mode == "stick" else p.mu * fsc
            return [y[3], y[4], y[5], (fsc - fe) / M[0], (fe - fst) / M[1], (fst - fp) / M[2], qd, fsc, ft]
        return f

    def separation(t, y):
        return contact_force(t, y)

    def landing(t, y):
        if kv_:
            return q0 + a * math.sin(w_ * t) - y[0] - y[6]
        return contact_force(t, y)

    separation.terminal, separation.direction = True, -1
    landing.terminal, landing.direction = True, 1

    def slip_event(tc):
        def slip(t, y):
            return kt_v * (t - tc) - p.mu * contact_force(t, y)
        slip.terminal, slip.direction = True, 1
        return slip

    y = np.zeros(9)
    y[6] = q0
    if state is not None:
        y[:7] = state
    mode, tc = "slide", -math.inf
    if state is not None and (landing(0.0, y) < -1e-12 * max(a, q0) or contact_force(0.0, y) <= 0):
        mode = "flight"  # a state off the plate (its stick history, if in contact, is unknown: skip >= 1)
    su = max(a, q0)
    atol = 1e-12 * np.array([su, su, su, su * w_, su * w_, su * w_, su, fp * T, fp * T])
    rows, contact_time, landings = [], 0.0, 0
    for k in range(periods):
        t, t_end = k * T, (k + 1) * T
        y[7:] = 0.0
        in_contact = 0.0
        while t < t_end:
            events = [landing] if mode == "flight" else [separation] + ([slip_event(tc)] if mode == "stick" else [])
            sol = solve_ivp(rhs(mode, tc), (t, t_end), y, method=method, rtol=rtol, atol=atol, max_step=T / 100,
                            events=events)
            t_new, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1:
                i = next(j for j, te in enumerate(sol.t_events) if len(te))
                t_new, y = sol.t_events[i][0], sol.y_events[i][0].copy()
            if mode != "flight":
                in_contact += t_new - t
            t = t_new
            if sol.status != 1:
                break
            if mode == "flight":
                mode, tc = "stick", t
                y[6] = q0 + a * math.sin(w_ * t) - y[0]
                if k >= skip:
                    landings += 1
                # the literal reading lands with f_Nsc = 0: the pulp slides at once if mu f_Nsc grows
                # more slowly than the stick force K_Tsc V_F (t - t_c), both zero at t_c
                if contact_force(t, y) <= 0 and kt_v >= p.mu * force_rate(t, y):
                    mode = "slide"
            elif i == 0:  # separation
                mode = "flight"
            else:  # the stick force reached mu f_N
                mode = "slide"
        if k >= skip:
            rows.append((y[8], y[7]))
            contact_time += in_contact
    rows = np.array(rows)
    ratio = rows[:, 0].sum() / (p.mu * rows[:, 1].sum())
    batches = np.array_split(rows, 10)
    r = np.array([b[:, 0].sum() / (p.mu * b[:, 1].sum()) for b in batches])
    n = len(rows)
    return BruteForceFinger(float(ratio), float(np.std(r, ddof=1) / math.sqrt(len(r))),
                            float(rows[:, 1].sum() / (n * T)), 100 * contact_time / (n * T), landings / n, rows,
                            y[:7].copy())
