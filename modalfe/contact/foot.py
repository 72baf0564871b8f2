"""Foot normal dynamics, flight ratio and Coulomb-Orowan friction of a plate standing on vibrating feet.

Model (seed 000, section 4.3; seed 001, section 5)
---------------------------------------------------
The plate (mass ``m``) stands on ``n`` massless feet of stiffness ``kn`` and free height ``h``, with a
damper ``dn`` on the plate's normal velocity, under a constant preload ``Fn``.  The working mode moves
the top of each foot by ``w_A(t) = W sin(omega t)`` (seed 000 eq. 1).  One foot carries a share
``m/n`` of the plate, so per foot, with ``z_G`` the height of the plate at rest and ``z_A`` the height of
the foot's top:

    contact (z_A <= h, eqs 6, 8, 11):  (m/n) z_G'' + dn z_G' + kn z_A = -Fn/n - (m/n) g + kn h
    flight  (z_A >  h, eqs 5, 9, 12):  (m/n) z_G'' = -Fn/n - (m/n) g
    normal reaction (eqs 3, 4):        Rn = kn (h - z_A) - dn z_G'  in contact,  Rn = 0 in flight

Reading of the sign of ``w_A``.  The seed prints ``z_A = z_G - w_A`` (eq. 7) but also writes the contact
test as ``z_G + w_A <= h`` (eqs 8, 9) and turns eq. 2, ``(m/n) z_A'' = (m/n) w_A'' - Fn/n - (m/n) g + Rn``,
into eq. 10, ``(m/n) z_G'' = -Fn/n - (m/n) g + Rn``.  Eq. 2 gives eq. 10 only with ``z_A = z_G + w_A``
(with the minus sign it gives ``z_G'' = 2 w_A'' + ...``), so eqs 2 and 8-12 agree with each other and
eq. 7 is the misprint: this module uses ``z_A = z_G + w_A``.  Flipping the sign of ``w_A`` only shifts the
drive by half a period, so no time-averaged output depends on this choice; the trajectories do.

The solver works in ``u = z_G - h`` (so the appendix's ``h = 4 mm`` drops out) and ``v = z_G'``.
Contact is decided by geometry, as printed (eqs 5, 6): ``Rn`` may dip slightly below zero just before
separation, because the damper acts on ``z_G'`` and not on the foot's compression rate (at the appendix
values by at most ~2 % of its peak, for < 0.3 % of a period, ~1e-4 of the impulse).  Averages use ``Rn``
as printed.

Flight ratio, seed 000 eq. 13: ``beta = 100 (t_s - t_c) / T`` generalised to the total flight time per
period when the foot lands several times a period ("chattering").

Tangential force, Coulomb-Orowan (seed 000 eqs 14-17; seed 001 eqs 1-4, 8): the foot slides at the
speed ``V`` imposed by the user; the tangential displacement since the last touchdown is
``delta = V (t - t_c)``; ``delta_crit = mu0 Rn / kt``; ``mu = mu0 delta / delta_crit`` while
``delta < delta_crit``, else ``mu0``; ``Rt = mu Rn``.  Written out, ``Rt = min(kt V (t - t_c), mu0 Rn)``
during contact and 0 in flight.  Without flight (contact since ``t_c = -inf``) ``Rt = mu0 Rn``.
The friction force felt by the user is ``n <Rt>``.

Method
------
Both phases are linear with closed-form solutions: in contact a damped oscillator driven at ``omega``
(steady sinusoid plus a homogeneous part propagated by the 2x2 exponential of the phase's state
matrix), in flight a parabola.  Transitions are the events ``z_A = h``: the gap is sampled on a grid
finer than the fastest time scale (64 points per drive or contact-oscillation period), a local extremum
between samples that reaches across zero is found through the gap rate (so short grazing contacts
are not missed), and each root is polished by Newton's method inside its bracket.  One period of this
event-driven exact solution is the period map ``(u, v)(0) -> (u, v)(T)``; the periodic steady state is
its fixed point, found by Newton's method on the map (shooting) from a quasi-static first guess.  The
map's Jacobian (monodromy matrix) is exact: the arcs' transition matrices chained with the saltation
matrix of each switch.  Its eigenvalues (Floquet multipliers) tell whether the orbit is the
attractor; if it is not, orbits of period k T (k <= 8) are shot from a state reached by marching in
time, and failing those the solver averages over many periods with the same exact solution
(``periodic = False`` in the result).  Period averages of ``Rn`` and ``Rt`` are Gauss-Legendre
integrals over the contact arcs, split where ``kt V (t - t_c) = mu0 Rn`` so every piece is smooth.

A brute-force reference in the seed's manner (``brute_force_steady_state``: scipy ``solve_ivp`` with
Bogacki-Shampine RK23, max step 1e-7 s, terminal events at the switches, run until the period
averages stop changing) is provided for the benchmark ``studies/benchmark_contact.py``.
"""

