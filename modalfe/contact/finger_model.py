"""Seed 004's bed-spring finger, normal axis: parameters, closed-form phases and the exact event-driven
solution with its sensitivity (steady state and friction are in ``modalfe.contact.finger``).

Three layers in series above the plate: stratum corneum (sc, touching the plate), dermis (``e`` in
the seed's Table I and equations, ``d`` in its text) and subcutaneous tissue (st), each a mass ``M_j``
on a spring ``K_j`` with a damper ``D_j = 2 sqrt(K_j M_j)`` (critical for the layer alone, section
II.C).  The user presses with ``f_p`` on the subcutaneous mass; the plate moves by
``w(t) = (A_pp / 2) sin(omega t)``.  Layer forces (seed 004 eq. 1), in the two readings of its damper:

    kelvin-voigt (default):  f_Nj = K_j int(u_i - u_j) dt + D_j (u_i - u_j)
    literal (as printed):    f_Nj = K_j int(u_i - u_j) dt - D_j u_j

and masses ``M_j u_j' = f_Nj - f_Nk`` (eq. 2, indices restored), ``f_Nb = f_p``.  In contact the pulp
surface moves with the plate and ``f_Nsc = K_sc q + D_sc q'`` (Kelvin-Voigt; ``q`` the compression
of the stratum corneum) or ``K_sc q - D_sc u_sc`` (literal); the finger flies from the instant
``f_Nsc`` reaches zero (the seed's saturated integrator).  While flying, the unloaded Kelvin-Voigt
layer relaxes, ``K_sc q + D_sc q' = 0``, and contact resumes when the plate reaches the relaxing
surface; in the literal reading contact is simply ``f_Nsc > 0``.

Each phase is linear: contact is solved modally (6x6), the free finger as its centre of mass (a
parabola) plus the modal relative motion.  Every event function (the contact force, the landing gap)
is a linear functional of the state, so on an arc it is an exponential sum
``c0 + c1 tau + c2 tau^2 + s sin(omega t) + c cos(omega t) + Re sum beta_k exp(lambda_k tau)`` (``ExpSum``):
evaluated and integrated in closed form, and cheap enough for events found on a grid and polished by
Newton's method (``kernel.first_crossing``).  The phase at the start of a period is decided with a
rounding tolerance (``_FingerDynamics.in_contact``): a state on the plate is in contact when its force
is positive, so a rounding error in the gap never counts a landing.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from modalfe.contact.kernel import first_crossing
from modalfe.contact.validation import choice, replaced, require_fields
from modalfe.errors import ContactError

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

SAMPLES_PER_PERIOD = 24  # event search grid: points per drive period or per fastest contact mode


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
        require_fields(self, positive=("K_sc", "K_e", "K_st", "M_sc", "M_e", "M_st", "K_Tsc", "preload", "mu",
                                       "damping_ratio"), nonnegative=("speed",))
        choice("reading", self.reading, READINGS)

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

    def modal_start(self, t0: float, x0: np.ndarray) -> np.ndarray:
        """Modal amplitudes at t0 of the homogeneous part of the solution through x(t0) = x0."""
        _, _, Vi = self._eig
        xc, Xr, Xi = self._particular
        w = self.omega
        return Vi @ (x0 - (xc + Xr * math.sin(w * t0) + Xi * math.cos(w * t0)))

    def arc(self, t0: float, x0: np.ndarray):
        """The solution through x(t0) = x0 as a callable t -> (x, x'), arrays (N, n)."""
        lam, V, _ = self._eig
        xc, Xr, Xi = self._particular
        w = self.omega
        m0 = self.modal_start(t0, x0)
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

    @cached_property
    def _offset_terms(self) -> tuple[np.ndarray, np.ndarray]:
        relative, _, _, _, b, c_r, P1 = self._flight
        return np.linalg.solve(relative.A, P1 - c_r), np.linalg.solve(relative.A, b)

    def _flight_offset(self, v_cm0: float) -> np.ndarray:
        """P0 of the relative motion's particular solution P0 + P1 tau for initial v_cm:
        A_r^-1 (P1 - b v_cm0 - c_r)."""
        u0, u1 = self._offset_terms
        return u0 - u1 * v_cm0

    def _flight_start(self, t0: float, x0: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A flight arc through x(t0) = x0: z0 = T x0, the particular offset P0 and the relative
        motion's modal amplitudes."""
        relative, T, _, _, _, _, _ = self._flight
        z0 = T @ x0[:6]
        P0 = self._flight_offset(z0[5])
        return z0, P0, relative.modal_start(t0, z0[:4] - P0)

    @property
    def relax_rate(self) -> float:
        """K_sc / D_sc [1/s]: relaxation of the unloaded stratum corneum (Kelvin-Voigt reading)."""
        return self.p.K_sc / self.d_sc if self.kelvin_voigt else math.inf

    @cached_property
    def slowest_decay_time(self) -> float:
        """1 / min |Re lambda| over the contact phase's modes [s]: the memory of the finger on the plate (the
        subcutaneous layer, 0.35 ms with Table I's values)."""
        return 1 / float(np.min(np.abs(self.contact.eigenvalues.real)))

    @property
    def q_rest(self) -> float:
        """Compression of the stratum corneum at rest under f_p [m]."""
        return self.p.preload / self.p.K_sc

    @cached_property
    def step(self) -> tuple[float, float, float]:
        """Event search grid (``kernel._grid``): 1/SAMPLES_PER_PERIOD of the drive or of the fastest
        oscillation, and a quarter of the fastest decay time over the first 8 decay times of an arc."""
        lam = np.concatenate([self.contact.eigenvalues, self._flight[0].eigenvalues])
        fastest = max(self.omega, float(np.max(np.abs(lam.imag))))
        decay = 1 / float(np.max(np.abs(lam)))
        coarse = 2 * math.pi / fastest / SAMPLES_PER_PERIOD
        return coarse, min(coarse, 0.25 * decay), 8 * decay

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

    def end_state(self, contact: bool, t0: float, x0: np.ndarray, t: float) -> np.ndarray:
        """x(t) on the arc through x(t0) = x0 (the same closed form as ``arc``, for one time)."""
        tau = t - t0
        x = np.empty(7)
        if contact:
            m = self.contact
            lam, V, _ = m._eig
            xc, Xr, Xi = m._particular
            w = self.omega
            m0 = m.modal_start(t0, x0[:6])
            x[:6] = xc + Xr * math.sin(w * t) + Xi * math.cos(w * t) + (V @ (m0 * np.exp(lam * tau))).real
            x[6] = self.q_rest + self.amplitude * math.sin(w * t) - x[0]
            return x
        relative, _, Ti, a_cm, _, _, P1 = self._flight
        lam, V, _ = relative._eig
        z0, P0, m0 = self._flight_start(t0, x0)
        z = np.empty(6)
        z[:4] = P0 + P1 * tau + (V @ (m0 * np.exp(lam * tau))).real
        z[4], z[5] = z0[4] + z0[5] * tau + 0.5 * a_cm * tau * tau, z0[5] + a_cm * tau
        x[:6] = Ti @ z
        x[6] = x0[6] * math.exp(-self.relax_rate * tau) if self.kelvin_voigt else 0.0
        return x

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
        """Whether state x at t is in contact, decided with a rounding tolerance.

        Kelvin-Voigt: a surface measurably above the plate (gap below -1e-12 of the length scale) is
        flying; a surface on the plate is in contact when its force f_Nsc (contact formula) is positive
        beyond rounding, or zero and rising.  Literal: the same force test.  In contact the gap is zero
        by construction, so its rounding residue never decides (it used to count a landing at t = 0).
        """
        x = np.asarray(x, float)
        if self.kelvin_voigt:
            w = float(self.plate(t)[0][0])
            if self.q_rest + w - x[0] - x[6] < -1e-12 * max(self.q_rest, self.amplitude):
                return False
        xs, rs = self.contact.arc(t, x[:6])(t)
        f, d = self.normal_force(xs, rs, t)
        tol = 1e-11 * self.p.preload
        return bool(f[0] > tol or (f[0] >= -tol and d[0] > 0))

    def functional(self, contact: bool, t0: float, x0: np.ndarray, g: np.ndarray, const: float,
                   sin_w: float, cos_w: float) -> ExpSum:
        """``const + g . x6(t) + sin_w sin(omega t) + cos_w cos(omega t)`` on the arc through x(t0) = x0,
        as an exponential sum (x6: the masses' displacements and velocities)."""
        if contact:
            m = self.contact
            lam, V, _ = m._eig
            xc, Xr, Xi = m._particular
            return ExpSum(t0, self.omega, (const + g @ xc, 0.0, 0.0), sin_w + g @ Xr, cos_w + g @ Xi,
                          lam, (g @ V) * m.modal_start(t0, x0[:6]))
        relative, _, Ti, a_cm, _, _, P1 = self._flight
        lam, V, _ = relative._eig
        z0, P0, m0 = self._flight_start(t0, x0)
        h = g @ Ti
        hr = h[:4]
        poly = (const + hr @ P0 + h[4] * z0[4] + h[5] * z0[5], hr @ P1 + h[4] * z0[5] + h[5] * a_cm, h[4] * a_cm / 2)
        return ExpSum(t0, self.omega, poly, sin_w, cos_w, lam, (hr @ V) * m0)

    def force_sum(self, t0: float, x0: np.ndarray, contact: bool = True) -> ExpSum:
        """f_Nsc by the contact formula (seed 004 eq. 1, sc layer) on an arc, as an exponential sum."""
        p, D, a = self.p, self.d_sc, self.amplitude
        g = np.array([-p.K_sc, 0, 0, -D, 0, 0])
        return self.functional(contact, t0, x0, g, p.preload, p.K_sc * a, D * a * self.omega * self.kelvin_voigt)

    def exit_sum(self, contact: bool, t0: float, x0: np.ndarray) -> ExpSum:
        """A phase's exit function: the contact force (falls through zero at lift-off) or the landing
        function (rises through zero at touchdown: the gap to the relaxing surface, Kelvin-Voigt, or
        the contact force, literal)."""
        if contact or not self.kelvin_voigt:
            return self.force_sum(t0, x0, contact)
        g = np.array([-1.0, 0, 0, 0, 0, 0])
        gap = self.functional(False, t0, x0, g, self.q_rest, self.amplitude, 0.0)
        return gap.plus_exponential(-self.relax_rate, -float(x0[6]))


@dataclass(frozen=True, eq=False)
class ExpSum:
    """``f(t) = c0 + c1 tau + c2 tau^2 + s sin(omega t) + c cos(omega t) + Re sum_k beta_k e^{lambda_k tau}``,
    ``tau = t - t0``: a linear functional of a phase's closed-form solution."""

    t0: float
    omega: float
    poly: tuple[float, float, float]
    s: float
    c: float
    lam: np.ndarray
    beta: np.ndarray

    @cached_property
    def _beta_lam(self) -> np.ndarray:
        return self.beta * self.lam

    @cached_property
    def _terms(self) -> list[tuple[complex, complex, complex]]:
        """(lambda, beta, beta lambda) as Python complex numbers: a float time is evaluated in plain
        Python, several times faster than numpy on six terms."""
        return [(complex(a), complex(b), complex(a * b)) for a, b in zip(self.lam, self.beta)]

    def plus_exponential(self, lam: float, beta: float) -> ExpSum:
        return ExpSum(self.t0, self.omega, self.poly, self.s, self.c, np.append(self.lam, lam),
                      np.append(self.beta, beta))

    def __call__(self, t):
        """(f, f') at t (a float or an array)."""
        c0, c1, c2 = self.poly
        w = self.omega
        if np.ndim(t):
            t = np.asarray(t, float)
            tau = t - self.t0
            e = np.exp(np.outer(tau, self.lam))
            ex, exd = (e @ self.beta).real, (e @ self._beta_lam).real
            sn, cs = np.sin(w * t), np.cos(w * t)
        else:
            t = float(t)
            tau = t - self.t0
            ex = exd = 0.0
            for lam, beta, beta_lam in self._terms:
                e = cmath.exp(lam * tau)
                ex += (e * beta).real
                exd += (e * beta_lam).real
            sn, cs = math.sin(w * t), math.cos(w * t)
        return (c0 + tau * (c1 + c2 * tau) + self.s * sn + self.c * cs + ex,
                c1 + 2 * c2 * tau + w * (self.s * cs - self.c * sn) + exd)

    def integral(self, a: float, b: float) -> float:
        """int_a^b f dt in closed form."""
        if b <= a:
            return 0.0
        c0, c1, c2 = self.poly
        ta, tb = a - self.t0, b - self.t0
        w = self.omega
        out = c0 * (tb - ta) + c1 * (tb * tb - ta * ta) / 2 + c2 * (tb ** 3 - ta ** 3) / 3
        out += (self.s * (math.cos(w * a) - math.cos(w * b)) + self.c * (math.sin(w * b) - math.sin(w * a))) / w
        ex = np.exp(self.lam * ta) * np.expm1(self.lam * (tb - ta)) / self.lam
        return float(out + (ex @ self.beta).real)


@dataclass(frozen=True, eq=False)
class Piece:
    """One arc of the solution on [t0, t1]: its phase, initial state, and (contact) f_Nsc as an
    exponential sum."""

    contact: bool
    t0: float
    t1: float
    x0: np.ndarray
    force: ExpSum | None


_MAX_EVENTS_PER_PERIOD = 10_000


def advance(dyn: _FingerDynamics, t0: float, t1: float, x: np.ndarray, *, sensitivity: bool = True,
            contact: bool | None = None) -> tuple[list[Piece], np.ndarray, np.ndarray | None]:
    """Event-driven exact solution on [t0, t1]: pieces, final state, and (``sensitivity``) the
    monodromy d x(t1) / d x(t0): transition matrices of the arcs and saltation matrices
    ``S = I + (f_after - f_before) grad(h)^T / (dh/dt along f_before)`` of the switches.

    A switch that would leave a phase at the instant it began (a tangency) adds no piece: a flight
    of zero duration is no flight, and the contact continues without a new touchdown.
    """
    x = np.asarray(x, float).copy()
    if contact is None:
        contact = dyn.in_contact(t0, x)
    pieces: list[Piece] = []
    Phi = np.eye(7) if sensitivity else None
    t = t0
    horizon = 2 * math.pi / dyn.omega
    limit = _MAX_EVENTS_PER_PERIOD * max(1, round((t1 - t0) / horizon))
    switches = 0
    while True:
        if contact:
            x[6] = dyn.q_rest + float(dyn.plate(t)[0][0]) - x[0]  # the surface is on the plate
        fr = dyn.exit_sum(contact, t, x)
        a = t
        while True:
            b = min(a + horizon, t1)
            te = first_crossing(fr, a, b, dyn.step, upward=not contact)
            if te is not None or b >= t1:
                break
            a = b
        end = t1 if te is None else te
        if end > t or te is None:
            pieces.append(Piece(contact, t, end, x.copy(), fr if contact else None))
        if sensitivity:
            x_end, f_before = (v[0] for v in dyn.arc(contact, t, x)(end))
            Phi = dyn.transition(contact, end - t) @ Phi
        else:
            x_end = dyn.end_state(contact, t, x, end)
        if te is None:
            return pieces, x_end, Phi
        if sensitivity and end > t:
            f_after = dyn.arc(not contact, te, x_end)(te)[1][0]
            grad, h_t = _event_gradient(dyn, contact, te)
            rate = grad @ f_before + h_t
            if rate != 0:
                Phi = (np.eye(7) + np.outer(f_after - f_before, grad) / rate) @ Phi
        t, x, contact = te, x_end, not contact
        switches += 1
        if switches > limit:
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
