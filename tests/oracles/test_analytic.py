"""Unit tests of the closed-form references in tests.oracles.analytic: tabulated values, limits between
theories, and independent numerical solutions of the same equations."""

import math

import numpy as np
import pytest
from scipy.linalg import eig

from modalfe.scene.materials import EPS0, MATERIALS
from tests.oracles import analytic

# ciliary beam of seed 003 made uniform: 100 x 5 x 5 mm brass (materials "brass-seed003")
BRASS = {"E": 105e9, "nu": 0.34, "rho": 8500.0}
SIDE = 5e-3


def _beam(length: float, side: float = SIDE) -> dict:
    return {"length": length, "E": BRASS["E"], "rho": BRASS["rho"], "area": side**2,
            "inertia": side**4 / 12}


def _timoshenko_beam(length: float, side: float = SIDE) -> dict:
    nu = BRASS["nu"]
    return {**_beam(length, side), "G": BRASS["E"] / (2 * (1 + nu)),
            "kappa": analytic.cowper_shear_coefficient_rectangle(nu)}


# ---------------------------------------------------------------------------------------------
# Euler-Bernoulli cantilever


def test_cantilever_roots_match_blevins_table():
    # Blevins, Formulas for Natural Frequency and Mode Shape (1979), Table 8-1, clamped-free,
    # tabulated to 8 decimals: the roots must agree to the table's last digit
    table = [1.87510407, 4.69409113, 7.85475744, 10.99554073, 14.13716839]
    assert analytic.cantilever_roots(5) == pytest.approx(table, abs=6e-9)


def test_cantilever_roots_tend_to_odd_multiples_of_half_pi():
    # 1 + cos x cosh x = 0 -> cos x = -1/cosh x: beta_n L - (2n - 1) pi/2 ~ +-2 exp(-beta_n L)
    roots = analytic.cantilever_roots(12)
    n = np.arange(1, 13)
    gap = np.abs(roots - (2 * n - 1) * np.pi / 2)
    assert gap[5:] == pytest.approx(2 * np.exp(-roots[5:]), rel=1e-3)


def test_euler_bernoulli_frequency_scales_and_ratios():
    f = analytic.euler_bernoulli_cantilever(**_beam(0.1), count=3)
    # f2/f1 = (4.69409113/1.87510407)^2 = 6.26689 (Blevins Table 8-1)
    assert f[1] / f[0] == pytest.approx(6.266893, rel=1e-6)
    # f ~ 1/L^2 at fixed section
    assert analytic.euler_bernoulli_cantilever(**_beam(0.2), count=1)[0] == pytest.approx(f[0] / 4, rel=1e-12)
    # mode 1 of the 100 x 5 x 5 mm brass beam by hand: 1.87510407^2 / (2 pi 0.1^2) sqrt(E h^2 / (12 rho))
    hand = 1.87510407**2 / (2 * math.pi * 0.01) * math.sqrt(105e9 * 25e-6 / (12 * 8500.0))
    assert f[0] == pytest.approx(hand, rel=1e-8)


# ---------------------------------------------------------------------------------------------
# Timoshenko cantilever


def test_cowper_coefficient_values():
    # Cowper (1966), rectangle: 10(1+nu)/(12+11nu): 5/6 at nu = 0, 0.8497 at nu = 0.3
    assert analytic.cowper_shear_coefficient_rectangle(0.0) == pytest.approx(5 / 6, rel=1e-15)
    assert analytic.cowper_shear_coefficient_rectangle(0.3) == pytest.approx(13 / 15.3, rel=1e-15)


def test_timoshenko_tends_to_euler_bernoulli_for_slender_beams():
    for length in (1.0, 10.0):  # L/h = 200 and 2000
        eb = analytic.euler_bernoulli_cantilever(**_beam(length), count=6)
        tim = analytic.timoshenko_cantilever(**_timoshenko_beam(length), count=6)
        # the Timoshenko frequencies lie below (min-max: psi = w' is a constraint) and the
        # relative gap is O((beta_n h)^2): 1.5e-3 for mode 6 at L/h = 200
        assert np.all(tim < eb)
        assert np.all(np.abs(tim / eb - 1) < 2e-3 * (1.0 / length) ** 2)
    # the gap scales as (h/L)^2: ten times longer, a hundred times smaller (to O((h/L)^4))
    gap1 = 1 - analytic.timoshenko_cantilever(**_timoshenko_beam(1.0), count=6) / \
        analytic.euler_bernoulli_cantilever(**_beam(1.0), count=6)
    gap10 = 1 - analytic.timoshenko_cantilever(**_timoshenko_beam(10.0), count=6) / \
        analytic.euler_bernoulli_cantilever(**_beam(10.0), count=6)
    assert gap1 / gap10 == pytest.approx(100.0, rel=3e-3)