from __future__ import annotations

import itertools
import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields, replace
from functools import cached_property

import numpy as np
from scipy.optimize import brentq

from modalfe.errors import ContactError

log = logging.getLogger(__name__)

# Seed 000, appendix (also seed 000 section 4.3.1.2, numerical example): the foot model's parameters.
KN = 9.7e6  # N/m, normal stiffness of one foot
DN = 200.0  # N s/m, damper on the plate's normal velocity
FN = 10.0  # N, preload
MASS = 0.0723  # kg, vibrating plate
N_FEET = 3  # feet sharing the load (appendix; the device has four)
G = 9.81  # m/s^2
# Seed 001 section 2: working frequency (measured resonance); seed 000 Fig. 12 uses 35 kHz.
FREQUENCY = 40.7e3  # Hz
# Friction coefficients: steel substrate, seed 000 section 6 / seed 001 section 7; glass, seed 001 section 5.
SUBSTRATES = {"steel": 0.2, "glass": 0.08}
# Tangential contact stiffness of one foot: not given by the seeds; identified from seed 001's
# measured reduction (0.71 N -> 0.274 N at 3 N preload, 1 cm/s, steel) by studies/identify_kt.py.
KT = 5.44e6  # N/m (fit at an assumed 0.65 um 0-peak; see the study for the sensitivity)
# Seed 001 section 7: the user's sliding speed of the measured reduction.
SPEED = 0.01  # m/s

SAMPLES_PER_PERIOD = 64  # event search grid: points per drive period or per contact oscillation
GAUSS_ORDER = 12  # Gauss-Legendre nodes per quadrature chunk
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(GAUSS_ORDER)


# ----------------------------------------------------------------------------------------------
# Event-driven tools, shared with modalfe.contact.finger
# ----------------------------------------------------------------------------------------------


def _grid(t0: float, t1: float, step: float) -> np.ndarray:
    return np.linspace(t0, t1, max(2, math.ceil((t1 - t0) / step) + 1))


def _root(fun: Callable[[float], float], a: float, b: float) -> float:
    """Brent's method to rounding accuracy on a bracket (the end nearer zero if rounding undid the bracket)."""
    fa, fb = fun(a), fun(b)
    if fa * fb > 0:
        return a if abs(fa) < abs(fb) else b
    return brentq(fun, a, b, xtol=4 * np.finfo(float).eps * max(abs(a), abs(b), 1e-300))


def _newton_root(fr: Callable, a: float, b: float) -> float:
    """Zero of f on [a, b] with f(a) <= 0 < f(b); ``fr(t) -> (f, f')``: Newton kept inside the bracket."""
    fa, fb = fr(a)[0], fr(b)[0]
    x = a - fa * (b - a) / (fb - fa) if fb > fa else 0.5 * (a + b)
    tol = 4 * np.finfo(float).eps * max(abs(a), abs(b))
    for _ in range(100):
        f, d = fr(x)
        if f > 0:
            b = x
        else:
            a = x
        xn = x - f / d if d != 0 else a - 1.0
        if not a <= xn <= b:
            xn = 0.5 * (a + b)
        if abs(xn - x) <= tol or b - a <= tol:
            return float(xn)
        x = xn
    return float(x)


def first_crossing(fun_rate: Callable, t0: float, t1: float, step: float, *, upward: bool) -> float | None:
    """First time in (t0, t1] where a function crosses zero upward (or downward), else None.

    ``fun_rate(t) -> (f, df/dt)`` takes arrays and floats.  ``f`` is on the near side of zero at ``t0``
    up to rounding (an arc starts at the previous event).  Sign changes are found on a grid of spacing
    ``step``; a local extremum between two samples that reaches across zero (a grazing arc shorter than
    ``step``) is found through the rate.  Roots are polished by Newton's method inside the bracket.
    Returns ``t0`` when the arc leaves at once (it starts moving towards its exit).  A start where
    both the function and its rate vanish to rounding is tangent: the samples after it decide.
    """
    sign = 1.0 if upward else -1.0

    def fr(t):
        f, d = fun_rate(t)
        return sign * f, sign * d

    def d(t):
        return fr(t)[1]

    t = _grid(t0, t1, step)
    fv, dv = fr(t)
    if abs(fv[0]) <= 1e-9 * np.max(np.abs(fv)) and abs(dv[0]) <= 1e-9 * np.max(np.abs(dv)):
        fv[0] = dv[0] = 0.0  # a tangent start (a Kelvin-Voigt layer's separation): the grid decides
    elif (fv[0] >= 0 and dv[0] > 0) or (fv[0] > 0 and dv[0] >= 0):
        return t0
    after = np.flatnonzero(fv[1:] > 0) + 1
    last = after[0] if after.size else len(t) - 1

    def low(i, b):
        # a point of [t_i, b) where f <= 0 after the start; at t0, f is zero or a rounding residue
        if i > 0 or fv[0] < 0:
            return t[i]
        tm = _root(d, t0, b) if d(b) > 0 else b
        return tm if fr(tm)[0] < 0 else None

    for i in np.flatnonzero((dv[:last] > 0) & (dv[1 : last + 1] < 0)):
        tm = _root(d, t[i], t[i + 1])
        if fr(tm)[0] > 0:
            a = low(i, tm)
            return t0 if a is None else _newton_root(fr, a, tm)
    if not after.size:
        return None
    a = low(last - 1, t[last])
    return t0 if a is None else _newton_root(fr, a, t[last])


