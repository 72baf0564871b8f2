"""Steady state of a plate on vibrating feet: flight ratio and Coulomb-Orowan friction (seed 000
eqs 2-17; seed 001 section 5).  The normal axis (parameters, closed-form arcs, events) is in
``modalfe.contact.foot_model``; the shooting kernel in ``modalfe.contact.kernel``.

Flight ratio, seed 000 eq. 13: ``beta = 100 (t_s - t_c) / T`` generalised to the total flight time per
period when the foot lands several times a period ("chattering").

Tangential force, Coulomb-Orowan (seed 000 eqs 14-17; seed 001 eqs 1-4, 8): the foot slides at the
speed ``V`` imposed by the user; the tangential displacement since the last touchdown is
``delta = V (t - t_c)``; ``delta_crit = mu0 Rn / kt``; ``mu = mu0 delta / delta_crit`` while
``delta < delta_crit``, else ``mu0``; ``Rt = mu Rn``.  Written out, ``Rt = min(kt V (t - t_c), mu0 Rn)``
during contact and 0 in flight.  Eq. 3's ``Rn`` dips slightly below zero just before lift-off (the
damper acts on ``z_G'``), which would make the printed ``Rt`` negative for an instant; by default the
friction uses ``Rn`` clipped at zero, **``Rt = min(kt V (t - t_c), mu0 max(Rn, 0))``**
(``FootParameters(friction_law="printed")`` keeps the printed form).  Without flight (contact since
``t_c = -inf``) ``Rt = mu0 max(Rn, 0)``.  The friction force felt by the user is ``n <Rt>``.

Speed 0 is the limit V -> 0+: after a touchdown ``kt V (t - t_c) = 0`` and the foot sticks with no
tangential force (``Rt = 0``); without flight (W at or below the onset) it has been sliding since
``t_c = -inf`` and ``Rt = mu0 max(Rn, 0)``.  So at V = 0 the friction is ``mu0 (Fn + m g)`` up to the
onset amplitude and 0 above it.

Onset of flight: up to ``FootParameters.onset_amplitude`` the contact-only linear response (a closed
form, no event to find) is a steady state; at the onset it grazes the ground.  Amplitudes up to the
onset are answered by that closed form exactly unless the motion from rest flies off it onto a
coexisting chattering orbit, which is then shot and reported; so are those less than ``GRAZING``
(1e-8, relative) above it, where the flight lasts < 1e-5 of a period and double precision cannot
resolve it (flight ratio < 1e-3 %; the friction is the limit from below the onset, which the one just
above it matches to 1e-7 at light loads only: at 10 N it is 40 % lower, docs/contact.md).

Method: one period of the event-driven exact solution is the period map; the periodic steady state is
its fixed point, found by Newton's method (shooting, ``kernel.shoot_periodic``) with the exact
monodromy matrix, seeded by the motion from rest and accepted only where that motion reaches it
(``_search_from_rest``: period k T, k <= 8, stable orbits only; issue 35); failing that the solver
averages over many periods (``periodic = False``, with a batch-means uncertainty).  Period averages of ``Rn`` and
``Rt`` are Gauss-Legendre integrals over the contact arcs, split where ``kt V (t - t_c) = mu0 Rn`` and
where ``Rn`` changes sign, so every piece is smooth.  A brute-force reference (scipy ``solve_ivp``, the
seed's ode23 settings) lives with the tests, ``tests/oracles/contact_brute_force.py``.
"""

from __future__ import annotations

