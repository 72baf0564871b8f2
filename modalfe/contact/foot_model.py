"""Seed 000's foot model, normal axis: parameters, closed-form contact and flight arcs, and the exact
event-driven solution with its sensitivity (``steady_state`` and the friction are in ``foot``).

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
values by at most ~2 % of its peak, for < 0.3 % of a period).  The normal dynamics and ``<Rn>`` use
``Rn`` as printed; the friction clips it at zero (``foot``).

Method: both phases are linear with closed-form solutions, in contact a damped oscillator driven at
``omega`` (steady sinusoid plus a homogeneous part propagated by the 2x2 exponential of the phase's
state matrix), in flight a parabola.  Transitions are the events ``z_A = h``, found by
``modalfe.contact.kernel.first_crossing`` on a grid of 64 points per drive or contact-oscillation
period and polished by Newton's method.  The sensitivity d(u, v)(t1)/d(u, v)(t0) chains the arcs'
transition matrices with the saltation matrix of each switch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from modalfe.contact.kernel import bracketed_root, first_crossing
from modalfe.contact.validation import choice, replaced, require, require_fields
from modalfe.errors import ContactError

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
FRICTION_LAWS = ("clipped", "printed")  # Rt with Rn clipped at zero (default) or as printed


@dataclass(frozen=True)
class FootParameters:
    """Foot contact model parameters (defaults: seed 000 appendix; kt identified, see module docstring).

    kn : normal stiffness of one foot [N/m]; dn : damper on the plate's normal velocity [N s/m];
    mass : vibrating plate, m [kg]; n : feet sharing the load;
    g : gravity [m/s^2]; frequency : drive frequency [Hz]; mu0 : maximum (static) friction
    coefficient; kt : tangential contact stiffness of one foot [N/m];
    friction_law : ``clipped`` (default), ``Rt = min(kt V (t - t_c), mu0 max(Rn, 0))``, so the friction
    never turns negative when the printed ``Rn`` (eq. 3) dips below zero just before lift-off; or
    ``printed``, ``Rt = min(kt V (t - t_c), mu0 Rn)`` with seed 000 eqs 14-16 exactly as printed.
    """

    kn: float = KN
    dn: float = DN
    mass: float = MASS
    n: int = N_FEET
    g: float = G
    frequency: float = FREQUENCY
    mu0: float = SUBSTRATES["steel"]
    kt: float = KT
    friction_law: str = "clipped"

    def __post_init__(self):
        choice("friction_law", self.friction_law, FRICTION_LAWS)
        require_fields(self, positive=("kn", "mass", "frequency", "kt"), nonnegative=("dn", "g", "mu0"))
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

    def contact_only_state(self, amplitude: float, preload: float) -> tuple[float, float]:
        """(u, v) at t = 0 of the contact-only steady response (seed 000 eq. 11 without flight):
        ``u = -P/kn + Xr sin(omega t) + Xi cos(omega t)``; the steady state for W <= ``onset_amplitude``."""
        d = _Dynamics.build(self, amplitude, preload)
        return d.contact_particular(0.0, 1.0)


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


def quasi_static_offset(W: float, P: float, kn: float) -> float:
    """u = z_G - h of a plate held still whose mean foot force kn <(-u - W sin)^+> equals P."""
    if P / kn >= W:
        return -P / kn

    def mean(a):  # <(a - sin theta)^+> over theta, |a| <= 1
        return (a * (math.pi + 2 * math.asin(a)) + 2 * math.sqrt(1 - a * a)) / (2 * math.pi)

    a = bracketed_root(lambda a: kn * W * mean(a) - P, -1.0, 1.0, xtol=1e-15)
    return -a * W

