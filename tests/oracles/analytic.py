"""Closed-form and semi-analytic references for verification: beams, plates, piezoelectric bars and
the honeycomb tile's hand formulas (seed 002).

Every function states its source (textbook or paper, and the equation or section). SI units
throughout: lengths [m], moduli [Pa], densities [kg/m^3], masses [kg], forces [N]; frequencies
are returned in [Hz], angular frequencies are called ``omega`` [rad/s].

Transcendental equations are solved with ``scipy.optimize.brentq`` on brackets that are known
to hold exactly one root (cantilever, k31 bar, Rayleigh-Lamb), or found as sign changes on a
grid refined until it finds no new root (Timoshenko). The functions are written without poles
(entire functions of omega^2: cosh / sinh(x)/x pairs that turn into cos / sin(x)/x smoothly),
so every sign change is a root.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from modalfe.models.beam import cowper_shear_coefficient_rectangle
from modalfe.results.coupling import k_eff
from modalfe.scene.materials import piezo_compliance_form

__all__ = [
    "K31Bar",
    "cantilever_roots",
    "cowper_shear_coefficient_rectangle",
    "euler_bernoulli_cantilever",
    "k31_bar",
    "k_eff",
    "kirchhoff_plate_ss",
    "mindlin_plate_ss",
    "piezo_compliance_form",
    "rayleigh_lamb_plate_ss",
    "sandwich_plate_frequency",
    "sandwich_plate_wavenumber",
    "suspension_frequency",
    "suspension_static_deflection",
    "timoshenko_cantilever",
]

_XTOL = 1e-14  # brentq tolerance on dimensionless roots: far below any verification tolerance


# ---------------------------------------------------------------------------------------------
# root finding helpers


def _bracketed_roots(fun, grid: np.ndarray) -> list[float]:
    """All roots of ``fun`` bracketed by sign changes on ``grid``, refined with brentq."""
    values = np.array([fun(x) for x in grid])
    roots: list[float] = []
    for i in range(len(grid) - 1):
        a, b, fa, fb = grid[i], grid[i + 1], values[i], values[i + 1]
        if fa == 0.0:
            roots.append(float(a))
        elif fa * fb < 0:
            roots.append(float(brentq(fun, a, b, xtol=_XTOL * max(abs(a), abs(b), 1.0), rtol=1e-15)))
    return roots


def _cosh_and_sinhc(S: float) -> tuple[float, float]:
    """(cosh(sqrt S), sinh(sqrt S)/sqrt S) for any real S: (cos(sqrt -S), sin(sqrt -S)/sqrt -S) when
    S < 0. Both are entire functions of S, so determinants built from them have no poles."""
    if abs(S) < 1e-12:
        return 1.0 + S / 2, 1.0 + S / 6
    if S > 0:
        r = math.sqrt(S)
        return math.cosh(r), math.sinh(r) / r
    r = math.sqrt(-S)
    return math.cos(r), math.sin(r) / r


# ---------------------------------------------------------------------------------------------
# beams


def cantilever_roots(count: int) -> np.ndarray:
    """The first ``count`` roots beta_n L of the clamped-free beam equation 1 + cos(x) cosh(x) = 0.

    Blevins, Formulas for Natural Frequency and Mode Shape (1979), Table 8-1 (clamped-free:
    1.87510407, 4.69409113, 7.85475744, ...). Solved as cos(x) + 1/cosh(x) = 0 (same roots,
    bounded), bracketed between consecutive multiples of pi/2 around (2n - 1) pi / 2.
    """
    if count < 1:
        raise ValueError(f"count must be >= 1, got {count}")

    def f(x: float) -> float:
        return math.cos(x) + 1.0 / math.cosh(x)

    roots = []
    for n in range(1, count + 1):
        # the n-th root lies within pi/2 of (2n - 1) pi / 2, where cos changes sign
        centre = (2 * n - 1) * math.pi / 2
        a, b = max(centre - math.pi / 2, 1e-6), centre + math.pi / 2 - 1e-9
        roots.append(brentq(f, a, b, xtol=1e-15, rtol=1e-15))
    return np.array(roots)


def euler_bernoulli_cantilever(
    *, length: float, E: float, rho: float, area: float, inertia: float, count: int = 6
) -> np.ndarray:
    """Bending frequencies [Hz] of a uniform Euler-Bernoulli cantilever (clamped at one end).

    f_n = (beta_n L)^2 / (2 pi L^2) sqrt(E I / (rho A)); Blevins (1979), Table 8-1.
    length L [m], E [Pa], rho [kg/m^3], area A [m^2], inertia I [m^4] (second moment of area
    about the bending axis).
    """
    beta_l = cantilever_roots(count)
    return beta_l**2 / (2 * math.pi * length**2) * math.sqrt(E * inertia / (rho * area))


def timoshenko_cantilever(
    *,
    length: float,
    E: float,
    G: float,
    rho: float,
    area: float,
    inertia: float,
    kappa: float,
    count: int = 6,
) -> np.ndarray:
    """Bending frequencies [Hz] of a uniform Timoshenko cantilever (shear and rotary inertia).

    Equations of motion (Timoshenko, Phil. Mag. 41 (1921) 744-746; in the notation of Han,
    Benaroya & Wei, 'Dynamics of transversely vibrating beams using four engineering theories',
    J. Sound Vib. 225 (1999) 935-988), for deflection w and section rotation psi:

        kappa G A (w'' - psi') + rho A omega^2 w = 0
        E I psi'' + kappa G A (w' - psi) + rho I omega^2 psi = 0

    Solutions exp(s x) with S = s^2 roots of
    kappa G A E I S^2 + omega^2 (kappa G A rho I + rho A E I) S + rho A omega^2 (rho I omega^2 - kappa G A) = 0.
    For each root, two solutions (w, psi) = (C(x), r Sn(x)) and (S Sn(x), r C(x)), with
    C = cosh(sqrt(S) x), Sn = sinh(sqrt(S) x)/sqrt(S), r = S + rho A omega^2 / (kappa G A): entire
    in S, so they hold below and above the cut-off sqrt(kappa G A / (rho I)) alike. Clamped at
    x = 0 (w = psi = 0), free at x = L (psi' = 0, w' - psi = 0) leaves the 2 x 2 determinant

        D = (r1 C1 - r2 C2)(r2 C1 - r1 C2) - r1 r2 (S1 Sn1 - S2 Sn2)(Sn1 - Sn2)

    (evaluated at x = L), whose Euler-Bernoulli limit is -2 beta^4 (1 + cos(beta L) cosh(beta L)).
    Its roots are bracketed on a grid fine in sqrt(omega) (where cantilever roots are nearly
    evenly spaced) up to the Euler-Bernoulli frequency of mode ``count``, an upper bound of the
    Timoshenko one (min-max: Euler-Bernoulli is Timoshenko with psi = w' and without rotary
    inertia), and the grid is refined until doubling it finds no new root. Roots of the second
    spectrum above the cut-off are returned in order with the rest.

    length [m], E, G [Pa], rho [kg/m^3], area [m^2], inertia [m^4], kappa (shear coefficient).
    """
    L = length
    kGA, EI, rA, rI = kappa * G * area, E * inertia, rho * area, rho * inertia

    def determinant(omega: float) -> float:
        w2 = omega**2
        # dimensionless S~ = S L^2: S~^2 + b S~ + c = 0
        b = w2 * L**2 * (rI / EI + rA / kGA)
        c = rA * w2 * L**4 * (rI * w2 - kGA) / (kGA * EI)
        # b^2 - 4c = w^4 L^4 (rI/EI - rA/kGA)^2 + 4 rA w^2 L^4 / EI > 0: two distinct real roots
        # S, one negative (oscillating), the other positive below the cut-off
        disc = math.sqrt(b * b - 4 * c)
        q = -0.5 * (b + disc)
        S1, S2 = (c / q, q) if q != 0 else (0.0, 0.0)
        g = rA * w2 * L**2 / kGA
        r1, r2 = S1 + g, S2 + g
        C1, Sn1 = _cosh_and_sinhc(S1)
        C2, Sn2 = _cosh_and_sinhc(S2)
        D = (r1 * C1 - r2 * C2) * (r2 * C1 - r1 * C2) - r1 * r2 * (S1 * Sn1 - S2 * Sn2) * (Sn1 - Sn2)
        scale = math.cosh(math.sqrt(max(S1, 0.0))) ** 2 * max(1.0, abs(r1 * r2))
        return D / scale

    upper = 2 * math.pi * euler_bernoulli_cantilever(
        length=L, E=E, rho=rho, area=area, inertia=inertia, count=count)[-1] * (1 + 1e-9)
    # a grid twice as fine must find the same roots (no pair of close roots hidden in one cell)
    previous: list[float] = []
    for points in (200, 400, 800, 1600, 3200, 6400):
        grid = np.linspace(1e-6, math.sqrt(upper), points * count) ** 2
        roots = _bracketed_roots(determinant, grid)
        if len(roots) >= count and len(roots) == len(previous):
            return np.array(roots[:count]) / (2 * math.pi)
        previous = roots
    raise RuntimeError(f"timoshenko_cantilever: root count not stable ({len(roots)} for {count} asked)")


# ---------------------------------------------------------------------------------------------
# plates, simply supported on all four edges; mode (m, n): m half-waves along x (side a),
# n half-waves along y (side b)


def _wavenumber(m: int, n: int, a: float, b: float) -> float:
    if m < 1 or n < 1:
        raise ValueError(f"mode (m, n) needs m, n >= 1, got ({m}, {n})")
    return math.pi * math.hypot(m / a, n / b)


def kirchhoff_plate_ss(m: int, n: int, *, a: float, b: float, h: float, E: float, nu: float,
                       rho: float) -> float:
    """Frequency [Hz] of mode (m, n) of a simply supported rectangular Kirchhoff plate.

    omega = pi^2 ((m/a)^2 + (n/b)^2) sqrt(D / (rho h)), D = E h^3 / (12 (1 - nu^2));
    Leissa, Vibration of Plates, NASA SP-160 (1969), sec. 4.1 (SS-SS-SS-SS, Navier solution).
    a, b sides along x, y [m]; h thickness [m]; E [Pa]; rho [kg/m^3].
    """
    k = _wavenumber(m, n, a, b)
    D = E * h**3 / (12 * (1 - nu**2))
    return k**2 * math.sqrt(D / (rho * h)) / (2 * math.pi)


def mindlin_plate_ss(m: int, n: int, *, a: float, b: float, h: float, E: float, nu: float,
                     rho: float, shear_factor: float = math.pi**2 / 12) -> float:
    """Flexural frequency [Hz] of mode (m, n) of a simply supported rectangular Mindlin plate.

    Mindlin, 'Influence of rotatory inertia and shear on flexural motions of isotropic, elastic
    plates', J. Appl. Mech. 18 (1951) 31-38, with shear factor kappa^2 = pi^2/12 (matches the
    exact thickness-shear cut-off). With w = W sin(al x) sin(be y), psi_x = X cos(al x) sin(be y),
    psi_y = Y sin(al x) cos(be y), al = m pi / a, be = n pi / b (the Navier form, exact for
    simple supports), the equations of motion become (K - omega^2 M) [W, X, Y] = 0 with
    M = diag(rho h, rho h^3/12, rho h^3/12) and, with S = kappa^2 G h, D = E h^3 / (12 (1 - nu^2)),

        K = [[S (al^2 + be^2),  S al,                             S be                            ],
             [S al,             D (al^2 + (1-nu)/2 be^2) + S,     D (1+nu)/2 al be                ],
             [S be,             D (1+nu)/2 al be,                 D (be^2 + (1-nu)/2 al^2) + S    ]]

    the 3 x 3 form of Mindlin's cubic in omega^2. The lowest root is the flexural one; the other
    two are thickness-shear modes. a, b sides [m]; h thickness [m]; E [Pa]; rho [kg/m^3].
    """
    from scipy.linalg import eigh

    _wavenumber(m, n, a, b)
    al, be = m * math.pi / a, n * math.pi / b
    D = E * h**3 / (12 * (1 - nu**2))
    kGh = shear_factor * E / (2 * (1 + nu)) * h
    K = np.array([
        [kGh * (al**2 + be**2), kGh * al, kGh * be],
        [kGh * al, D * (al**2 + (1 - nu) / 2 * be**2) + kGh, D * (1 + nu) / 2 * al * be],
        [kGh * be, D * (1 + nu) / 2 * al * be, D * (be**2 + (1 - nu) / 2 * al**2) + kGh],
    ])
    M = np.diag([rho * h, rho * h**3 / 12, rho * h**3 / 12])
    lam = eigh(K, M, eigvals_only=True)
    return float(math.sqrt(lam[0]) / (2 * math.pi))


def rayleigh_lamb_plate_ss(m: int, n: int, *, a: float, b: float, h: float, E: float, nu: float,
                           rho: float) -> float:
    """Exact 3-D flexural frequency [Hz] of mode (m, n) of a rectangular plate on diaphragm supports.

    Diaphragm supports (at x = 0, a: u_y = u_z = 0, sigma_xx = 0; at y = 0, b: u_x = u_z = 0,
    sigma_yy = 0) admit the lowest antisymmetric Lamb wave of wavenumber
    k = pi sqrt((m/a)^2 + (n/b)^2) as a standing wave, exactly (Srinivas, Rao & Rao, J. Sound
    Vib. 12 (1970) 187-199). Its frequency is the root of the antisymmetric Rayleigh-Lamb
    equation (Graff, Wave Motion in Elastic Solids (1975), sec. 8.1.2), d = h/2:

        tan(q d) / tan(p d) = -(q^2 - k^2)^2 / (4 k^2 p q),
        p^2 = omega^2 / c_L^2 - k^2,  q^2 = omega^2 / c_T^2 - k^2.

    The flexural (A0) wave is slower than shear waves, so p and q are imaginary: with
    z_p = -(p d)^2, z_q = -(q d)^2 >= 0, T(z) = tanh(sqrt z)/sqrt z, Omega = omega d / c_T,
    K = (k d)^2 and g = c_T^2 / c_L^2 the equation reads (Q + K)^2 T(z_p) + 4 K Q (T(z_q) - T(z_p)) = 0,
    Q = -z_q. The spurious root omega = 0 (p = q) is divided out exactly, since Q + K = Omega^2 and
    z_p - z_q = (1 - g) Omega^2:

        G(Omega) = Omega^2 T(z_p) + 4 K z_q (1 - g) [T(z_q) - T(z_p)] / (z_q - z_p) = 0,

    with the divided difference summed from the Taylor series of T for thin plates (no
    cancellation). G < 0 at Omega = 0 and G > 0 at the shear-wave line Omega^2 = K, and A0 is
    the only wave below that line: one root, found by brentq.
    """
    k = _wavenumber(m, n, a, b)
    d = h / 2
    G = E / (2 * (1 + nu))
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    cT2 = G / rho
    g = G / (lam + 2 * G)
    K = (k * d) ** 2

    def residual(Omega: float) -> float:
        W = Omega**2
        zp, zq = K - g * W, K - W
        return W * _tanhc(zp) + 4 * K * zq * (1 - g) * _tanhc_divided_difference(zq, zp)

    Omega = brentq(residual, 0.0, math.sqrt(K), xtol=1e-16 * math.sqrt(K), rtol=1e-15)
    return Omega * math.sqrt(cT2) / d / (2 * math.pi)


_TANHC_TERMS = 48  # Taylor terms of tanh(x)/x used for z = x^2 <= 1: ratio 4/pi^2, error < 1e-18


@functools.cache
def _tanhc_coefficients() -> np.ndarray:
    """a_n with tanh(x)/x = sum_n a_n x^(2n), a_n = 2^(2n+2) (2^(2n+2) - 1) B_(2n+2) / (2n+2)!
    (Abramowitz & Stegun 4.5.64), with exact rational Bernoulli numbers from the recurrence
    sum_(j <= m) C(m+1, j) B_j = 0 (scipy's floating-point ones carry 1e-12 errors)."""
    from fractions import Fraction

    top = 2 * _TANHC_TERMS + 2
    B = [Fraction(1)]
    for m in range(1, top + 1):
        B.append(-sum(math.comb(m + 1, j) * B[j] for j in range(m)) / (m + 1))
    return np.array([float(4 ** (j + 1) * (4 ** (j + 1) - 1) * B[2 * j + 2] / math.factorial(2 * j + 2))
                     for j in range(_TANHC_TERMS)])


def _tanhc(z: float) -> float:
    """tanh(sqrt z)/sqrt z for z >= 0."""
    if z <= 1.0:
        return float(np.polyval(_tanhc_coefficients()[::-1], z))
    r = math.sqrt(z)
    return math.tanh(r) / r


def _tanhc_divided_difference(z1: float, z2: float) -> float:
    """(T(z1) - T(z2)) / (z1 - z2) for T = tanh(sqrt z)/sqrt z, z >= 0; T'(z1) when z1 = z2.
    Summed term by term (complete homogeneous polynomials) when both z <= 1, so thin plates
    lose no digits to cancellation."""
    if max(z1, z2) <= 1.0:
        a = _tanhc_coefficients()
        total, h_prev, p2 = 0.0, 1.0, 1.0  # h_j = sum_i z1^i z2^(j-i), h_0 = 1
        for j in range(1, _TANHC_TERMS):
            total += a[j] * h_prev
            p2 *= z2
            h_prev = z1 * h_prev + p2
        return total
    if z1 == z2:
        r = math.sqrt(z1)
        return (r / math.cosh(r) ** 2 - math.tanh(r)) / (2 * r**3)
    return (_tanhc(z1) - _tanhc(z2)) / (z1 - z2)


# ---------------------------------------------------------------------------------------------
# piezoelectric length-extensional bar (k31)


@dataclass(frozen=True)
class K31Bar:
    """Length-extensional bar poled and electroded through its thickness.

    fr : resonance (short circuit) [Hz]; fa : antiresonance (open circuit) [Hz];
    k31 : material coupling factor; k_eff : effective coupling from fr, fa;
    s11E [1/Pa], d31 [C/N], eps33T [F/m].
    """

    fr: float
    fa: float
    k31: float
    k_eff: float
    s11E: float
    d31: float
    eps33T: float


def k31_bar(*, length: float, c_E: np.ndarray, e: np.ndarray, eps_S: np.ndarray,
            rho: float) -> K31Bar:
    """fr and fa [Hz] of a thin piezoelectric bar of ``length`` [m] along x, poled along z (3),
    electrodes on the two z faces, free ends, lateral faces free (1-D, T1 only).

    IEEE Std 176-1987 (length-extensional bar with the field across its length; also Berlincourt,
    Curran & Jaffe, Physical Acoustics vol. 1A (1964), the k31 bar): admittance
    Y ~ 1 + k31^2/(1 - k31^2) tan(x)/x with x = omega L / (2 v), v = 1/sqrt(rho s11E), so

        fr = 1 / (2 L sqrt(rho s11E))                       (pole, x = pi/2)
        tan(x)/x = -(1 - k31^2)/k31^2,  fa = fr x / (pi/2)   (zero, pi/2 < x < pi)

    k31^2 = d31^2 / (s11E eps33T), constants from the e-form tensors by ``piezo_compliance_form``.
    c_E [Pa] (6, 6), e [C/m^2] (3, 6), eps_S [F/m] (3, 3), rho [kg/m^3].
    """
    s_E, d, eps_T = piezo_compliance_form(c_E, e, eps_S)
    s11, d31, eps33 = float(s_E[0, 0]), float(d[2, 0]), float(eps_T[2, 2])
    k2 = d31**2 / (s11 * eps33)
    fr = 1 / (2 * length * math.sqrt(rho * s11))

    def zero(x: float) -> float:  # k^2 sin x + (1 - k^2) x cos x: tan(x)/x = -(1-k^2)/k^2, no pole
        return k2 * math.sin(x) + (1 - k2) * x * math.cos(x)

    x = brentq(zero, math.pi / 2, math.pi, xtol=1e-15, rtol=1e-15)
    fa = fr * x / (math.pi / 2)
    return K31Bar(fr, fa, math.sqrt(k2), k_eff(fr, fa), s11, d31, eps33)


# ---------------------------------------------------------------------------------------------
# honeycomb floor tile hand formulas (seed 002)


def sandwich_plate_wavenumber(side: float) -> float:
    """Lowest wavenumber k = pi sqrt(2) / L [1/m] of a square plate of ``side`` L [m] simply
    supported on all edges (mode (1,1)), as used with seed 002 eq. (5) (seed 002, sec. 4.2.2)."""
    return math.pi * math.sqrt(2) / side


def sandwich_plate_frequency(*, k: float, E_f: float, t_f: float, h: float, rho: float) -> float:
    """Bending frequency [Hz] of a thin-faced sandwich plate, seed 002 eq. (5):

        f = k^2 / (2 pi) sqrt(E_f t_f h / (12 rho))

    k wavenumber [1/m]; E_f facing modulus [Pa]; t_f facing thickness [m]; h panel thickness [m];
    rho mean density of the whole panel [kg/m^3]. Valid for t_f << h (seed 002, sec. 4.2.2).
    """
    return k**2 / (2 * math.pi) * math.sqrt(E_f * t_f * h / (12 * rho))


def suspension_frequency(*, E: float, area: float, height: float, mass: float,
                         mounts: int = 4) -> float:
    """Heave frequency [Hz] of a rigid plate of ``mass`` M0 [kg] on ``mounts`` elastic blocks, each
    K = E A / h: f0 = (2 pi)^-1 sqrt(4 E A / (h M0)) for four mounts (seed 002, sec. 4.3).
    E [Pa]; area A [m^2]; height h [m]."""
    return math.sqrt(mounts * E * area / (height * mass)) / (2 * math.pi)


def suspension_static_deflection(*, force: float, E: float, area: float, height: float) -> float:
    """Static deflection [m] dz = F / K = F h / (E A) of one suspension element under ``force``
    F [N] (seed 002, sec. 4.3). E [Pa]; area A [m^2]; height h [m].

    Note: with the seed's numbers (F = 1000 N, E = 2 MPa, A = 8 cm^2, h = 2.5 cm) this gives
    15.6 mm for one element (3.9 mm if the four share the load), while the seed quotes 4.5 mm.
    """
    return force * height / (E * area)