import itertools
import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from modalfe.contact.foot_model import (  # noqa: F401  (re-exported: the foot's public names)
    DN,
    FN,
    FREQUENCY,
    FRICTION_LAWS,
    KN,
    KT,
    MASS,
    N_FEET,
    SPEED,
    SUBSTRATES,
    FootParameters,
    G,
    _advance,
    _Arc,
    _Dynamics,
    _Piece,
    quasi_static_offset,
)
from modalfe.contact.kernel import (
    batch_ratio,
    find_orbit,
    gauss_nodes,
    landed_window,
    shoot_periodic,
    sign_changes,
)
from modalfe.contact.validation import require, values
from modalfe.errors import ContactError

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class ContactOrbit:
    """Steady state of one foot at one amplitude, preload and speed.

    amplitude : W, 0-peak [m]; preload : Fn [N]; speed : V [m/s];
    flight_ratio : beta, flight time per period [%] (seed 000 eq. 13);
    normal_mean : <Rn> per foot [N]; friction_mean : <Rt> per foot [N] (seed 001 eq. 8);
    contacts_per_period : touchdowns per drive period (0 in permanent contact);
    periodic : True for an exact periodic orbit (shooting) of ``periods`` drive periods (1, or k for a
    subharmonic orbit), False for a time average over ``periods`` periods; residual : scaled shooting
    residual (NaN for a time average).  ``balance_error`` states how far a time average is from converged, and
    ``friction_uncertainty`` the relative uncertainty of its <Rt> (batch means, an upper 95 % bound on the
    standard error; 0 on an orbit).
    """

    amplitude: float
    preload: float
    speed: float
    parameters: FootParameters
    flight_ratio: float
    normal_mean: float
    friction_mean: float
    contacts_per_period: float
    periodic: bool
    residual: float
    periods: int
    pieces: tuple[_Piece, ...]
    touchdowns: tuple[float, ...]
    piece_touchdowns: tuple[float | None, ...] = ()
    friction_uncertainty: float = 0.0

    @property
    def balance_error(self) -> float:
        """|<Rn> / (load per foot) - 1|: zero on a periodic orbit (momentum balance over a period),
        and for a time average the size of its unfinished transient, M (v_end - v_start) / (span P)."""
        return abs(self.normal_mean * self.parameters.n / self.parameters.total_load(self.preload) - 1)

    @property
    def friction_force(self) -> float:
        """Friction felt by the user, n <Rt> [N]."""
        return self.parameters.n * self.friction_mean

    @property
    def t_start(self) -> float:
        """Start of the analysed window [s] (a touchdown when there is one)."""
        return self.pieces[0].t0

    def _locate(self, t):
        """Wrap times into the analysed window and find each one's arc."""
        t = np.asarray(t, float)
        span = self.pieces[-1].t1 - self.t_start
        tw = self.t_start + np.mod(t - self.t_start, span)
        ends = np.array([p.t1 for p in self.pieces])
        return tw, np.minimum(np.searchsorted(ends, tw), len(self.pieces) - 1)

    def _per_piece(self, t, value) -> np.ndarray:
        """``value(piece, times)`` on each analysed piece, at the times t wrapped into the window."""
        tw, idx = self._locate(t)
        out = np.zeros_like(tw)
        for i in np.unique(idx):
            m = idx == i
            out[m] = value(self.pieces[i], tw[m])
        return out

    def normal_force(self, t) -> np.ndarray:
        """Rn(t) per foot [N] (seed 000 eqs 3, 4) on the steady state."""
        return self._per_piece(t, lambda piece, tw: piece.arc.normal_force(tw))

    def friction(self, t) -> np.ndarray:
        """Rt(t) per foot [N], Coulomb-Orowan (seed 000 eqs 14-17, Rn clipped unless printed) on the steady state."""
        p = self.parameters

        def rt(piece, tw):
            if not piece.arc.contact:
                return 0.0
            return _tangential(piece.arc.normal_force(tw), tw, self._touchdown(piece), p.kt, self.speed, p.mu0,
                               p.friction_law == "clipped")
        return self._per_piece(t, rt)

    def gap(self, t) -> np.ndarray:
        """z_A - h per foot [m]: negative in contact."""
        return self._per_piece(t, lambda piece, tw: piece.arc.gap(tw))

    def _touchdown(self, piece: _Piece) -> float:
        return self.piece_touchdowns[self.pieces.index(piece)]


