"""Bed-spring model of a fingertip on an ultrasonic plate: friction reduction against amplitude and
frequency (seed 004, section II, Figs 1-7, Table I).  The normal axis is in
``modalfe.contact.finger_model``; the shooting kernel in ``modalfe.contact.kernel``.

Reading of eq. (1).  Seed 004 prints ``f_Nj = K_j int(u_i - u_j) dt - D_j u_j`` (``u`` are velocities):
a spring on the layer's compression but a damper on the *absolute* velocity ``u_j`` of mass ``j``.
**The seed's equations support that literal reading** (``reading="literal"``): nothing else in eqs 1-2
puts a relative velocity in the damper, and "critical damping of each layer" (section II.C) holds in
both readings (a layer alone, one end fixed, has u_i = 0).  Taken literally, though, the finger never
leaves the plate below 0.8 um pp at 66 kHz (0 % flight at 0.6 um pp, where the Kelvin-Voigt reading
gives 69 %) and, where it does fly, its contact force restarts from zero at each landing and grows
more slowly than ``K_Tsc V_F / mu``, so the pulp slides from the first instant and
``<f_Tsc> = mu <f_Nsc> = mu f_p``: no friction reduction at all (to rounding, up to 3 um pp at 66 kHz
and 1 um pp at 225 kHz).  That contradicts the seed's own results (Figs 5-7: flying and sticking
states, friction reduction, the 0.12 amplitude ratio), so the default is the reading that reproduces
them, Kelvin-Voigt layers whose damper acts on the layer's rate of compression,
``f_Nj = K_j int(u_i - u_j) dt + D_j (u_i - u_j)`` (``reading="kelvin-voigt"``).  Both are tested
against an independent solve_ivp integration (``tests/oracles/contact_brute_force.py``).

Tangential axis (Fig. 2): on landing the pulp sticks, ``f_Tsc = K_Tsc V_F (t - t_c)``; once that reaches
``mu f_Nsc`` it slides, ``f_Tsc = mu f_Nsc``, until it flies (``f_Tsc = 0``).  The friction ratio is
``mu_US / mu = <f_Tsc> / (mu <f_Nsc>)`` (see ``FingerOrbit``).  A landing needs a flight of positive
duration: a tangency of ``f_Nsc`` with zero is no flight and restarts nothing.

Steady state, by ``kernel.find_orbit``: periodic orbits of period k T (k = 1..``max_period``) found
directly by shooting on k T with the exact monodromy, accepted only when stable (every Floquet
multiplier inside the unit circle); only when there is none the result is a time average, with its
stated uncertainty (an upper 95 % bound on its standard error, by batch means).  Each result says which:
``FingerOrbit.method`` is ``"periodic kT"`` or ``"average +- u"``.  At 66 kHz the finger is on a period-1
orbit up to ~0.66 um pp, on a period-2 orbit from there to ~0.79 um pp (the period-1 orbit loses stability
through a multiplier -1), and above that it bounces irregularly (no stable orbit up to 8 T; a 1500-period march
shows no recurrence).
Every integral is in closed form (``finger_model.ExpSum``).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from modalfe.contact.finger_model import (  # noqa: F401  (re-exported: the finger's public names)
    FREQUENCIES,
    K_E,
    K_SC,
    K_ST,
    K_TSC,
    M_E,
    M_SC,
    M_ST,
    MU,
    PRELOAD,
    READINGS,
    SPEED,
    FingerParameters,
    Piece,
    _FingerDynamics,
    advance,
)
from modalfe.contact.kernel import batch_ratio, find_orbit, first_crossing, landed_window, touchdown_times
from modalfe.contact.validation import require, values
from modalfe.errors import ContactError

log = logging.getLogger(__name__)

MAX_PERIOD = 8  # longest periodic orbit sought, in drive periods
# Time marching before the search for orbits of period k >= 2 and before a time average: from rest
# or from the period-1 orbit (a cold start), or from a neighbouring amplitude's attractor (warm).
MARCH_PERIODS = 300
WARM_MARCH_PERIODS = 20  # from a neighbouring attractor: a short run-in (the st layer decays by e^-1.7)
MAX_AVERAGE_PERIODS = 8000  # the window doubles up to this while the stated uncertainty exceeds the target
# Target of the stated uncertainty of mu_US / mu for a time average (the window doubles while it is above).
AVERAGE_TOL = 4e-3
# A time average's uncertainty is by batch means (``kernel.batch_ratio``: an upper 95 % bound on the standard
# error) over BATCHES batches, each at least BATCH_DECAY_TIMES of the finger's slowest decay time in contact
# (``slowest_decay_time``: 23 periods at 66 kHz; e^-3 of a deviation is left after a batch), so the first window
# is 8 x 71 = 568 periods at 66 kHz.  With 150-period windows of 10 batches (15 periods each) the plain standard
# error was 0.66 and 0.64 of the scatter between averages at 3.2 and 5 um pp; with batches of 71-568 periods
# 0.86-0.99 (studies/finger_uncertainty.py batches).
BATCHES = 8
BATCH_DECAY_TIMES = 3
# A window that stops doubling once its own bound is below the target stops more often where that
# bound is low by chance, so the stated uncertainty is the largest of its bound and those of the shorter windows
# tried, each scaled to the window (x sqrt(its length / the window's), the standard error of an average falling
# as the root of its length); it can exceed the target by up to sqrt(2).  In sequences of averages cut from
# 100 000- and 300 000-period runs at 66 kHz the window's own bound was 1.24 (3.2 um pp) and 1.08 (5 um pp) times
# the scatter between averages, the largest one 1.52 and 1.42 (studies/finger_uncertainty.py batches).


@dataclass(frozen=True, eq=False)
class FingerOrbit:
    """Steady state of the finger at one amplitude and frequency.

    amplitude_pp : peak-to-peak plate amplitude [m]; frequency [Hz];
    friction_ratio : mu_US / mu = <f_Tsc> / (mu <f_Nsc>), which is <f_Tsc> / (mu f_p) on a periodic orbit
    (momentum balance, <f_Nsc> = f_p) and its lower-variance estimate over a time average;
    uncertainty : an upper 95 % bound on the standard error of friction_ratio (batch means over the time average,
    ``kernel.batch_ratio``; 0 on an orbit);
    normal_mean : <f_Nsc> [N]; contact_ratio : time in contact [%]; contacts_per_period : landings
    per drive period; periodic : a stable periodic orbit of ``periods`` drive periods (its minimal
    period k), else a time average over ``periods`` periods; state : the state at t = 0 on the orbit
    (or at the end of the average); period_one : the period-1 orbit's state, stable or not (a guess
    for a neighbouring amplitude), None if shooting did not converge; unstable : (k, largest
    |multiplier|) of the periodic orbits found and rejected as unstable.
    """

    amplitude_pp: float
    frequency: float
    parameters: FingerParameters
    friction_ratio: float
    uncertainty: float
    normal_mean: float
    contact_ratio: float
    contacts_per_period: float
    periodic: bool
    periods: int
    state: np.ndarray
    period_one: np.ndarray | None = None
    unstable: tuple[tuple[int, float], ...] = ()

    @property
    def method(self) -> str:
        """``periodic kT`` (a stable orbit of period k T) or ``average +- u`` (a time average)."""
        return f"periodic {self.periods}T" if self.periodic else f"average +- {self.uncertainty:.1e}"


def _sums(dyn: _FingerDynamics, pieces: Sequence[Piece], tcs: Sequence[float | None]):
    """Per piece: int f_Nsc dt, int f_Tsc dt (stick, then slide; seed 004 Fig. 2), contact time."""
    p = dyn.p
    kv = p.K_Tsc * p.speed
    n_int, t_int, c_time = np.zeros(len(pieces)), np.zeros(len(pieces)), np.zeros(len(pieces))
    episode, sliding = None, False
    for i, (q, tc) in enumerate(zip(pieces, tcs)):
        if not q.contact:
            continue
        if tc != episode:
            episode, sliding = tc, False
        f = q.force
        n = f.integral(q.t0, q.t1)
        n_int[i], c_time[i] = n, q.t1 - q.t0
        if tc == -math.inf or sliding:
            t_int[i] = p.mu * n
            continue

        def excess(t, f=f, tc=tc):  # K_Tsc X_T - mu f_N: the pulp slides once this reaches zero
            v, d = f(t)
            return kv * (t - tc) - p.mu * v, kv - p.mu * d

        ts = first_crossing(excess, q.t0, q.t1, dyn.step, upward=True)
        end = q.t1 if ts is None else ts
        t_int[i] = 0.5 * kv * ((end - tc) ** 2 - (q.t0 - tc) ** 2)
        if ts is not None:
            sliding = True
            t_int[i] += p.mu * f.integral(ts, q.t1)
    return n_int, t_int, c_time


def finger_steady_state(amplitude_pp: float, frequency: float, *, parameters: FingerParameters | None = None,
                        guess: np.ndarray | None = None, hints: Sequence[tuple[int, np.ndarray]] = (),
                        start: np.ndarray | None = None, max_period: int = MAX_PERIOD,
                        march_periods: int | None = None, average_tol: float = AVERAGE_TOL) -> FingerOrbit:
    """Steady state of seed 004's bed-spring finger (section II: eqs 1-2, the contact/flying states and
    Fig. 2's stick-slip) on a plate vibrating at ``frequency`` [Hz] with peak-to-peak amplitude
    ``amplitude_pp`` [m]: mu_US / mu as on p. 3 ("by averaging the tangential force"), by a stable
    periodic orbit of period k T or a time average with its standard error (see ``FingerOrbit.method``).

    guess : a state at t = 0 to shoot the period-1 orbit from (default: the preloaded rest);
    hints : (k, state) pairs to shoot period-k orbits from (e.g. a neighbouring amplitude's);
    start : a state to march from before the search for k >= 2 and a time average (default: the
    period-1 orbit, disturbed along its unstable direction); march_periods : the march's length
    (default MARCH_PERIODS, or WARM_MARCH_PERIODS from a ``start``); max_period : N, orbits of period k T,
    k = 1..N are sought (``kernel.find_orbit``); average_tol : target of a time average's uncertainty
    of mu_US / mu (the window doubles from BATCHES batches of BATCH_DECAY_TIMES decay times up to
    MAX_AVERAGE_PERIODS while its own bound exceeds it; the stated uncertainty: see BATCHES).
    """
    p = parameters if parameters is not None else FingerParameters()
    A = require("amplitude", amplitude_pp, nonnegative=True)
    f = require("frequency", frequency, positive=True)
    require("average_tol", average_tol, positive=True)
    dyn = _FingerDynamics(p, 2 * math.pi * f, A / 2)
    T = 1 / f
    x0 = np.zeros(7)
    x0[6] = dyn.q_rest
    if guess is not None:
        x0 = np.asarray(guess, float)

    def period_map(k, x, sensitivity=True):
        _, xT, Phi = advance(dyn, 0.0, k * T, x, sensitivity=sensitivity)
        return xT, Phi

    if march_periods is None:
        march_periods = MARCH_PERIODS if start is None else WARM_MARCH_PERIODS
    su = max(A / 2, dyn.q_rest)
    scale = np.array([su] * 3 + [su * dyn.omega] * 3 + [su])
    search = find_orbit(period_map, x0, scale, max_period=max_period, march_periods=march_periods,
                        hints=hints, march_from=start)
    one = search.shooting.state if search.shooting.converged and search.period in (0, 1) else None
    x = search.state
    if search.period:
        k = search.period
        pieces, tcs = landed_window(lambda t0, t1: advance(dyn, t0, t1, x, sensitivity=False)[0], k * T, True)
        n_int, t_int, c_time = _sums(dyn, pieces, tcs)
        span = k * T
        ratio, uncertainty, periods = float(t_int.sum() / (p.mu * n_int.sum())), 0.0, k
    else:
        # batches of BATCH_DECAY_TIMES decay times (a lightly damped finger's capped: the window's limit in one)
        batch = math.ceil(min(BATCH_DECAY_TIMES * dyn.slowest_decay_time * f, MAX_AVERAGE_PERIODS / BATCHES))
        window, pieces, end = BATCHES * batch, [], 0.0
        tried = []  # (bound, window) of each shorter window: its bound exceeded the target
        while True:
            more, x, _ = advance(dyn, end, window * T, x, sensitivity=False)
            pieces += more
            end = window * T
            first = next((i for i in range(1, len(pieces)) if pieces[i].contact and not pieces[i - 1].contact
                          and pieces[i - 1].t1 > pieces[i - 1].t0), None)
            if first is None:
                raise ContactError(f"amplitude: the finger did not land while averaging at {A:g} m pp, {f:g} Hz")
            used = pieces[first:]
            tcs = touchdown_times(used, first=used[0].t0)
            n_int, t_int, c_time = _sums(dyn, used, tcs)
            ratio, bound = batch_ratio(t_int / p.mu, n_int, BATCHES)
            if bound <= average_tol or window >= MAX_AVERAGE_PERIODS:
                break
            tried.append((bound, window))
            window *= 2
        pieces, span = used, end - used[0].t0
        periods = round(span * f)
        uncertainty = max([bound] + [b * math.sqrt(w / window) for b, w in tried])  # see BATCHES
        if bound > average_tol:
            log.warning("finger: time average over %d periods at %g m pp, %g Hz has an uncertainty %.2g",
                        periods, A, f, uncertainty)
    landings = sum(1 for q, tc in zip(pieces, tcs) if q.contact and tc == q.t0)
    if n_int.sum() <= 0:
        raise ContactError(f"amplitude: the finger did not touch the plate at {A:g} m pp, {f:g} Hz")
    return FingerOrbit(
        amplitude_pp=A, frequency=f, parameters=p, friction_ratio=ratio, uncertainty=uncertainty,
        normal_mean=float(n_int.sum() / span), contact_ratio=float(100 * c_time.sum() / span),
        contacts_per_period=landings / (periods if search.period else span * f), periodic=bool(search.period),
        periods=periods, state=x,
        period_one=one, unstable=search.unstable)


@dataclass(frozen=True, eq=False)
class FingerCurve:
    """Friction ratio mu_US / mu against peak-to-peak amplitude at one frequency (seed 004 Fig. 6).

    amplitude_pp [m]; frequency [Hz]; friction_ratio; uncertainty (standard error; 0 on a periodic
    orbit); contact_ratio [%]; contacts_per_period; periodic (a stable periodic orbit, else a time
    average); periods (k of the orbit, or the periods averaged); ``method`` says it per point.
    """

    amplitude_pp: np.ndarray
    frequency: float
    parameters: FingerParameters
    friction_ratio: np.ndarray
    uncertainty: np.ndarray
    contact_ratio: np.ndarray
    contacts_per_period: np.ndarray
    periodic: np.ndarray
    periods: np.ndarray

    @property
    def method(self) -> list[str]:
        """Per point: ``periodic kT`` or ``average +- u``."""
        return [f"periodic {k}T" if per else f"average +- {u:.1e}"
                for per, k, u in zip(self.periodic, self.periods, self.uncertainty)]

    def to_json(self) -> dict:
        return {"frequency_hz": self.frequency, "amplitude_pp_m": self.amplitude_pp.tolist(),
                "friction_ratio": self.friction_ratio.tolist(), "uncertainty": self.uncertainty.tolist(),
                "method": self.method, "contact_ratio_percent": self.contact_ratio.tolist(),
                "contacts_per_period": self.contacts_per_period.tolist(), "periodic": self.periodic.tolist(),
                "periods": self.periods.tolist()}


def simulate_finger(amplitude_pp, frequency: float = FREQUENCIES[0], *, parameters: FingerParameters | None = None,
                    progress: bool = False) -> FingerCurve:
    """mu_US / mu against peak-to-peak amplitude [m] at ``frequency`` [Hz] (seed 004 Fig. 6).

    Amplitudes are solved in increasing order, each continued from the previous one: its period-1
    orbit as the first guess, its stable orbit of period k > 1 as a hint, its state as the start of
    the march.
    """
    p = parameters if parameters is not None else FingerParameters()
    A = values("amplitude", amplitude_pp)
    require("frequency", frequency, positive=True)
    order = np.argsort(A, kind="stable")
    items = order
    if progress:
        from tqdm import tqdm

        items = tqdm(order, desc=f"finger {frequency / 1e3:g} kHz", unit="amplitude", leave=False)
    orbits: dict[int, FingerOrbit] = {}
    prev: FingerOrbit | None = None
    for i in items:
        kw = {}
        if prev is not None:
            kw["guess"] = prev.period_one if prev.period_one is not None else prev.state
            kw["hints"] = [(prev.periods, prev.state)] if prev.periodic and prev.periods > 1 else []
            kw["start"] = None if prev.periodic and prev.periods == 1 else prev.state
        prev = orbits[int(i)] = finger_steady_state(A[i], frequency, parameters=p, **kw)
    ordered = [orbits[i] for i in range(len(A))]
    return FingerCurve(
        amplitude_pp=A, frequency=float(frequency), parameters=p,
        friction_ratio=np.array([o.friction_ratio for o in ordered]),
        uncertainty=np.array([o.uncertainty for o in ordered]),
        contact_ratio=np.array([o.contact_ratio for o in ordered]),
        contacts_per_period=np.array([o.contacts_per_period for o in ordered]),
        periodic=np.array([o.periodic for o in ordered]),
        periods=np.array([o.periods for o in ordered]))


@dataclass(frozen=True, eq=False)
class EqualFriction:
    """Amplitudes giving the same friction at two frequencies (seed 004 Fig. 7).

    level : mu_US / mu; amplitude_low, amplitude_high : peak-to-peak [m] at ``frequencies``
    (low, high) [Hz]; *_uncertainty : their standard errors from the curves' uncertainties (through
    the local slope); ratio : amplitude_high / amplitude_low.  For comparison, equal velocity gives
    f_low / f_high and equal acceleration (f_low / f_high)^2.
    """

    level: np.ndarray
    frequencies: tuple[float, float]
    amplitude_low: np.ndarray
    amplitude_high: np.ndarray
    amplitude_low_uncertainty: np.ndarray | None = None
    amplitude_high_uncertainty: np.ndarray | None = None

    @property
    def ratio(self) -> np.ndarray:
        return self.amplitude_high / self.amplitude_low

    @property
    def ratio_uncertainty(self) -> np.ndarray:
        """Standard error of the ratio (relative errors of the two amplitudes added in quadrature)."""
        zero = np.zeros_like(self.level)
        lo = self.amplitude_low_uncertainty if self.amplitude_low_uncertainty is not None else zero
        hi = self.amplitude_high_uncertainty if self.amplitude_high_uncertainty is not None else zero
        return self.ratio * np.hypot(lo / self.amplitude_low, hi / self.amplitude_high)

    @property
    def velocity_ratio(self) -> float:
        return self.frequencies[0] / self.frequencies[1]

    @property
    def acceleration_ratio(self) -> float:
        return self.velocity_ratio ** 2

    def to_json(self) -> dict:
        return {"frequencies_hz": list(self.frequencies), "level": self.level.tolist(),
                "amplitude_low_pp_m": self.amplitude_low.tolist(), "amplitude_high_pp_m": self.amplitude_high.tolist(),
                "ratio": self.ratio.tolist(), "ratio_uncertainty": self.ratio_uncertainty.tolist(),
                "equal_velocity_ratio": self.velocity_ratio, "equal_acceleration_ratio": self.acceleration_ratio}


def _amplitude_for(curve: FingerCurve, level: float) -> tuple[float, float]:
    """Smallest amplitude at which the curve's friction ratio falls to ``level`` (linear interpolation
    between the two bracketing points) and its standard error (the points' uncertainty over the slope)."""
    order = np.argsort(curve.amplitude_pp, kind="stable")
    a, r, u = curve.amplitude_pp[order], curve.friction_ratio[order], curve.uncertainty[order]
    below = np.flatnonzero(r <= level)
    if not below.size or below[0] == 0:
        raise ContactError(f"level: friction ratio {level:g} is outside the curve at {curve.frequency:g} Hz "
                           f"({r.min():.3g} to {r.max():.3g}); widen the amplitude range")
    i = below[0]
    a0, a1, r0, r1 = a[i - 1], a[i], r[i - 1], r[i]
    slope = (r1 - r0) / (a1 - a0)
    return float(a0 + (level - r0) / slope), float(max(u[i - 1], u[i]) / abs(slope))


def equal_friction(low: FingerCurve, high: FingerCurve, levels: Sequence[float]) -> EqualFriction:
    """Amplitude ratio A(high) / A(low) giving equal mu_US / mu at each level (seed 004 Fig. 7: about 0.12).

    Each curve must start above each level and reach below it; the curves' resolution sets the
    accuracy (linear interpolation between the two points around the first crossing).
    """
    lv = values("level", levels)
    for i, x in enumerate(lv):
        if not 0 < x < 1:
            raise ContactError(f"level[{i}]: a friction ratio strictly between 0 and 1, got {x:g}")
    lo = np.array([_amplitude_for(low, x) for x in lv]).reshape(-1, 2)
    hi = np.array([_amplitude_for(high, x) for x in lv]).reshape(-1, 2)
    return EqualFriction(lv, (low.frequency, high.frequency), lo[:, 0], hi[:, 0], lo[:, 1], hi[:, 1])