def sign_changes(fun: Callable, t0: float, t1: float, step: float) -> list[float]:
    """All sign changes of ``fun`` in (t0, t1) seen on a grid of spacing ``step``, polished by Brent."""
    t = _grid(t0, t1, step)
    fv = fun(t)
    idx = np.flatnonzero(np.sign(fv[:-1]) * np.sign(fv[1:]) < 0)
    return [_root(fun, t[i], t[i + 1]) for i in idx]


def gauss_nodes(a: float, b: float, chunk: float) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [a, b], split into chunks no longer than ``chunk``."""
    if b <= a:
        return np.empty(0), np.empty(0)
    edges = np.linspace(a, b, max(1, math.ceil((b - a) / chunk)) + 1)
    half = 0.5 * np.diff(edges)[:, None]
    mid = 0.5 * (edges[:-1] + edges[1:])[:, None]
    return (mid + half * _GAUSS_X).ravel(), (half * _GAUSS_W).ravel()


@dataclass(frozen=True)
class PeriodicState:
    """Fixed point of a period map found by Newton shooting.

    state : the state at the start of the period; iterations : Newton steps taken;
    residual : scaled |P(x) - x| at the end; multipliers : Floquet multipliers (eigenvalues of dP/dx);
    converged : residual below tolerance.
    """

    state: np.ndarray
    iterations: int
    residual: float
    multipliers: np.ndarray
    converged: bool

    @property
    def stable(self) -> bool:
        """Every Floquet multiplier inside the unit circle (with a margin for rounding)."""
        return bool(np.all(np.abs(self.multipliers) < 1 + 1e-6))


def shoot_periodic(period_map: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], x0: np.ndarray,
                   scale: np.ndarray, *, tol: float = 1e-11, max_iter: int = 40) -> PeriodicState:
    """Periodic steady state x = P(x) by Newton's method (shooting).

    ``period_map(x) -> (P(x), dP/dx)``: the state one period later and the monodromy matrix.
    Works in the scaled variables ``x / scale``; ``tol`` bounds the scaled residual.  A Newton step
    that does not reduce the residual is halved up to six times, then replaced by one step of the map
    itself (time marching), which the physical attractor contracts.
    """
    scale = np.asarray(scale, float)
    n = len(scale)

    def residual(y):
        xT, Phi = period_map(y * scale)
        return xT / scale - y, Phi * scale[None, :] / scale[:, None] - np.eye(n)

    y = np.asarray(x0, float) / scale
    r, J = residual(y)
    steps = 0
    while np.linalg.norm(r) >= tol and steps < max_iter:
        steps += 1
        try:
            dy = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            dy = r
        norm = np.linalg.norm(r)
        for _ in range(7):
            r_new, J_new = residual(y + dy)
            if np.linalg.norm(r_new) < (1 - 1e-4) * norm:
                y, r, J = y + dy, r_new, J_new
                break
            dy = dy / 2
        else:
            y = y + r
            r, J = residual(y)
    res = float(np.linalg.norm(r))
    return PeriodicState(y * scale, steps, res, np.linalg.eigvals(J + np.eye(n)), res < tol)


# ----------------------------------------------------------------------------------------------
# Parameters and validation
# ----------------------------------------------------------------------------------------------


def replaced(params, kind: str, changes: dict):
    """A validated copy of a parameter dataclass with ``changes``; unknown names raise ContactError."""
    known = {f.name for f in fields(params)}
    for key in changes:
        if key not in known:
            raise ContactError(f"{key}: not a {kind} parameter (known: {', '.join(sorted(known))})")
    return replace(params, **changes)


def require(name: str, value, *, positive: bool = False, nonnegative: bool = False) -> float:
    """``value`` as a finite float, or a one-line ContactError naming ``name``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ContactError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ContactError(f"{name}: must be finite, got {x}")
    if positive and x <= 0:
        raise ContactError(f"{name}: must be positive, got {x:g}")
    if nonnegative and x < 0:
        raise ContactError(f"{name}: must be >= 0, got {x:g}")
    return x