def _tangential(Rn, t, tc: float, kt: float, speed: float, mu0: float, clipped: bool = True):
    """Rt from seed 000 eqs 14-16, ``min(kt V (t - tc), mu0 Rn)``, with Rn clipped at zero unless
    ``clipped`` is False (the printed form); ``mu0 Rn`` alone without a touchdown (tc = -inf)."""
    limit = mu0 * (np.maximum(Rn, 0.0) if clipped else Rn)
    if tc == -math.inf:
        return limit
    return np.minimum(kt * speed * (t - tc), limit)


def _integrate(dyn: _Dynamics, p: FootParameters, speed: float, pieces: Sequence[_Piece],
               tcs: Sequence[float | None]) -> tuple[float, float, float]:
    """Time integrals over the pieces: flight time [s], int Rn dt, int Rt dt [N s]; ``tcs``: each
    piece's touchdown time (``kernel.touchdown_times``)."""
    chunk = min(2 * math.pi / dyn.omega, 2 * math.pi / math.sqrt(dyn.w0sq)) / 8
    clipped = p.friction_law == "clipped"
    flight = sum_rn = sum_rt = 0.0
    for piece, tc in zip(pieces, tcs):
        if not piece.contact:
            flight += piece.t1 - piece.t0
            continue
        arc = piece.arc
        cuts = []
        if tc != -math.inf:
            cuts += sign_changes(lambda t, arc=arc, tc=tc: p.kt * speed * (t - tc) - p.mu0 * arc.normal_force(t),
                                 piece.t0, piece.t1, dyn.step)
        if clipped:
            cuts += sign_changes(arc.normal_force, piece.t0, piece.t1, dyn.step)
        edges = [piece.t0, *sorted(cuts), piece.t1]
        for a, b in itertools.pairwise(edges):
            x, w = gauss_nodes(a, b, chunk)
            rn = arc.normal_force(x)
            sum_rn += float(w @ rn)
            sum_rt += float(w @ _tangential(rn, x, tc, p.kt, speed, p.mu0, clipped))
    return flight, sum_rn, sum_rt


# Relative neighbourhood above the onset answered by the contact-only response: there the flight lasts
# < 1e-5 of a period (flight ratio 9.3e-4 % at 1e-8, 3.6e-2 % at 1e-6 above the onset, 3 N) and
# the shooting on a grazing orbit is ill-conditioned in double precision (0.3 s and a wrong
# average at 1e-9 instead); the friction there differs from the contact-only value by < 1e-7.
GRAZING = 1e-8
BALANCE_TOL = 1e-2  # accepted momentum-balance error of a time average (chaotic motion)
MAX_AVERAGE_GROWTH = 16  # a time average runs over at most 16 x march_periods periods
BATCHES = 8  # batch means for the uncertainty of a time average