def _timoshenko_chebyshev(*, length, E, G, rho, area, inertia, kappa, count, points=32):
    """Independent solution: Chebyshev collocation (Trefethen, Spectral Methods in MATLAB (2000),
    ch. 6-7) of the same equations, made dimensionless with xi = x/L, v = w/L:
    v'' - psi' = -lam v,  s psi'' + v' - psi = -lam r psi,  lam = rho A omega^2 L^2 / (kappa G A),
    s = E I / (kappa G A L^2), r = I / (A L^2); a generalised eigenproblem."""
    N = points
    j = np.arange(N + 1)
    t = np.cos(np.pi * j / N)  # 1 .. -1
    c = np.where((j == 0) | (j == N), 2.0, 1.0) * (-1.0) ** j
    T = np.tile(t, (N + 1, 1)).T
    D = np.outer(c, 1 / c) / (T - T.T + np.eye(N + 1))
    D -= np.diag(D.sum(axis=1))
    D1 = -2 * D  # d/dxi with xi = (1 - t)/2 in [0, 1]
    D2 = D1 @ D1
    s = E * inertia / (kappa * G * area * length**2)
    r = inertia / (area * length**2)
    n = N + 1
    I = np.eye(n)
    Z = np.zeros((n, n))
    K = np.block([[-D2, D1], [-D1, -s * D2 + I]])
    M = np.block([[I, Z], [Z, r * I]])
    root, tip = N, 0  # xi = 0 at t = -1, xi = 1 at t = 1
    rows = {  # boundary rows replace the equations at the end points
        root: np.concatenate([I[root], np.zeros(n)]),  # w(0) = 0
        tip: np.concatenate([D1[tip], -I[tip]]),  # w'(L) - psi(L) = 0
        n + root: np.concatenate([np.zeros(n), I[root]]),  # psi(0) = 0
        n + tip: np.concatenate([np.zeros(n), D1[tip]]),  # psi'(L) = 0
    }
    for row, values in rows.items():
        K[row] = values
        M[row] = 0.0
    lam = eig(K, M, right=False)
    lam = np.sort(lam[np.isfinite(lam) & (np.abs(lam.imag) < 1e-6 * np.abs(lam))].real)
    lam = lam[lam > 0]
    omega = np.sqrt(lam[:count] * kappa * G * area / (rho * area * length**2))
    return omega / (2 * np.pi)


@pytest.mark.parametrize("length", [0.1, 0.025, 0.01])
def test_timoshenko_determinant_matches_spectral_collocation(length):
    # L/h = 20 (the ciliary beam), 5, and 2 (modes 4-8 above the shear cut-off of 218 kHz, in
    # the second spectrum). 32-point Chebyshev collocation converges exponentially; its
    # round-off (measured by varying the points, 24-40) stays below 1e-9, so 1e-8 tests the
    # determinant and its root bracketing, not the collocation
    beam = _timoshenko_beam(length)
    reference = _timoshenko_chebyshev(**beam, count=8)
    assert analytic.timoshenko_cantilever(**beam, count=8) == pytest.approx(reference, rel=1e-8)


def test_timoshenko_mode6_of_the_ciliary_beam():
    # seed 003's 24,221 Hz is Euler-Bernoulli theory; for the uniform 100 x 5 x 5 mm brass beam
    # EB gives 24105 Hz, shear and rotary inertia lower mode 6 by 11.6 % (h/wavelength ~ 0.14)
    eb = analytic.euler_bernoulli_cantilever(**_beam(0.1), count=6)[5]
    tim = analytic.timoshenko_cantilever(**_timoshenko_beam(0.1), count=6)[5]
    assert eb == pytest.approx(24105.1, rel=1e-5)
    assert tim == pytest.approx(21320.2, rel=1e-5)