@dataclass(frozen=True)
class FootParameters:
    """Foot contact model parameters (defaults: seed 000 appendix; kt identified, see module docstring).

    kn : normal stiffness of one foot [N/m]; dn : damper on the plate's normal velocity [N s/m];
    mass : vibrating plate, m [kg]; n : feet sharing the load;
    g : gravity [m/s^2]; frequency : drive frequency [Hz]; mu0 : maximum (static) friction
    coefficient; kt : tangential contact stiffness of one foot [N/m].
    """

    kn: float = KN
    dn: float = DN
    mass: float = MASS
    n: int = N_FEET
    g: float = G
    frequency: float = FREQUENCY
    mu0: float = SUBSTRATES["steel"]
    kt: float = KT

    def __post_init__(self):
        for name in ("kn", "mass", "frequency", "kt"):
            require(name, getattr(self, name), positive=True)
        for name in ("dn", "g", "mu0"):
            require(name, getattr(self, name), nonnegative=True)
        n = require("n", self.n, positive=True) if not isinstance(self.n, bool) else 0.5
        if n != int(n):
            raise ContactError(f"n: number of feet must be a positive integer, got {self.n!r}")
        object.__setattr__(self, "n", int(n))

    def on(self, substrate: str) -> FootParameters:
        """A copy with ``mu0`` of a named substrate (``steel`` 0.2, ``glass`` 0.08; seeds 000, 001)."""
        if substrate not in SUBSTRATES:
            raise ContactError(f"substrate: expected one of {sorted(SUBSTRATES)}, got {substrate!r}")
        return replace(self, mu0=SUBSTRATES[substrate])

    def with_(self, **changes) -> FootParameters:
        """A copy with some fields changed (validated); unknown names raise ContactError."""
        return replaced(self, "foot", changes)

    @property
    def omega(self) -> float:
        """Drive angular frequency [rad/s]."""
        return 2 * math.pi * self.frequency

    @property
    def period(self) -> float:
        """Drive period T [s]."""
        return 1.0 / self.frequency

    def total_load(self, preload: float) -> float:
        """Fn + m g [N], the load the feet carry on average (seed 000, after eq. 17)."""
        return preload + self.mass * self.g

    def onset_amplitude(self, preload: float) -> float:
        """Smallest amplitude W [m] at which a foot leaves the ground (contact-only steady response).

        Without flight the plate's response is linear: ``z_A - h = -P/kn + Im((W + X) e^{i omega t})``
        with ``X = -kn W / (kn - M omega^2 + i dn omega)``, so the foot lifts off once ``|W + X| = P/kn``.
        """
        M = self.mass / self.n
        P = self.total_load(preload) / self.n
        w = self.omega
        gain = abs((-M * w * w + 1j * self.dn * w) / (self.kn - M * w * w + 1j * self.dn * w))
        return P / self.kn / gain


# ----------------------------------------------------------------------------------------------
# Closed-form arcs
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Dynamics:
    """Per-foot constants of one operating point, in u = z_G - h and v = z_G'."""

    M: float  # m/n [kg]
    P: float  # (Fn + m g)/n [N]
    kn: float
    dn: float
    omega: float
    W: float
    Xr: float  # steady contact response to the drive, X = Xr + i Xi
    Xi: float
    alpha: float  # -dn / (2M)
    beta: float  # sqrt(|w0^2 - alpha^2|)
    w0sq: float  # kn / M
    overdamped: bool

    @classmethod
    def build(cls, p: FootParameters, W: float, preload: float) -> _Dynamics:
        M = p.mass / p.n
        P = p.total_load(preload) / p.n
        w = p.omega
        X = -p.kn * W / (p.kn - M * w * w + 1j * p.dn * w)
        alpha = -p.dn / (2 * M)
        w0sq = p.kn / M
        disc = w0sq - alpha * alpha
        return cls(M, P, p.kn, p.dn, w, W, X.real, X.imag, alpha, math.sqrt(abs(disc)), w0sq, disc < 0)

    @property
    def step(self) -> float:
        """Event search grid spacing [s]: the shorter of the drive and the contact oscillation periods."""
        return 2 * math.pi / max(self.omega, math.sqrt(self.w0sq)) / SAMPLES_PER_PERIOD

    def contact_particular(self, s, c):
        """Steady sinusoidal solution (u_p, v_p) of seed 000 eq. 11, given sin and cos of omega t."""
        return -self.P / self.kn + self.Xr * s + self.Xi * c, self.omega * (self.Xr * c - self.Xi * s)

    def kernels(self, tau, f=np):
        """e^{alpha tau} cosh(s tau) and e^{alpha tau} sinh(s tau)/s, s^2 = alpha^2 - w0^2; ``f`` is
        numpy for arrays or math for one time (several times faster on a float)."""
        if self.overdamped:
            g = self.beta
            ep = f.exp((self.alpha + g) * tau)
            return 0.5 * (ep + f.exp((self.alpha - g) * tau)), -ep * f.expm1(-2 * g * tau) / (2 * g)
        e = f.exp(self.alpha * tau)
        if self.beta == 0:  # critically damped
            return e, e * tau
        return e * f.cos(self.beta * tau), e * f.sin(self.beta * tau) / self.beta