def steady_state(amplitude: float, *, preload: float = FN, speed: float = SPEED,
                 parameters: FootParameters | None = None, max_subharmonic: int = 8,
                 march_periods: int = 400) -> ContactOrbit:
    """Periodic steady state of one foot (seed 000 eqs 2-17) at amplitude W [m, 0-peak].

    preload : Fn [N]; speed : sliding speed V [m/s] (0: the limit V -> 0+, see the module docstring);
    parameters : FootParameters (defaults: seed 000 appendix).  At or below the onset amplitude
    (``FootParameters.onset_amplitude``) the answer is the contact-only response in closed form (seed
    000 eq. 11, no flight) unless the motion from rest flies off it.  Otherwise the answer is the periodic
    orbit (period k T, k <= ``max_subharmonic``) that the motion from rest reaches (``_search_from_rest``);
    failing one within ``march_periods`` periods, a time average (``periodic = False``) over
    ``march_periods`` further periods, four times as many while its momentum balance is off by more than
    BALANCE_TOL (up to MAX_AVERAGE_GROWTH times).
    """
    p = parameters if parameters is not None else FootParameters()
    W = require("amplitude", amplitude, nonnegative=True)
    Fn = require("preload", preload, nonnegative=True)
    V = require("speed", speed, nonnegative=True)
    if p.total_load(Fn) <= 0:
        raise ContactError(f"preload: the load Fn + m g must be positive, got {p.total_load(Fn):g} N")
    dyn = _Dynamics.build(p, W, Fn)
    T = p.period
    su = max(W, dyn.P / dyn.kn)
    scale = np.array([su, su * dyn.omega])
    last: dict = {}

    def period_map(k, x, sensitivity=True):
        pieces, u, v, Phi = _advance(dyn, 0.0, k * T, float(x[0]), float(x[1]))
        last.update(k=k, x=tuple(x), pieces=pieces)
        return np.array([u, v]), Phi

    with np.errstate(over="ignore", invalid="ignore"):  # the unused sensitivity of a long march
        search = _search_from_rest(dyn, p, W, Fn, period_map, scale, max_subharmonic, march_periods)
    if search is None:  # the contact-only orbit, reached from rest: exact, no event to find
        piece = _Piece(_Arc(dyn, True, 0.0, *p.contact_only_state(W, Fn)), 0.0, T)
        return _orbit(dyn, p, W, Fn, V, [piece], [-math.inf], periods=1, residual=0.0, uncertainty=0.0)
    periods, x, residual = search
    if not periods:
        log.warning("no stable orbit of period up to %d T reached from rest at W = %g m, Fn = %g N; averaging "
                    "over %d periods", max_subharmonic, W, Fn, march_periods)

    def advance(t0, t1):
        if t0 == 0 and last.get("x") == tuple(x) and last["k"] * T == t1:  # the shooting's last period
            return last["pieces"]
        return _advance(dyn, t0, t1, float(x[0]), float(x[1]))[0]

    window = periods or march_periods
    while True:
        with np.errstate(over="ignore", invalid="ignore"):
            pieces, tcs = landed_window(advance, window * T, bool(periods))
        span = pieces[-1].t1 - pieces[0].t0
        _, int_rn, _ = _integrate(dyn, p, V, pieces, tcs)
        balance = abs(int_rn / span / dyn.P - 1)
        if periods or balance <= BALANCE_TOL or window >= MAX_AVERAGE_GROWTH * march_periods:
            break
        window *= 4
    uncertainty = 0.0 if periods else _batch_uncertainty(dyn, p, V, pieces, tcs)
    if not periods and max(balance, uncertainty) > BALANCE_TOL:
        log.warning("time average over %d periods: momentum balance off by %.2g, <Rt> uncertain by %.2g "
                    "(upper 95 %% bound on its standard error, %d batch means)", window, balance, uncertainty, BATCHES)
    return _orbit(dyn, p, W, Fn, V, pieces, tcs, periods=periods, residual=residual, uncertainty=uncertainty)


# The march from rest seeds Newton on k T once it comes back within SEED (scaled) of its state k periods
# before, and again each time that gap has shrunk tenfold; the orbit Newton finds is accepted as the one the
# motion reaches only when it lies within REACHED (scaled) of the marched state: an attracting orbit is approached
# geometrically (|x_j - x*| ~ gap r / (1 - r) for a contraction r per k T; r = 0.82 for the slowest seen,
# 1.5 kHz, dn 20 N s/m, W 1.3 um), so a state whose recurrence gap is 1e-3 lies within ~5e-3 of its attractor.
SEED = 1e-3
REACHED = 1e-2
SAME_STATE = 1e-7  # scaled distance under which two states of an orbit are one (its minimal period)