# ---------------------------------------------------------------------------------------------
# simply supported plates


PLATE = {"E": 123e9, "nu": 0.3, "rho": 8250.0}  # CuBe (seed 001)


def test_kirchhoff_plate_formula_by_hand():
    # square steel-like plate: omega_11 = 2 pi^2 / a^2 sqrt(D / (rho h)) (Leissa 1969, sec. 4.1)
    a, h = 0.1, 1e-3
    D = PLATE["E"] * h**3 / (12 * (1 - PLATE["nu"] ** 2))
    hand = 2 * math.pi**2 / a**2 * math.sqrt(D / (PLATE["rho"] * h)) / (2 * math.pi)
    assert analytic.kirchhoff_plate_ss(1, 1, a=a, b=a, h=h, **PLATE) == pytest.approx(hand, rel=1e-14)
    # f_mn ~ (m/a)^2 + (n/b)^2: (2,1) of a square = 5/2 (1,1)
    assert analytic.kirchhoff_plate_ss(2, 1, a=a, b=a, h=h, **PLATE) == pytest.approx(2.5 * hand, rel=1e-14)


@pytest.mark.parametrize("mn", [(1, 1), (2, 1), (1, 3), (3, 2)])
def test_mindlin_and_exact_tend_to_kirchhoff_for_thin_plates(mn):
    a, b = 0.04, 0.03
    nu = PLATE["nu"]
    for h in (1e-4, 1e-5):
        kirchhoff = analytic.kirchhoff_plate_ss(*mn, a=a, b=b, h=h, **PLATE)
        mindlin = analytic.mindlin_plate_ss(*mn, a=a, b=b, h=h, **PLATE)
        exact = analytic.rayleigh_lamb_plate_ss(*mn, a=a, b=b, h=h, **PLATE)
        kh = math.pi * math.hypot(mn[0] / a, mn[1] / b) * h
        # leading-order corrections f / f_K = 1 - C (kh)^2 + O((kh)^4):
        # Mindlin: C = (1 + 2 / (kappa^2 (1 - nu))) / 24, kappa^2 = pi^2/12 (its 3 x 3 system
        # expanded in kh, like a Timoshenko beam with modulus E/(1-nu^2) and shear kappa^2 G);
        # exact 3-D: C = (17 - 7 nu) / (120 (1 - nu)) (the antisymmetric Rayleigh-Lamb equation
        # expanded in kh; derived for this test by series expansion, Omega^2 = (4/3)(1-g) K^2
        # (1 + (4g/3 - 9/5) K), K = (kh/2)^2, g = c_T^2/c_L^2). kh <= 0.04 here, so the
        # O((kh)^4) remainder is < 1e-3 of the correction: 0.5 % tolerance
        c_mindlin = (1 + 2 / (math.pi**2 / 12 * (1 - nu))) / 24
        c_exact = (17 - 7 * nu) / (120 * (1 - nu))
        assert (kirchhoff - mindlin) / kirchhoff == pytest.approx(c_mindlin * kh**2, rel=5e-3)
        assert (kirchhoff - exact) / kirchhoff == pytest.approx(c_exact * kh**2, rel=5e-3)


@pytest.mark.parametrize("h", [0.5e-3, 1e-3, 1.8e-3])
def test_mindlin_close_to_exact_3d(h):
    # Mindlin (1951) with kappa^2 = pi^2/12 is accurate for kh up to ~1: within 1 % of the exact
    # Lamb-wave frequency for these modes (kh = 0.13 .. 0.94; measured 0.61 % at kh = 0.94),
    # while Kirchhoff is up to 15 % off at the thickest
    a, b = 0.02, 0.015
    for mn in [(1, 1), (2, 1), (1, 2), (2, 2)]:
        mindlin = analytic.mindlin_plate_ss(*mn, a=a, b=b, h=h, **PLATE)
        exact = analytic.rayleigh_lamb_plate_ss(*mn, a=a, b=b, h=h, **PLATE)
        assert mindlin == pytest.approx(exact, rel=0.01), mn
        # Mindlin lies below: its leading correction 0.186 (kh)^2 exceeds the exact 0.177 (kh)^2
        assert mindlin < exact, mn