@dataclass(frozen=True)
class _Arc:
    """One contact or flight arc starting at t0 from (u0, v0); evaluates anywhere on the arc."""

    dyn: _Dynamics
    contact: bool
    t0: float
    u0: float
    v0: float

    def _evaluate(self, t):
        """u, v (seed 000 eq. 11 in contact, eq. 12 in flight, closed form) and sin, cos(omega t)."""
        f = math if isinstance(t, float) else np
        t = t if f is math else np.asarray(t, float)
        d = self.dyn
        sn, cs = f.sin(d.omega * t), f.cos(d.omega * t)
        tau = t - self.t0
        if not self.contact:
            a = d.P / d.M
            return self.u0 + self.v0 * tau - 0.5 * a * tau * tau, self.v0 - a * tau, sn, cs
        y0, y1 = self._homogeneous0
        c, s = d.kernels(tau, f)
        up, vp = d.contact_particular(sn, cs)
        return (up + (c - d.alpha * s) * y0 + s * y1, vp - d.w0sq * s * y0 + (c + d.alpha * s) * y1, sn, cs)

    def state(self, t):
        """(u, v) = (z_G - h, z_G') at t."""
        return self._evaluate(t)[:2]

    @cached_property
    def _homogeneous0(self) -> tuple[float, float]:
        up0, vp0 = self.dyn.contact_particular(math.sin(self.dyn.omega * self.t0), math.cos(self.dyn.omega * self.t0))
        return self.u0 - up0, self.v0 - vp0

    def gap_and_rate(self, t):
        """z_A - h = z_G + w_A - h (contact when <= 0, seed 000 eqs 1, 8, 9) and its rate."""
        u, v, sn, cs = self._evaluate(t)
        W = self.dyn.W
        return u + W * sn, v + W * self.dyn.omega * cs

    def gap(self, t):
        return self.gap_and_rate(t)[0]

    def normal_force(self, t):
        """Rn = kn (h - z_A) - dn z_G' in contact (seed 000 eq. 3), 0 in flight (eq. 4)."""
        if not self.contact:
            return np.zeros_like(np.asarray(t, float))
        u, v, sn, _ = self._evaluate(t)
        return -self.dyn.kn * (u + self.dyn.W * sn) - self.dyn.dn * v

    def transition(self, t: float) -> np.ndarray:
        """d(u, v)(t) / d(u, v)(t0): the 2x2 state transition matrix of the arc."""
        tau = t - self.t0
        if not self.contact:
            return np.array([[1.0, tau], [0.0, 1.0]])
        d = self.dyn
        c, s = d.kernels(tau, math)
        return np.array([[c - d.alpha * s, s], [-d.w0sq * s, c + d.alpha * s]])


@dataclass(frozen=True)
class _Piece:
    arc: _Arc
    t0: float
    t1: float

    @property
    def contact(self) -> bool:
        return self.arc.contact


_MAX_EVENTS_PER_PERIOD = 10_000