def _search_from_rest(dyn: _Dynamics, p: FootParameters, W: float, Fn: float, period_map: Callable,
                      scale: np.ndarray, max_period: int,
                      periods: int) -> tuple[int, np.ndarray, float] | None:
    """The steady state that the motion from rest reaches (the plate at rest under its load when the vibration
    starts, as in the seed's simulations; issue 35): None for the contact-only orbit, else (k, x, residual) for a
    stable periodic orbit of minimal period k T through the state x at t = 0, or (0, x, nan) with x a state to
    average from when none is found.

    The march is exact (``_advance``), one period at a time.  Below the onset amplitude the deviation from the
    contact-only orbit is, in contact, a free damped oscillation whose energy never grows: once its amplitude
    sqrt(du^2 + M dv^2 / kn) is below the orbit's margin to lift-off, P/kn (1 - W / onset), without a flight in the
    last period, the foot never lifts again; a motion that touches without progress grazes the contact-only orbit
    (at the onset, where the margin is nil).  Otherwise, once the march recurs after k periods (gap below SEED),
    Newton on k T (``kernel.shoot_periodic``) polishes its state into the orbit; the orbit counts only if it is
    stable and within REACHED of the marched state.  A stable orbit that the motion from rest does not reach (a
    contact-only orbit beside a chattering one below the onset; at 1.3 um above it, 2.04 % flight where the
    motion reaches 75.9 %) is never reported.  A march that does not recur within ``periods`` periods (a slow
    approach) leaves the search to ``kernel.find_orbit`` from the contact-only state or a quasi-static guess.
    """
    onset = p.onset_amplitude(Fn)
    below = onset * (1 + GRAZING) > W
    contact_only = np.array(p.contact_only_state(W, Fn))
    margin = dyn.P / dyn.kn * (1 - W / onset)
    x = np.array([-dyn.P / dyn.kn, 0.0])
    history = [x / scale]
    flew = False
    seeded = math.inf  # the gap at the last Newton attempt
    for j in range(periods):
        if below and not flew:
            du, dv = x - contact_only
            if math.sqrt(du * du + dyn.M * dv * dv / dyn.kn) < margin:
                return None
        try:
            pieces, u, v, _ = _advance(dyn, j * p.period, (j + 1) * p.period, float(x[0]), float(x[1]))
        except ContactError:
            if below:  # touching without progress: grazing the contact-only orbit at its onset, its limit
                return None
            raise
        flew = any(not q.contact for q in pieces)
        x = np.array([u, v])
        history.append(x / scale)
        if below and not flew:  # in contact all period long: the margin decides
            continue
        gaps = [float(np.linalg.norm(history[-1] - history[-1 - k])) for k in range(1, min(max_period, j + 1) + 1)]
        k = next((i + 1 for i, g in enumerate(gaps) if g < SEED), 0)
        if not k or gaps[k - 1] > 0.1 * seeded:
            continue
        if below and np.linalg.norm((x - contact_only) / scale) < REACHED:
            return None  # settling on the contact-only orbit, or within GRAZING above the onset on its grazing limit
        seeded = gaps[k - 1]
        sol = shoot_periodic(lambda y, k=k: period_map(k, y), x, scale, max_iter=12)
        if sol.converged and sol.stable and np.linalg.norm((sol.state - x) / scale) < REACHED:
            return _minimal_period(period_map, sol.state, k, scale), sol.state, sol.residual
    if below and not flew:
        return None
    # no recurrence within the march (a slow approach from rest: kn 1e4-1e6 N/m, W 0.1 mm, where the plate is thrown
    # high): the orbit search from the contact-only state near the onset or a quasi-static guess (``kernel.find_orbit``:
    # Newton on k T, then a march and its recurrences), else an average
    guess = contact_only if 1.01 * onset > W else np.array([quasi_static_offset(W, dyn.P, dyn.kn), 0.0])
    search = find_orbit(period_map, guess, scale, max_period=max_period, march_periods=periods)
    return search.period, search.state, search.shooting.residual if search.period else math.nan


def _minimal_period(period_map: Callable, x: np.ndarray, k: int, scale: np.ndarray) -> int:
    """The smallest j <= k after which the orbit through x comes back to x (within SAME_STATE, scaled)."""
    y = x
    for j in range(1, k):
        y = period_map(1, y, False)[0]
        if np.linalg.norm((y - x) / scale) < SAME_STATE:
            return j
    return k


