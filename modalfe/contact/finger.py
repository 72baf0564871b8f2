"""Bed-spring model of a fingertip on an ultrasonic plate: friction reduction against amplitude and frequency.

Model (seed 004, section II, Fig. 1-4, Table I)
------------------------------------------------
Three layers in series above the plate: stratum corneum (sc, touching the plate), dermis (``e`` in
the seed's Table I and equations, ``d`` in its text) and subcutaneous tissue (st), each a mass ``M_j``
on a spring ``K_j`` with a damper ``D_j`` tuned for critical damping of that layer alone,
``D_j = 2 sqrt(K_j M_j)`` (section II.C).  The user presses with a constant force ``f_p`` on the
subcutaneous mass.  The plate moves by ``w(t) = (A_pp / 2) sin(omega t)``.

Reading of eq. (1).  The seed prints ``f_Nj = K_j int(u_i - u_j) dt - D_j u_j``: a spring on the
relative displacement but a damper on the absolute velocity of mass ``j``.  Taken literally
(``reading="literal"``), nothing in the contact force jumps at a landing: it restarts from zero and
grows more slowly than ``K_Tsc V_F / mu``, so the pulp slides from the first instant and
``<f_Tsc> = mu <f_Nsc> = mu f_p`` - no friction reduction over the seed's amplitude range (to rounding
up to 3 um peak-to-peak at 66 kHz and 1 um at 225 kHz; 0.06 % at 6 um, 66 kHz), although the finger
does leave the plate (at 66 kHz it is in contact 74 % of the time at 1 um and 34 % at 3 um).
That contradicts the seed's Figs 6 and 7, so it cannot be the seed's model.  The seed's own words,
each layer with "its own stiffness, equivalent mass and damping" tuned "to achieve a critical damping
of each layer", describe Kelvin-Voigt layers, whose damper acts on the layer's rate of compression:
``f_Nj = K_j int(u_i - u_j) dt + D_j (u_i - u_j)``.  That is the default (``reading="kelvin-voigt"``).
Eq. (2) is printed with garbled indices; its physical content, used here, is
``M_j u_j' = f_Nj - f_Nk`` with ``f_Nb = f_p`` above the subcutaneous mass.

Contact and flying (section II.A, B).  In contact the pulp surface moves with the plate and
``f_Nsc = K_sc q + D_sc q'`` with ``q`` the compression of the stratum corneum.  The force cannot be
negative (the seed's saturated integrator): the finger flies from the instant ``f_Nsc`` reaches zero.
While flying, the unloaded Kelvin-Voigt layer relaxes, ``K_sc q + D_sc q' = 0`` (its surface has no
mass), and contact resumes when the plate catches up with the relaxing surface.  In the literal
reading the damper does not act on ``q``, so the surface relaxes at once and contact is simply
``f_Nsc > 0``.

Tangential axis (Fig. 2): on landing the pulp sticks, ``f_Tsc = K_Tsc V_F (t - t_c)``; once that reaches
``mu f_Nsc`` it slides, ``f_Tsc = mu f_Nsc``, until it flies (``f_Tsc = 0``).  The friction ratio is
``mu_US / mu = <f_Tsc> / (mu f_p)`` over a period of the steady state (see ``FingerOrbit``).

Method: the same as ``modalfe.contact.foot`` - each phase is linear and solved in closed form (modal
decomposition of the phase's state matrix, the free finger's rigid-body motion as a parabola),
events are found on a fine grid and polished by Newton's method, and the periodic steady state is
the fixed point of the period map, found by shooting with the exact monodromy matrix (transition
matrices and saltation matrices at the switches).  Amplitude sweeps use the previous amplitude's
orbit as the first guess.  At 66 kHz above ~0.7 um peak-to-peak the finger bounces irregularly (no
stable orbit of period up to 8 T): those points are time averages (``periodic = False``).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from modalfe.contact.foot import (
    find_orbit,
    first_crossing,
    gauss_nodes,
    landed_window,
    replaced,
    require,
    values,
)
from modalfe.errors import ContactError

log = logging.getLogger(__name__)

# Seed 004, Table I (N/mm -> N/m, g -> kg), for a normal force of 0.5 N.
K_SC = 8.7e6  # N/m, stratum corneum
K_E = 2.17e6  # N/m, dermis
K_ST = 1.0e3  # N/m, subcutaneous tissue
M_SC = 0.01e-3  # kg
M_E = 0.04e-3  # kg
M_ST = 0.12e-3  # kg
K_TSC = 98.12e6  # N/m, tangential stiffness of the stratum corneum, as printed (98120 N/mm)
# Seed 004 section II.C: preload, finger speed and friction coefficient of the simulations.
PRELOAD = 0.5  # N
SPEED = 0.1  # m/s
MU = 1.0
FREQUENCIES = (66e3, 225e3)  # Hz, seed 004 sections II.C and III.A
READINGS = ("kelvin-voigt", "literal")

SAMPLES_PER_PERIOD = 48  # event search grid: points per drive period or per fastest contact mode


@dataclass(frozen=True)
class FingerParameters:
    """Bed-spring finger (seed 004 Table I; SI units).

    K_sc, K_e, K_st : layer stiffnesses [N/m]; M_sc, M_e, M_st : layer masses [kg];
    K_Tsc : tangential stiffness [N/m]; preload : f_p [N]; speed : finger speed V_F [m/s];
    mu : friction coefficient; damping_ratio : of each layer alone (1 = critical, seed 004 II.C);
    reading : ``kelvin-voigt`` (dampers on the layers' compression rates, default) or ``literal``
    (eq. (1) as printed, dampers on the masses' absolute velocities); see the module docstring.
    """

    K_sc: float = K_SC
    K_e: float = K_E
    K_st: float = K_ST
    M_sc: float = M_SC
    M_e: float = M_E
    M_st: float = M_ST
    K_Tsc: float = K_TSC
    preload: float = PRELOAD
    speed: float = SPEED
    mu: float = MU
    damping_ratio: float = 1.0
    reading: str = "kelvin-voigt"

    def __post_init__(self):
        for name in ("K_sc", "K_e", "K_st", "M_sc", "M_e", "M_st", "K_Tsc", "preload", "mu", "damping_ratio"):
            require(name, getattr(self, name), positive=True)
        require("speed", self.speed, nonnegative=True)
        if self.reading not in READINGS:
            raise ContactError(f"reading: expected one of {READINGS}, got {self.reading!r}")

    def with_(self, **changes) -> FingerParameters:
        """A copy with some fields changed (validated); unknown names raise ContactError."""
        return replaced(self, "finger", changes)

    @property
    def stiffness(self) -> np.ndarray:
        """K_sc, K_e, K_st [N/m]."""
        return np.array([self.K_sc, self.K_e, self.K_st])

    @property
    def mass(self) -> np.ndarray:
        """M_sc, M_e, M_st [kg]."""
        return np.array([self.M_sc, self.M_e, self.M_st])

    @property
    def damping(self) -> np.ndarray:
        """D_sc, D_e, D_st [N s/m]: 2 zeta sqrt(K_j M_j), critical per layer by default (seed 004 II.C)."""
        return 2 * self.damping_ratio * np.sqrt(self.stiffness * self.mass)


# ----------------------------------------------------------------------------------------------
# Closed-form phases.  State x = (y_sc, y_e, y_st, v_sc, v_e, v_st, q): upward displacements of the
# masses from the preloaded rest, their velocities, and the compression q of the stratum corneum.
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class _Modal:
    """x' = A x + c + Im(F e^{i omega t}) with A diagonalizable and invertible, solved modally."""

    A: np.ndarray
    c: np.ndarray
    F: np.ndarray
    omega: float

    @cached_property
    def _eig(self):
        lam, V = np.linalg.eig(self.A)
        if np.linalg.cond(V) > 1e10:
            raise ContactError("finger parameters: a phase's modes are (nearly) defective; change damping_ratio")
        return lam, V, np.linalg.inv(V)

    @cached_property
    def _particular(self):
        """Constant and sinusoidal steady solution: x_const, Re X, Im X."""
        X = np.linalg.solve(1j * self.omega * np.eye(len(self.c)) - self.A, self.F)
        return -np.linalg.solve(self.A, self.c), X.real, X.imag

    @property
    def eigenvalues(self) -> np.ndarray:
        return self._eig[0]

    def arc(self, t0: float, x0: np.ndarray):
        """The solution through x(t0) = x0 as a callable t -> (x, x'), arrays (N, n)."""
        lam, V, Vi = self._eig
        xc, Xr, Xi = self._particular
        w = self.omega
        m0 = Vi @ (x0 - (xc + Xr * math.sin(w * t0) + Xi * math.cos(w * t0)))
        VT, lamVT = V.T, (lam[:, None] * V.T)

        def at(t):
            t = np.atleast_1d(t)
            e = np.exp(np.outer(t - t0, lam)) * m0
            s, c = np.sin(w * t)[:, None], np.cos(w * t)[:, None]
            return xc + Xr * s + Xi * c + (e @ VT).real, w * (Xr * c - Xi * s) + (e @ lamVT).real
        return at

    def transition(self, tau: float) -> np.ndarray:
        """expm(A tau)."""
        lam, V, Vi = self._eig
        return ((V * np.exp(lam * tau)[None, :]) @ Vi).real


@dataclass(frozen=True, eq=False)
class _FingerDynamics:
    """One operating point: contact and flight phases, events and forces of seed 004's model."""

    p: FingerParameters
    omega: float
    amplitude: float  # 0-peak [m]

    @cached_property
    def d_sc(self) -> float:
        return float(self.p.damping[0])

    @cached_property
    def kelvin_voigt(self) -> bool:
        return self.p.reading == "kelvin-voigt"

    def _state_matrix(self, contact: bool) -> np.ndarray:
        """d(y, v)'/d(y, v): M_j a_j = f_j - f_(j+1) with layer forces f_sc, f_e, f_st (seed 004 eqs 1, 2)."""
        p = self.p
        K, D, M = p.stiffness, p.damping, p.mass
        Fy = np.zeros((3, 3))  # d(layer force)/dy, rows sc, e, st; compression positive
        Fv = np.zeros((3, 3))
        Fy[1, :2] = K[1], -K[1]
        Fy[2, 1:] = K[2], -K[2]
        if self.kelvin_voigt:
            Fv[1, :2] = D[1], -D[1]
            Fv[2, 1:] = D[2], -D[2]
        else:
            Fv[1, 1], Fv[2, 2] = -D[1], -D[2]
        if contact:  # the plate holds the lower end of the sc layer
            Fy[0, 0], Fv[0, 0] = -K[0], -D[0]
        B = np.array([[1.0, -1.0, 0.0], [0.0, 1.0, -1.0], [0.0, 0.0, 1.0]]) / M[:, None]
        A = np.zeros((6, 6))
        A[:3, 3:] = np.eye(3)
        A[3:, :3], A[3:, 3:] = B @ Fy, B @ Fv
        return A

    @cached_property
    def contact(self) -> _Modal:
        """Contact: the sc layer's force is f_p + K_sc (w - y_sc) + D_sc (w' - v_sc) (Kelvin-Voigt)."""
        p = self.p
        F = np.zeros(6, complex)
        F[3] = self.amplitude * (p.K_sc + 1j * self.omega * self.d_sc * self.kelvin_voigt) / p.M_sc
        return _Modal(self._state_matrix(True), np.zeros(6), F, self.omega)

    @cached_property
    def _flight(self):
        """Free finger in z = T x = (y_sc - y_e, y_e - y_st, v_sc - v_e, v_e - v_st, y_cm, v_cm).

        The centre of mass falls freely under f_p (a parabola).  The relative motion r obeys
        ``r' = A_r r + b v_cm + c_r``: ``b = 0`` for Kelvin-Voigt layers; the literal reading's dampers on
        absolute velocities make it feel the centre of mass's velocity (a ramp, so r has the particular
        solution ``P0 + P1 tau``).  The relative part is solved modally.
        """
        p = self.p
        A = self._state_matrix(False)
        c = np.zeros(6)
        c[3] = -p.preload / p.M_sc  # the sc layer's rest force f_p is gone
        M = p.mass
        T = np.zeros((6, 6))
        T[0, :3] = T[2, 3:] = [1, -1, 0]
        T[1, :3] = T[3, 3:] = [0, 1, -1]
        T[4, :3] = T[5, 3:] = M / M.sum()
        Ti = np.linalg.inv(T)
        Az, cz = T @ A @ Ti, T @ c
        A_r, b = Az[:4, :4], Az[:4, 5]
        relative = _Modal(A_r, np.zeros(4), np.zeros(4, complex), self.omega)
        a_cm = float(cz[5])
        P1 = -np.linalg.solve(A_r, b * a_cm)
        return relative, T, Ti, a_cm, b, cz[:4], P1

    def _flight_offset(self, v_cm0: float) -> np.ndarray:
        """P0 of the relative motion's particular solution P0 + P1 tau for initial v_cm."""
        relative, _, _, _, b, c_r, P1 = self._flight
        return np.linalg.solve(relative.A, P1 - b * v_cm0 - c_r)

    @property
    def relax_rate(self) -> float:
        """K_sc / D_sc [1/s]: relaxation of the unloaded stratum corneum (Kelvin-Voigt reading)."""
        return self.p.K_sc / self.d_sc if self.kelvin_voigt else math.inf

    @property
    def q_rest(self) -> float:
        """Compression of the stratum corneum at rest under f_p [m]."""
        return self.p.preload / self.p.K_sc

    @cached_property
    def step(self) -> float:
        """Event search grid spacing [s]: 1/SAMPLES_PER_PERIOD of the drive or of the fastest
        oscillation, and no longer than a quarter of the fastest decay time."""
        lam = np.concatenate([self.contact.eigenvalues, self._flight[0].eigenvalues])
        fastest = max(self.omega, float(np.max(np.abs(lam.imag))))
        return min(2 * math.pi / fastest / SAMPLES_PER_PERIOD, 0.25 / float(np.max(np.abs(lam))))

    def plate(self, t):
        """w, w', w'' of the plate at t [m, m/s, m/s^2]."""
        wt = self.omega * np.atleast_1d(t)
        a = self.amplitude
        s = np.sin(wt)
        return a * s, a * self.omega * np.cos(wt), -a * self.omega ** 2 * s

    def arc(self, contact: bool, t0: float, x0: np.ndarray):
        """The solution through x(t0) = x0 on one phase, as a callable t -> (x, x') of shape (N, 7)."""
        q_rest = self.q_rest
        if contact:
            inner = self.contact.arc(t0, x0[:6])

            def at(t):
                x6, r6 = inner(t)
                w, wd, _ = self.plate(t)
                x, r = np.empty((len(x6), 7)), np.empty((len(x6), 7))
                x[:, :6], r[:, :6] = x6, r6
                x[:, 6], r[:, 6] = q_rest + w - x6[:, 0], wd - r6[:, 0]  # the surface is on the plate
                return x, r
            return at
        relative, T, Ti, a_cm, _, _, P1 = self._flight
        z0 = T @ x0[:6]
        P0 = self._flight_offset(z0[5])
        inner = relative.arc(t0, z0[:4] - P0)
        k, q0 = self.relax_rate, x0[6]

        def at(t):
            t = np.atleast_1d(t)
            tau = t - t0
            hr, hd = inner(t)
            z, zd = np.empty((len(t), 6)), np.empty((len(t), 6))
            z[:, :4], zd[:, :4] = P0 + np.outer(tau, P1) + hr, P1 + hd
            z[:, 4], z[:, 5] = z0[4] + z0[5] * tau + 0.5 * a_cm * tau * tau, z0[5] + a_cm * tau
            zd[:, 4], zd[:, 5] = z[:, 5], a_cm
            x, r = np.empty((len(t), 7)), np.empty((len(t), 7))
            x[:, :6], r[:, :6] = z @ Ti.T, zd @ Ti.T
            x[:, 6] = q0 * np.exp(-k * tau) if k < math.inf else 0.0
            r[:, 6] = -k * x[:, 6] if k < math.inf else 0.0
            return x, r
        return at

    def transition(self, contact: bool, tau: float) -> np.ndarray:
        """d x(t0 + tau) / d x(t0) on one phase (7 x 7)."""
        Phi = np.zeros((7, 7))
        if contact:
            E = self.contact.transition(tau)
            Phi[:6, :6] = E
            Phi[6, :6] = -E[0]  # q = q_rest + w - y_sc
            return Phi
        relative, T, Ti, _, b, _, _ = self._flight
        E = relative.transition(tau)
        Ez = np.zeros((6, 6))
        Ez[:4, :4] = E
        Ez[:4, 5] = -(np.eye(4) - E) @ np.linalg.solve(relative.A, b)  # through P0(v_cm0)
        Ez[4:, 4:] = [[1.0, tau], [0.0, 1.0]]
        Phi[:6, :6] = Ti @ Ez @ T
        Phi[6, 6] = math.exp(-self.relax_rate * tau)
        return Phi

    def normal_force(self, x, r, t):
        """f_Nsc from the contact formula (seed 004 eq. 1 for the sc layer) and its rate."""
        p = self.p
        w, wd, wdd = self.plate(t)
        D = self.d_sc
        if self.kelvin_voigt:
            return (p.preload + p.K_sc * (w - x[:, 0]) + D * (wd - x[:, 3]),
                    p.K_sc * (wd - r[:, 0]) + D * (wdd - r[:, 3]))
        return p.preload + p.K_sc * (w - x[:, 0]) - D * x[:, 3], p.K_sc * (wd - r[:, 0]) - D * r[:, 3]

    def landing(self, x, r, t):
        """Touchdown function (rises through 0 on landing) and its rate: the plate reaching the
        relaxing surface (Kelvin-Voigt) or a positive contact force (literal)."""
        if not self.kelvin_voigt:
            return self.normal_force(x, r, t)
        w, wd, _ = self.plate(t)
        return self.q_rest + w - x[:, 0] - x[:, 6], wd - r[:, 0] - r[:, 6]

    def in_contact(self, t: float, x: np.ndarray) -> bool:
        """Whether state x at t is in contact (the landing function is >= 0)."""
        return bool(self.landing(x[None, :], np.zeros((1, 7)), t)[0][0] >= 0)

    def exit_function(self, contact: bool, at):
        """A phase's exit function and rate as a callable of t (arrays or floats): the contact force
        falling through zero (contact), the landing function rising through zero (flight)."""
        force = self.normal_force if contact else self.landing

        def fr(t):
            x, r = at(t)
            f, d = force(x, r, t)
            return (f, d) if np.ndim(t) else (float(f[0]), float(d[0]))
        return fr


@dataclass(frozen=True, eq=False)
class _Piece:
    contact: bool
    t0: float
    t1: float
    x0: np.ndarray
    at: object  # t -> (x, x') on this piece


def _advance(dyn: _FingerDynamics, t0: float, t1: float, x: np.ndarray, *, contact: bool | None = None):
    """Event-driven exact solution on [t0, t1]: pieces, final state, monodromy d x(t1) / d x(t0)."""
    x = np.asarray(x, float).copy()
    if contact is None:
        contact = dyn.in_contact(t0, x)
    if contact:
        x[6] = dyn.q_rest + float(dyn.plate(t0)[0][0]) - x[0]  # the surface is on the plate
    pieces: list[_Piece] = []
    Phi = np.eye(7)
    t = t0
    horizon = 2 * math.pi / dyn.omega
    while True:
        at = dyn.arc(contact, t, x)
        fr = dyn.exit_function(contact, at)
        a = t
        while True:
            b = min(a + horizon, t1)
            te = first_crossing(fr, a, b, dyn.step, upward=not contact)
            if te is not None or b >= t1:
                break
            a = b
        end = t1 if te is None else te
        pieces.append(_Piece(contact, t, end, x, at))
        Phi = dyn.transition(contact, end - t) @ Phi
        x_end, f_before = (v[0] for v in at(end))
        if te is None:
            return pieces, x_end, Phi
        # saltation S = I + (f_after - f_before) grad(h)^T / (dh/dt along f_before), h the exit function
        f_after = dyn.arc(not contact, te, x_end)(te)[1][0]
        grad, h_t = _event_gradient(dyn, contact, te)
        rate = grad @ f_before + h_t
        if rate != 0:
            Phi = (np.eye(7) + np.outer(f_after - f_before, grad) / rate) @ Phi
        t, x, contact = te, x_end, not contact
        if len(pieces) > 10_000 * max(1, round((t1 - t0) / horizon)):
            raise ContactError("finger events: no progress (chattering without end); check the parameters")


def _event_gradient(dyn: _FingerDynamics, contact: bool, t: float) -> tuple[np.ndarray, float]:
    """Gradient in x and partial time derivative of the exit function of a phase."""
    _, wd, wdd = dyn.plate(t)
    g = np.zeros(7)
    if contact or not dyn.kelvin_voigt:  # the contact force
        g[0], g[3] = -dyn.p.K_sc, -dyn.d_sc
        return g, dyn.p.K_sc * wd[0] + dyn.d_sc * wdd[0] * dyn.kelvin_voigt
    g[0], g[6] = -1.0, -1.0  # the landing gap
    return g, wd[0]


# ----------------------------------------------------------------------------------------------
# Steady state and curves
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class FingerOrbit:
    """Steady state of the finger at one amplitude and frequency.

    amplitude_pp : peak-to-peak plate amplitude [m]; frequency [Hz];
    friction_ratio : mu_US / mu = <f_Tsc> / (mu <f_Nsc>), which is <f_Tsc> / (mu f_p) on a periodic orbit
    (momentum balance, <f_Nsc> = f_p) and its lower-variance estimate over a time average;
    normal_mean : <f_Nsc> [N] (f_p at steady state; over a time average its deviation from f_p
    measures the averaging error); contact_ratio : time in contact [%];
    contacts_per_period; periodic : exact periodic orbit of ``periods`` drive periods, else a time
    average over ``periods`` periods; state : the state at t = 0 (guess for a neighbouring point).
    """

    amplitude_pp: float
    frequency: float
    parameters: FingerParameters
    friction_ratio: float
    normal_mean: float
    contact_ratio: float
    contacts_per_period: float
    periodic: bool
    periods: int
    state: np.ndarray


def _friction_integral(dyn: _FingerDynamics, piece: _Piece, landed: bool) -> tuple[float, float]:
    """int f_Nsc dt and int f_Tsc dt over a contact piece: stick, then slide (seed 004 Fig. 2)."""
    p = dyn.p

    def fn(t):
        x, r = piece.at(t)
        return dyn.normal_force(x, r, t)

    chunk = dyn.step * 8
    x, w = gauss_nodes(piece.t0, piece.t1, chunk)
    int_n = float(w @ fn(x)[0]) if len(x) else 0.0
    if not landed:
        return int_n, p.mu * int_n
    kv = p.K_Tsc * p.speed

    def stick_excess(t):  # K_Tsc X_T - mu f_N: the pulp slides once this reaches zero
        f, d = fn(t)
        out = kv * (np.atleast_1d(t) - piece.t0) - p.mu * f, kv - p.mu * d
        return out if np.ndim(t) else (float(out[0][0]), float(out[1][0]))

    ts = first_crossing(stick_excess, piece.t0, piece.t1, dyn.step, upward=True)
    ts = piece.t1 if ts is None else ts
    stick = 0.5 * kv * (ts - piece.t0) ** 2
    xs, ws = gauss_nodes(ts, piece.t1, chunk)
    return int_n, stick + (p.mu * float(ws @ fn(xs)[0]) if len(xs) else 0.0)


def finger_steady_state(amplitude_pp: float, frequency: float, *, parameters: FingerParameters | None = None,
                        guess: np.ndarray | None = None, max_subharmonic: int = 8,
                        march_periods: int = 300) -> FingerOrbit:
    """Steady state of seed 004's bed-spring finger on a plate vibrating at ``frequency`` [Hz] with
    peak-to-peak amplitude ``amplitude_pp`` [m]; ``guess``: a state at t = 0 to start shooting from
    (default: the preloaded rest).  Subharmonic orbits and the time-average fallback as in
    ``modalfe.contact.foot.steady_state``."""
    p = parameters if parameters is not None else FingerParameters()
    A = require("amplitude", amplitude_pp, nonnegative=True)
    f = require("frequency", frequency, positive=True)
    dyn = _FingerDynamics(p, 2 * math.pi * f, A / 2)
    T = 1 / f
    x0 = np.zeros(7)
    x0[6] = dyn.q_rest
    if guess is not None:
        x0 = np.asarray(guess, float)

    def period_map(k, x):
        _, xT, Phi = _advance(dyn, 0.0, k * T, x)
        return xT, Phi

    su = max(A / 2, dyn.q_rest)
    scale = np.array([su] * 3 + [su * dyn.omega] * 3 + [su])
    periods, x_start, _ = find_orbit(period_map, x0, scale, max_subharmonic=max_subharmonic,
                                     march_periods=march_periods)
    if not periods:
        log.warning("finger: no stable orbit of period up to %d T at %g m pp, %g Hz; averaging over %d periods",
                    max_subharmonic, A, f, march_periods)
    periodic = bool(periods)
    periods = periods or march_periods

    def advance(piece, t0, t1):
        if piece is None:
            return _advance(dyn, t0, t1, x_start)[0]
        return _advance(dyn, t0, t1, piece.x0, contact=True)[0]

    pieces, landed = landed_window(advance, periods * T, periodic)
    span = pieces[-1].t1 - pieces[0].t0
    int_n = int_t = contact_time = 0.0
    n_land = 0
    for q in pieces:
        if q.contact:
            a, b = _friction_integral(dyn, q, landed=landed)
            int_n, int_t, contact_time = int_n + a, int_t + b, contact_time + q.t1 - q.t0
            n_land += landed
    if int_n <= 0:
        raise ContactError(f"amplitude: the finger did not touch the plate while averaging at {A:g} m pp, "
                           f"{f:g} Hz; raise march_periods")
    n_periods = periods if periodic else span * f
    return FingerOrbit(
        amplitude_pp=A, frequency=f, parameters=p, friction_ratio=int_t / (p.mu * int_n),
        normal_mean=int_n / span, contact_ratio=100 * contact_time / span, contacts_per_period=n_land / n_periods,
        periodic=periodic, periods=round(span * f), state=x_start)


@dataclass(frozen=True, eq=False)
class FingerCurve:
    """Friction ratio mu_US / mu against peak-to-peak amplitude at one frequency (seed 004 Fig. 6).

    amplitude_pp [m]; frequency [Hz]; friction_ratio; contact_ratio [%]; contacts_per_period;
    periodic (exact periodic orbit, else a time average).
    """

    amplitude_pp: np.ndarray
    frequency: float
    parameters: FingerParameters
    friction_ratio: np.ndarray
    contact_ratio: np.ndarray
    contacts_per_period: np.ndarray
    periodic: np.ndarray

    def to_json(self) -> dict:
        return {"frequency_hz": self.frequency, "amplitude_pp_m": self.amplitude_pp.tolist(),
                "friction_ratio": self.friction_ratio.tolist(), "contact_ratio_percent": self.contact_ratio.tolist(),
                "contacts_per_period": self.contacts_per_period.tolist(), "periodic": self.periodic.tolist()}


def simulate_finger(amplitude_pp, frequency: float = FREQUENCIES[0], *, parameters: FingerParameters | None = None,
                    progress: bool = False) -> FingerCurve:
    """mu_US / mu against peak-to-peak amplitude [m] at ``frequency`` [Hz] (seed 004 Fig. 6).

    Amplitudes are solved in increasing order, each starting from the previous orbit.
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
    guess = None
    for i in items:
        o = finger_steady_state(A[i], frequency, parameters=p, guess=guess)
        orbits[int(i)] = o
        guess = o.state
    ordered = [orbits[i] for i in range(len(A))]
    return FingerCurve(
        amplitude_pp=A, frequency=float(frequency), parameters=p,
        friction_ratio=np.array([o.friction_ratio for o in ordered]),
        contact_ratio=np.array([o.contact_ratio for o in ordered]),
        contacts_per_period=np.array([o.contacts_per_period for o in ordered]),
        periodic=np.array([o.periodic for o in ordered]))


@dataclass(frozen=True, eq=False)
class EqualFriction:
    """Amplitudes giving the same friction at two frequencies (seed 004 Fig. 7).

    level : mu_US / mu; amplitude_low, amplitude_high : peak-to-peak [m] at ``frequencies``
    (low, high) [Hz]; ratio : amplitude_high / amplitude_low.  For comparison, equal velocity gives
    f_low / f_high and equal acceleration (f_low / f_high)^2.
    """

    level: np.ndarray
    frequencies: tuple[float, float]
    amplitude_low: np.ndarray
    amplitude_high: np.ndarray

    @property
    def ratio(self) -> np.ndarray:
        return self.amplitude_high / self.amplitude_low

    @property
    def velocity_ratio(self) -> float:
        return self.frequencies[0] / self.frequencies[1]

    @property
    def acceleration_ratio(self) -> float:
        return self.velocity_ratio ** 2

    def to_json(self) -> dict:
        return {"frequencies_hz": list(self.frequencies), "level": self.level.tolist(),
                "amplitude_low_pp_m": self.amplitude_low.tolist(), "amplitude_high_pp_m": self.amplitude_high.tolist(),
                "ratio": self.ratio.tolist(), "equal_velocity_ratio": self.velocity_ratio,
                "equal_acceleration_ratio": self.acceleration_ratio}


def _amplitude_for(curve: FingerCurve, level: float) -> float:
    """Smallest amplitude at which the curve's friction ratio falls to ``level`` (linear interpolation
    between the two bracketing points of the curve)."""
    order = np.argsort(curve.amplitude_pp, kind="stable")
    a, r = curve.amplitude_pp[order], curve.friction_ratio[order]
    below = np.flatnonzero(r <= level)
    if not below.size or below[0] == 0:
        raise ContactError(f"level: friction ratio {level:g} is outside the curve at {curve.frequency:g} Hz "
                           f"({r.min():.3g} to {r.max():.3g}); widen the amplitude range")
    i = below[0]
    a0, a1, r0, r1 = a[i - 1], a[i], r[i - 1], r[i]
    return float(a0 + (level - r0) * (a1 - a0) / (r1 - r0))


def equal_friction(low: FingerCurve, high: FingerCurve, levels: Sequence[float]) -> EqualFriction:
    """Amplitude ratio A(high) / A(low) giving equal mu_US / mu at each level (seed 004 Fig. 7: about 0.12).

    Each curve must start above each level and reach below it; the curves' resolution sets the
    accuracy (linear interpolation between the two points around the first crossing).
    """
    lv = values("level", levels)
    for i, x in enumerate(lv):
        if not 0 < x < 1:
            raise ContactError(f"level[{i}]: a friction ratio strictly between 0 and 1, got {x:g}")
    return EqualFriction(lv, (low.frequency, high.frequency),
                         np.array([_amplitude_for(low, x) for x in lv]),
                         np.array([_amplitude_for(high, x) for x in lv]))