def _advance(dyn: _Dynamics, t0: float, t1: float, u: float, v: float, *,
             contact: bool | None = None) -> tuple[list[_Piece], float, float, np.ndarray]:
    """Exact event-driven solution on [t0, t1]: the arcs, the final (u, v) and d(u, v)(t1)/d(u, v)(t0).

    The sensitivity chains the arcs' transition matrices with the saltation matrix of each switch,
    ``S = I + (f_after - f_before) (dh/dx)^T / (dh/dt along the flow)`` for the gap ``h = z_A - h``; the
    acceleration jumps by ``Rn/M = -dn z_G'/M`` at a switch (the damper force, eq. 3 at zero gap).
    """
    if contact is None:
        gap, rate = (float(x) for x in _Arc(dyn, True, t0, u, v).gap_and_rate(t0))
        contact = gap < 0 or (gap == 0 and rate <= 0)
    pieces: list[_Piece] = []
    t = t0
    Phi = np.eye(2)
    horizon = 2 * math.pi / dyn.omega
    limit = _MAX_EVENTS_PER_PERIOD * max(1, round((t1 - t0) / horizon))
    while True:
        arc = _Arc(dyn, contact, t, u, v)
        a = t
        while True:  # search one drive period at a time
            b = min(a + horizon, t1)
            te = first_crossing(arc.gap_and_rate, a, b, dyn.step, upward=contact)
            if te is not None or b >= t1:
                break
            a = b
        end = t1 if te is None else te
        pieces.append(_Piece(arc, t, end))
        Phi = arc.transition(end) @ Phi
        u, v, _, cs = arc._evaluate(float(end))
        if te is None:
            return pieces, u, v, Phi
        jump = (-1.0 if contact else 1.0) * (-dyn.dn * v) / dyn.M  # a_after - a_before
        rate = v + dyn.W * dyn.omega * cs  # gap rate
        if rate != 0:
            Phi = np.array([[1.0, 0.0], [jump / rate, 1.0]]) @ Phi
        t, contact = te, not contact
        if len(pieces) > limit:
            raise ContactError("contact events: no progress (more than "
                               f"{_MAX_EVENTS_PER_PERIOD} switches per period); check kn, dn and frequency")