def _orbit(dyn: _Dynamics, p: FootParameters, W: float, Fn: float, V: float, pieces: list, tcs: list, *,
           periods: int, residual: float, uncertainty: float) -> ContactOrbit:
    flight, int_rn, int_rt = _integrate(dyn, p, V, pieces, tcs)
    span = pieces[-1].t1 - pieces[0].t0
    touchdowns = sorted({tc for q, tc in zip(pieces, tcs) if q.contact and tc == q.t0})
    n_periods = span / p.period
    return ContactOrbit(
        amplitude=W, preload=Fn, speed=V, parameters=p,
        flight_ratio=100.0 * flight / span, normal_mean=int_rn / span, friction_mean=int_rt / span + 0.0,
        contacts_per_period=len(touchdowns) / (periods or n_periods), periodic=bool(periods), residual=residual,
        periods=round(n_periods), pieces=tuple(pieces), touchdowns=tuple(touchdowns),
        piece_touchdowns=tuple(tcs), friction_uncertainty=uncertainty)


def _batch_uncertainty(dyn: _Dynamics, p: FootParameters, speed: float, pieces: Sequence[_Piece],
                       tcs: Sequence[float | None]) -> float:
    """Relative uncertainty of a time average of Rt by batch means (an upper 95 % bound on its standard error):
    the window cut into BATCHES consecutive stretches of pieces (``kernel.batch_ratio``)."""
    starts = np.array([q.t0 for q in pieces])
    bounds = np.searchsorted(starts, np.linspace(starts[0], pieces[-1].t1, BATCHES + 1)[1:-1])
    sums, spans = [], []
    for group in np.split(np.arange(len(pieces)), bounds):
        if len(group) == 0:
            continue
        _, _, int_rt = _integrate(dyn, p, speed, [pieces[i] for i in group], [tcs[i] for i in group])
        sums.append(int_rt)
        spans.append(pieces[group[-1]].t1 - pieces[group[0]].t0)
    mean, error = batch_ratio(np.array(sums), np.array(spans), batches=len(sums))
    return 0.0 if mean == 0 or not math.isfinite(error) else error / abs(mean)


# ----------------------------------------------------------------------------------------------
# Curves
# ----------------------------------------------------------------------------------------------



@dataclass(frozen=True, eq=False)
class ContactCurve:
    """Steady-state friction of the plate against vibration amplitude (seed 000 Fig. 15, seed 001 Figs 6, 9, 10).

    amplitude : W at the feet, 0-peak [m]; voltage : drive voltage [V] when the curve was asked in
    volts, else None; preload : Fn [N]; speed : sliding speed V [m/s]; parameters : the model's;
    flight_ratio : beta [%] (seed 000 eq. 13); normal_mean : <Rn> per foot [N];
    friction_force : friction felt by the user, n <Rt> [N]; contacts_per_period : touchdowns per
    drive period; periodic : exact periodic orbit (else a time average, see ``steady_state``).
    """

    amplitude: np.ndarray
    voltage: np.ndarray | None
    preload: float
    speed: float
    parameters: FootParameters
    flight_ratio: np.ndarray
    normal_mean: np.ndarray
    friction_force: np.ndarray
    contacts_per_period: np.ndarray
    periodic: np.ndarray

    @property
    def static_friction(self) -> float:
        """mu0 (Fn + m g) [N]: the friction without vibration."""
        return self.parameters.mu0 * self.parameters.total_load(self.preload)

    @property
    def friction_coefficient(self) -> np.ndarray:
        """Apparent friction coefficient n <Rt> / (Fn + m g)."""
        return self.friction_force / self.parameters.total_load(self.preload)

    @property
    def friction_reduction(self) -> np.ndarray:
        """1 - n <Rt> / (mu0 (Fn + m g)): the fraction of friction removed by the vibration."""
        return 1.0 - self.friction_force / self.static_friction

    def to_json(self) -> dict:
        """Plain dict of lists, SI units in the key names."""
        p = self.parameters
        return {
            "preload_n": self.preload, "speed_m_s": self.speed,
            "parameters": {"kn_n_m": p.kn, "dn_n_s_m": p.dn, "mass_kg": p.mass, "n": p.n,
                           "g_m_s2": p.g, "frequency_hz": p.frequency, "mu0": p.mu0, "kt_n_m": p.kt},
            "amplitude_m": self.amplitude.tolist(),
            "voltage_v": None if self.voltage is None else self.voltage.tolist(),
            "flight_ratio_percent": self.flight_ratio.tolist(),
            "normal_mean_n": self.normal_mean.tolist(),
            "friction_force_n": self.friction_force.tolist(),
            "friction_coefficient": self.friction_coefficient.tolist(),
            "friction_reduction": self.friction_reduction.tolist(),
            "contacts_per_period": self.contacts_per_period.tolist(),
            "periodic": self.periodic.tolist(),
        }