def test_exact_3d_plate_is_the_rayleigh_lamb_root():
    # substitute the returned frequency into the textbook form of the antisymmetric equation
    # (Graff 1975, sec. 8.1.2), written with real hyperbolic functions below the shear-wave line
    a, b, h = 0.02, 0.016, 2e-3
    f = analytic.rayleigh_lamb_plate_ss(2, 1, a=a, b=b, h=h, **PLATE)
    E, nu, rho = PLATE["E"], PLATE["nu"], PLATE["rho"]
    G = E / (2 * (1 + nu))
    cL = math.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / rho)
    cT = math.sqrt(G / rho)
    k = math.pi * math.hypot(2 / a, 1 / b)
    w = 2 * math.pi * f
    p, q, d = math.sqrt(k**2 - (w / cL) ** 2), math.sqrt(k**2 - (w / cT) ** 2), h / 2
    lhs = math.tanh(q * d) / math.tanh(p * d)
    rhs = (k**2 + q**2) ** 2 / (4 * k**2 * p * q)
    assert lhs == pytest.approx(rhs, rel=1e-12)
    # A0 is slower than the Rayleigh wave: cR/cT = 0.9274 at nu = 0.3 (Graff 1975, sec. 6.3)
    assert w / k < 0.9274 * cT


def test_plate_rejects_mode_zero():
    with pytest.raises(ValueError, match="m, n >= 1"):
        analytic.kirchhoff_plate_ss(0, 1, a=1.0, b=1.0, h=0.01, **PLATE)


# ---------------------------------------------------------------------------------------------
# piezoelectric k31 bar


@pytest.mark.parametrize("name, s11E, d31, eps33T_rel, k31", [
    # compliance-form data of the same source as the e-form tensors (Berlincourt, Curran & Jaffe
    # 1964, in Sherman & Butler 2007, App. A.5): s11E [1e-12 m^2/N], d31 [1e-12 C/N], eps33T/eps0
    ("PZT-5A", 16.4, -171.0, 1700.0, 0.34),
    ("PZT-4", 12.3, -123.0, 1300.0, 0.33),
])
def test_compliance_form_matches_published_constants(name, s11E, d31, eps33T_rel, k31):
    mat = MATERIALS[name]
    s, d, epsT = analytic.piezo_compliance_form(mat.C, mat.e, mat.eps_S)
    assert s @ mat.C == pytest.approx(np.eye(6), abs=1e-12)
    # both published sets are rounded to 3 digits and were fitted separately: they agree to
    # ~2 % (eps33T of PZT-4: 1277 from the e-form vs 1300 listed), so 2.5 %
    assert s[0, 0] == pytest.approx(s11E * 1e-12, rel=0.025)
    assert d[2, 0] == pytest.approx(d31 * 1e-12, rel=0.025)
    assert epsT[2, 2] / EPS0 == pytest.approx(eps33T_rel, rel=0.025)
    bar = analytic.k31_bar(length=0.03, c_E=mat.C, e=mat.e, eps_S=mat.eps_S, rho=mat.rho)
    # k31 is listed to 2 digits: +-0.005 absolute
    assert bar.k31 == pytest.approx(k31, abs=0.006)


@pytest.mark.parametrize("name, N1", [("PZT-5A", 1400.0), ("PZT-4", 1650.0)])
def test_k31_bar_frequency_constant(name, N1):
    # frequency constant N1 = fr L [Hz m] of a thin bar (Berlincourt, Krueger & Near, Morgan
    # Electro Ceramics TP-226): listed to 2-3 digits, and s11E from the e-form differs by up
    # to 1 % from the listed one (test above): 1.5 %
    mat = MATERIALS[name]
    bar = analytic.k31_bar(length=0.03, c_E=mat.C, e=mat.e, eps_S=mat.eps_S, rho=mat.rho)
    assert bar.fr * 0.03 == pytest.approx(N1, rel=0.015)
    assert bar.fr == pytest.approx(1 / (2 * 0.03 * math.sqrt(mat.rho * bar.s11E)), rel=1e-14)