# ----------------------------------------------------------------------------------------------
# Steady state
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class ContactOrbit:
    """Steady state of one foot at one amplitude, preload and speed.

    amplitude : W, 0-peak [m]; preload : Fn [N]; speed : V [m/s];
    flight_ratio : beta, flight time per period [%] (seed 000 eq. 13);
    normal_mean : <Rn> per foot [N]; friction_mean : <Rt> per foot [N] (seed 001 eq. 8);
    contacts_per_period : touchdowns per drive period (0 in permanent contact);
    periodic : True for an exact periodic orbit (shooting) of ``periods`` drive periods (1, or k for a
    subharmonic orbit), False for a time average over ``periods`` periods; residual : scaled shooting
    residual.  ``balance_error`` states how far a time average is from converged, and
    ``friction_uncertainty`` the relative standard error of its <Rt> (batch means; 0 on an orbit).
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

    def normal_force(self, t) -> np.ndarray:
        """Rn(t) per foot [N] (seed 000 eqs 3, 4) on the steady state."""
        tw, idx = self._locate(t)
        out = np.zeros_like(tw)
        for i in np.unique(idx):
            m = idx == i
            out[m] = self.pieces[i].arc.normal_force(tw[m])
        return out

    def friction(self, t) -> np.ndarray:
        """Rt(t) per foot [N], Coulomb-Orowan (seed 000 eqs 14-17) on the steady state."""
        tw, idx = self._locate(t)
        out = np.zeros_like(tw)
        p = self.parameters
        for i in np.unique(idx):
            m = idx == i
            piece = self.pieces[i]
            out[m] = _tangential(piece.arc.normal_force(tw[m]), tw[m], self._touchdown(piece), p.kt, self.speed,
                                 p.mu0) if piece.arc.contact else 0.0
        return out

    def gap(self, t) -> np.ndarray:
        """z_A - h per foot [m]: negative in contact."""
        tw, idx = self._locate(t)
        out = np.empty_like(tw)
        for i in np.unique(idx):
            m = idx == i
            out[m] = self.pieces[i].arc.gap(tw[m])
        return out

    def _touchdown(self, piece: _Piece) -> float:
        return piece.arc.t0 if piece.arc.t0 in self.touchdowns else -math.inf


def _tangential(Rn, t, tc: float, kt: float, speed: float, mu0: float):
    """Rt = mu(t) Rn with mu from seed 000 eqs 14-16: min(kt V (t - tc), mu0 Rn)."""
    if tc == -math.inf:
        return mu0 * Rn
    return np.minimum(kt * speed * (t - tc), mu0 * Rn)


def _quasi_static_offset(W: float, P: float, kn: float) -> float:
    """u = z_G - h of a plate held still whose mean foot force kn <(-u - W sin)^+> equals P."""
    if P / kn >= W:
        return -P / kn

    def mean(a):  # <(a - sin theta)^+> over theta, |a| <= 1
        return (a * (math.pi + 2 * math.asin(a)) + 2 * math.sqrt(1 - a * a)) / (2 * math.pi)

    a = brentq(lambda a: kn * W * mean(a) - P, -1.0, 1.0, xtol=1e-15)
    return -a * W


def _integrate(dyn: _Dynamics, p: FootParameters, speed: float, pieces: Sequence[_Piece],
               touchdowns: set[float]) -> tuple[float, float, float]:
    """Time integrals over the pieces: flight time [s], int Rn dt, int Rt dt [N s]."""
    chunk = min(2 * math.pi / dyn.omega, 2 * math.pi / math.sqrt(dyn.w0sq)) / 8
    flight = sum_rn = sum_rt = 0.0
    for piece in pieces:
        if not piece.contact:
            flight += piece.t1 - piece.t0
            continue
        tc = piece.arc.t0 if piece.arc.t0 in touchdowns else -math.inf
        arc = piece.arc
        if tc == -math.inf:
            cuts = []
        else:
            cuts = sign_changes(lambda t, arc=arc, tc=tc: p.kt * speed * (t - tc) - p.mu0 * arc.normal_force(t),
                                piece.t0, piece.t1, dyn.step)
        edges = [piece.t0, *cuts, piece.t1]
        for a, b in itertools.pairwise(edges):
            x, w = gauss_nodes(a, b, chunk)
            rn = arc.normal_force(x)
            sum_rn += float(w @ rn)
            sum_rt += float(w @ _tangential(rn, x, tc, p.kt, speed, p.mu0))
    return flight, sum_rn, sum_rt


def find_orbit(period_map: Callable[[int, np.ndarray], tuple[np.ndarray, np.ndarray]], x0: np.ndarray,
               scale: np.ndarray, *, max_subharmonic: int, march_periods: int) -> tuple[int, np.ndarray, PeriodicState]:
    """A stable periodic orbit of period k T: k = 1 shot from ``x0``, then k = 2..``max_subharmonic``
    shot from the state reached after ``march_periods`` periods (from the unstable period-1 orbit, or
    from ``x0`` if Newton did not converge).

    ``period_map(k, x) -> (x(k T), dx(k T)/dx(0))``.  Returns (k, state at t = 0, shooting result),
    or k = 0 and the marched state when there is none (the caller then averages over time).
    """
    sol = shoot_periodic(lambda x: period_map(1, x), x0, scale)
    if sol.converged and sol.stable:
        return 1, sol.state, sol
    marched = period_map(march_periods, sol.state if sol.converged else x0)[0]
    for k in range(2, max_subharmonic + 1):
        # from a state on the attractor, Newton converges in a few steps if a period-k orbit attracts
        sol_k = shoot_periodic(lambda x, k=k: period_map(k, x), marched, scale, max_iter=8)
        if sol_k.converged and sol_k.stable:
            return k, sol_k.state, sol_k
    return 0, marched, sol


def landed_window(advance: Callable, span: float, periodic: bool) -> tuple[list, bool]:
    """The pieces to average over, starting at a touchdown when there is one, and whether there is.

    ``advance(piece, t0, t1)`` returns the pieces from the start state (``piece`` None) or from a
    landing piece's initial state.  Starting at a touchdown puts each contact's tangential history
    (Coulomb-Orowan displacement, stick phase) inside the window.  Arcs alternate, so a contact piece
    after the first is a touchdown; a window that opens in contact and has a flight lands at its start.
    A periodic orbit is re-run for one full period from its touchdown; a time average drops the
    pieces before the first touchdown.
    """
    pieces = advance(None, 0.0, span)
    i = next((k for k in range(1, len(pieces)) if pieces[k].contact), None)
    if i is None and pieces[0].contact and len(pieces) > 1:
        i = 0
    if i is None:
        return pieces, False
    if not periodic:
        return pieces[i:], True
    start = pieces[i]
    window = advance(start, start.t0, start.t0 + span)
    # a touchdown found a rounding error before the window's end is the next window's first one
    return [q for q in window if q.t0 < start.t0 + span * (1 - 1e-9)], True


BALANCE_TOL = 1e-2  # accepted momentum-balance error of a time average (chaotic motion)
MAX_AVERAGE_GROWTH = 16  # a time average runs over at most 16 x march_periods periods
BATCHES = 8  # batch means for the uncertainty of a time average


def steady_state(amplitude: float, *, preload: float = FN, speed: float = SPEED,
                 parameters: FootParameters | None = None, max_subharmonic: int = 8,
                 march_periods: int = 400) -> ContactOrbit:
    """Periodic steady state of one foot (seed 000 eqs 2-17) at amplitude W [m, 0-peak].

    preload : Fn [N]; speed : sliding speed V [m/s]; parameters : FootParameters (defaults: seed 000
    appendix).  When the period-1 orbit is unstable, orbits of period k T (k <= ``max_subharmonic``)
    are sought from the state reached after ``march_periods`` periods; failing that, the result is a
    time average (``periodic = False``) over ``march_periods`` further periods, four times as many
    while its momentum balance is off by more than BALANCE_TOL (up to MAX_AVERAGE_GROWTH times).
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

    def period_map(k, x):
        pieces, u, v, Phi = _advance(dyn, 0.0, k * T, float(x[0]), float(x[1]))
        last.update(k=k, x=tuple(x), pieces=pieces)
        return np.array([u, v]), Phi

    periods, x, sol = find_orbit(period_map, np.array([_quasi_static_offset(W, dyn.P, dyn.kn), 0.0]), scale,
                                 max_subharmonic=max_subharmonic, march_periods=march_periods)
    if not periods:
        log.warning("no stable orbit of period up to %d T at W = %g m, Fn = %g N; averaging over %d periods",
                    max_subharmonic, W, Fn, march_periods)

    def advance(piece, t0, t1):
        if piece is None:
            if last.get("x") == tuple(x) and last["k"] * T == t1:  # the shooting's last period
                return last["pieces"]
            return _advance(dyn, t0, t1, float(x[0]), float(x[1]))[0]
        return _advance(dyn, t0, t1, piece.arc.u0, piece.arc.v0, contact=True)[0]

    window = periods or march_periods
    while True:
        with np.errstate(over="ignore", invalid="ignore"):  # the unused sensitivity of a long march
            pieces, landed = landed_window(advance, window * T, bool(periods))
        span = pieces[-1].t1 - pieces[0].t0
        touchdowns = {q.arc.t0 for q in pieces if q.contact} if landed else set()
        flight, int_rn, int_rt = _integrate(dyn, p, V, pieces, touchdowns)
        balance = abs(int_rn / span / dyn.P - 1)
        if periods or balance <= BALANCE_TOL or window >= MAX_AVERAGE_GROWTH * march_periods:
            break
        window *= 4
    uncertainty = 0.0 if periods else _batch_uncertainty(dyn, p, V, pieces, touchdowns)
    if not periods and max(balance, uncertainty) > BALANCE_TOL:
        log.warning("time average over %d periods: momentum balance off by %.2g, <Rt> uncertain by %.2g "
                    "(standard error of %d batch means)", window, balance, uncertainty, BATCHES)
    n_periods = span / T
    return ContactOrbit(
        amplitude=W, preload=Fn, speed=V, parameters=p,
        flight_ratio=100.0 * flight / span, normal_mean=int_rn / span, friction_mean=int_rt / span,
        contacts_per_period=len(touchdowns) / (periods or n_periods), periodic=bool(periods), residual=sol.residual,
        periods=round(n_periods),
        pieces=tuple(pieces), touchdowns=tuple(sorted(touchdowns)), friction_uncertainty=uncertainty)