def amplitudes_from_voltage(voltage, amplitude_per_volt: float | Callable[[float], float],
                            frequency: float) -> np.ndarray:
    """W = volts x amplitude per volt [m]; the latter a number [m/V] or a callable of the drive
    frequency [Hz] (for instance a reduced modal model's receptance at the feet)."""
    volts = values("voltage", voltage)
    apv = amplitude_per_volt(frequency) if callable(amplitude_per_volt) else amplitude_per_volt
    return volts * require("amplitude_per_volt", apv, nonnegative=True)


def simulate_contact(amplitude=None, *, voltage=None,
                     amplitude_per_volt: float | Callable[[float], float] | None = None,
                     preload: float = FN, speed: float = SPEED, substrate: str | None = None,
                     parameters: FootParameters | None = None, progress: bool = False) -> ContactCurve:
    """Friction, flight ratio and mean normal force against vibration amplitude (seed 000 eqs 2-17).

    Give either ``amplitude`` (W at the feet, 0-peak [m], a number or a sequence) or ``voltage`` [V]
    with ``amplitude_per_volt`` [m/V] (a number or a callable of the drive frequency [Hz]).
    preload : Fn [N]; speed : sliding speed V [m/s]; substrate : ``steel`` or ``glass`` sets mu0
    (seeds 000, 001); parameters : FootParameters (defaults: seed 000 appendix, identified kt);
    progress : show a tqdm bar.
    """
    p = parameters if parameters is not None else FootParameters()
    if substrate is not None:
        p = p.on(substrate)
    if (amplitude is None) == (voltage is None):
        raise ContactError("amplitude: give either amplitude [m] or voltage [V] (with amplitude_per_volt)")
    volts = None
    if voltage is not None:
        if amplitude_per_volt is None:
            raise ContactError("amplitude_per_volt: needed to turn voltage into amplitude")
        volts = values("voltage", voltage)
        W = amplitudes_from_voltage(volts, amplitude_per_volt, p.frequency)
    else:
        W = values("amplitude", amplitude)
    require("preload", preload, nonnegative=True)
    require("speed", speed, nonnegative=True)
    items = W
    if progress:
        from tqdm import tqdm

        items = tqdm(W, desc="friction", unit="amplitude", leave=False)
    orbits = [steady_state(w, preload=preload, speed=speed, parameters=p) for w in items]
    return ContactCurve(
        amplitude=W, voltage=volts, preload=float(preload), speed=float(speed), parameters=p,
        flight_ratio=np.array([o.flight_ratio for o in orbits]),
        normal_mean=np.array([o.normal_mean for o in orbits]),
        friction_force=np.array([o.friction_force for o in orbits]),
        contacts_per_period=np.array([o.contacts_per_period for o in orbits]),
        periodic=np.array([o.periodic for o in orbits]))


# ----------------------------------------------------------------------------------------------
# Brute-force reference in the seed's manner
# ----------------------------------------------------------------------------------------------