@pytest.mark.parametrize("name", ["PZT-5A", "PZT-4", "PZT-5H"])
def test_k31_antiresonance_satisfies_ieee_form(name):
    # the same root, written as in IEEE Std 176 for the k31 bar:
    # k31^2 / (1 - k31^2) = (pi/2)(fa/fr) tan((pi/2)(fa - fr)/fr)
    mat = MATERIALS[name]
    bar = analytic.k31_bar(length=0.03, c_E=mat.C, e=mat.e, eps_S=mat.eps_S, rho=mat.rho)
    lhs = bar.k31**2 / (1 - bar.k31**2)
    rhs = math.pi / 2 * bar.fa / bar.fr * math.tan(math.pi / 2 * (bar.fa - bar.fr) / bar.fr)
    assert lhs == pytest.approx(rhs, rel=1e-12)
    assert bar.fr < bar.fa < 2 * bar.fr
    assert bar.k_eff == pytest.approx(math.sqrt(1 - (bar.fr / bar.fa) ** 2), rel=1e-14)
    assert bar.k_eff < bar.k31


def test_k_eff_of_a_weakly_coupled_bar():
    # weak coupling: k_eff^2 -> (8/pi^2) k31^2 for the fundamental (the modal share of the
    # uniform field, sum 8/((2n-1)^2 pi^2) over modes = 1); error O(k31^2) ~ 1e-7 here
    mat = MATERIALS["PZT-5A"]
    bar = analytic.k31_bar(length=0.03, c_E=mat.C, e=1e-3 * mat.e, eps_S=mat.eps_S, rho=mat.rho)
    assert bar.k_eff**2 / bar.k31**2 == pytest.approx(8 / math.pi**2, rel=1e-5)
    assert analytic.k_eff(100.0, 125.0) == pytest.approx(0.6, rel=1e-14)


# ---------------------------------------------------------------------------------------------
# honeycomb tile hand formulas (seed 002)


def test_sandwich_formula_against_the_seed():
    # seed 002, eq. (5) with its stated inputs (L = 30.4 cm, h = 2.5 cm, t_f = 0.083 cm,
    # E_f = 60 GPa, rho = 170 kg/m^3) gives 839.8 Hz; the seed quotes 845 Hz, which the 2.54 cm
    # panel thickness (seed sec. 3.1) reproduces (846.5 Hz): 1 % covers the rounding of inputs
    k = analytic.sandwich_plate_wavenumber(0.304)
    f = analytic.sandwich_plate_frequency(k=k, E_f=60e9, t_f=0.083e-2, h=0.025, rho=170.0)
    assert f == pytest.approx(839.79, rel=1e-4)
    assert f == pytest.approx(845.0, rel=0.01)
    f_254 = analytic.sandwich_plate_frequency(k=k, E_f=60e9, t_f=0.083e-2, h=0.0254, rho=170.0)
    assert f_254 == pytest.approx(845.0, rel=0.003)
    # k = pi sqrt(2)/L is the (1,1) wavenumber of the SS square plate
    assert k == pytest.approx(math.pi * math.hypot(1 / 0.304, 1 / 0.304), rel=1e-15)


def test_suspension_formulas_against_the_seed():
    # seed 002 sec. 4.3: E = 2 MPa, A = 8 cm^2, h = 2.5 cm, M0 = 2.7 kg -> f0 ~ 49 Hz (the seed
    # rounds to 2 digits: 0.2 %)
    f0 = analytic.suspension_frequency(E=2.0e6, area=8e-4, height=0.025, mass=2.7)
    assert f0 == pytest.approx(49.0, rel=2e-3)
    assert f0 == pytest.approx(math.sqrt(4 * 2.0e6 * 8e-4 / (0.025 * 2.7)) / (2 * math.pi), rel=1e-14)
    # dz = F h / (E A) as the seed writes it: 15.6 mm for one mount at 1000 N (the seed's quoted
    # 4.5 mm matches neither one mount nor four sharing the load, 3.9 mm)
    dz = analytic.suspension_static_deflection(force=1000.0, E=2.0e6, area=8e-4, height=0.025)
    assert dz == pytest.approx(0.015625, rel=1e-14)