def _batch_uncertainty(dyn: _Dynamics, p: FootParameters, speed: float, pieces: Sequence[_Piece],
                       touchdowns: set) -> float:
    """Relative standard error of a time average of Rt by batch means: the window cut into BATCHES
    consecutive stretches of pieces, std(means) / sqrt(BATCHES) / mean (Law & Kelton, Simulation
    Modeling and Analysis, 2000, sec. 9.5.3)."""
    starts = np.array([q.t0 for q in pieces])
    bounds = np.searchsorted(starts, np.linspace(starts[0], pieces[-1].t1, BATCHES + 1)[1:-1])
    means = []
    for group in np.split(np.arange(len(pieces)), bounds):
        if len(group) == 0:
            continue
        chosen = [pieces[i] for i in group]
        _, _, int_rt = _integrate(dyn, p, speed, chosen, touchdowns)
        means.append(int_rt / (chosen[-1].t1 - chosen[0].t0))
    mean = float(np.mean(means))
    if len(means) < 2 or mean == 0:
        return 0.0
    return float(np.std(means, ddof=1) / math.sqrt(len(means)) / abs(mean))


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


def values(name: str, x, *, nonnegative: bool = True) -> np.ndarray:
    """A 1-D array of finite numbers (>= 0 unless told), or a one-line ContactError naming the entry."""
    try:
        arr = np.atleast_1d(np.asarray(x, dtype=float))
    except (TypeError, ValueError):
        raise ContactError(f"{name}: expected numbers, got {x!r}") from None
    if arr.ndim != 1 or arr.size == 0:
        raise ContactError(f"{name}: expected a number or a 1-D sequence of numbers")
    for i, xi in enumerate(arr):
        require(f"{name}[{i}]" if arr.size > 1 else name, xi, nonnegative=nonnegative)
    return arr


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
    u0 = -P / p.kn if start == "rest" else _quasi_static_offset(W, P, p.kn)
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
