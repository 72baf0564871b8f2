"""Verification of the 3-D solid model (quadratic serendipity hexahedra) against analytic theory:
cantilever vs Euler-Bernoulli and Timoshenko, diaphragm-supported plates vs Kirchhoff, Mindlin
and the exact 3-D (Rayleigh-Lamb) solution, a k31 piezoelectric bar vs the IEEE 1-D formulas,
the observed convergence order, and invariance under a rotation of the whole model.

Each tolerance is justified next to its assertion by the model error of the theory (how far the
theory itself is from the 3-D problem) plus the discretization error at the mesh used (measured
by refinement: the numbers quoted come from ``python studies/verification.py``, which prints
every case at two or three mesh sizes, and from the slow tests here).
"""

import functools
import math

import numpy as np
import pytest

from modalfe.scene.materials import MATERIALS
from modalfe.solve.api import solve_modes
from tests.oracles import analytic
from tests.oracles.cases import cantilever_scene, diaphragm_plate_scene, k31_bar_scene

# ---------------------------------------------------------------------------------------------
# scenes: every mesh is sized by max_size alone (one element per wavelength never binds), so
# the element counts below are exact and refinement by size_factor is uniform


CUBE = {"E": 123e9, "nu": 0.30, "rho": 8250.0}  # modalfe.scene.materials "CuBe" (seed 001)
BRASS = {"E": 105e9, "nu": 0.34, "rho": 8500.0}  # modalfe.scene.materials "brass-seed003" (seed 003)
THIN = (0.040, 0.030, 0.5e-3)  # h/a = 0.0125
THICK = (0.020, 0.016, 2.0e-3)  # h/a = 0.1
CONVERGENCE = (0.012, 0.010, 2.0e-3)  # 6 x 5 x 1 elements of 2 mm, then halved twice
PLATE_MODES = [(1, 1), (2, 1), (1, 2), (2, 2), (3, 1)]

# a generic rotation (Euler z-y-x 37, -23, 61 degrees), no symmetry of the boxes survives it
_z, _y, _x = np.radians([37.0, -23.0, 61.0])
ROTATION = (
    np.array([[np.cos(_z), -np.sin(_z), 0], [np.sin(_z), np.cos(_z), 0], [0, 0, 1]])
    @ np.array([[np.cos(_y), 0, np.sin(_y)], [0, 1, 0], [-np.sin(_y), 0, np.cos(_y)]])
    @ np.array([[1, 0, 0], [0, np.cos(_x), -np.sin(_x)], [0, np.sin(_x), np.cos(_x)]])
)


def plate_label(m: int, n: int) -> str:
    """modalfe's label of SS mode (m, n): m - 1 nodal lines across x, n - 1 along x."""
    return f"({n - 1},{m - 1})"


def bending(modes, order: int, near: float):
    """Bending mode ``order`` of a square-section beam: y and z bending are degenerate, so the
    solver may return either (or a mix labelled by its larger part)."""
    found = [m for m in modes if m.label in (f"bending-z {order}", f"bending-y {order}")]
    assert found, f"no bending mode {order} among {[m.label for m in modes]}"
    return min(found, key=lambda m: abs(m.frequency - near))


def axial(modes, near: float):
    """The extensional mode nearest ``near`` [Hz] (a free-free bar's first is labelled axial 2)."""
    found = [m for m in modes if m.label.startswith("axial")]
    assert found, f"no axial mode among {[m.label for m in modes]}"
    return min(found, key=lambda m: abs(m.frequency - near))


@functools.cache
def cantilever_modes(max_size: float, rotated: bool = False):
    return solve_modes(cantilever_scene(max_size), error_estimate=False,
                       frame=ROTATION if rotated else None)


@functools.cache
def plate_modes(dims: tuple, max_size: float, size_factor: float = 1.0):
    a, b, h = dims
    near = 0.5 * (analytic.rayleigh_lamb_plate_ss(1, 1, a=a, b=b, h=h, **CUBE)
                  + analytic.rayleigh_lamb_plate_ss(2, 2, a=a, b=b, h=h, **CUBE))
    return solve_modes(diaphragm_plate_scene(a, b, h, max_size), near=near, count=10,
                       error_estimate=False, size_factor=size_factor)


@functools.cache
def bar_modes(circuit: str, rotated: bool = False):
    return solve_modes(k31_bar_scene(1.0e-3), circuit=circuit, error_estimate=False,
                       frame=ROTATION if rotated else None)


def timoshenko_reference(count: int = 6) -> np.ndarray:
    E, nu, rho = BRASS["E"], BRASS["nu"], BRASS["rho"]
    return analytic.timoshenko_cantilever(
        length=0.1, E=E, G=E / (2 * (1 + nu)), rho=rho, area=25e-6, inertia=5e-3**4 / 12,
        kappa=analytic.cowper_shear_coefficient_rectangle(nu), count=count)


def euler_bernoulli_reference(count: int = 6) -> np.ndarray:
    return analytic.euler_bernoulli_cantilever(
        length=0.1, E=BRASS["E"], rho=BRASS["rho"], area=25e-6, inertia=5e-3**4 / 12, count=count)


def k31_reference():
    mat = MATERIALS["PZT-5A"]
    return analytic.k31_bar(length=0.03, c_E=mat.C, e=mat.e, eps_S=mat.eps_S, rho=mat.rho)


# ---------------------------------------------------------------------------------------------
# cantilever beam


def test_cantilever_matches_timoshenko_within_one_percent():
    modes = cantilever_modes(2.5e-3)
    assert modes.model.mesh.nelements == 40 * 2 * 2
    tim = timoshenko_reference()
    fe = np.array([bending(modes, n, tim[n - 1]).frequency for n in range(1, 7)])
    # issue 3: the 3-D solid of the uniform beam must agree with Timoshenko (Cowper's kappa)
    # within 1 %. Model difference of the converged 3-D solid: +0.31 % (mode 1) to +0.44 %
    # (mode 6): the 3-D clamp also stops the root section's Poisson contraction and warping,
    # and Cowper's kappa is itself approximate (146,880 DOFs, slow test below; the excess is
    # nearly uniform over the modes, as a root effect is). Discretization at this 2 x 2 x 40
    # mesh adds +0.15 % to +0.25 % (same refinement). Sum <= 0.7 %: 1 % holds with margin and
    # still catches a missing shear or rotary-inertia effect (together 13 % at mode 6)
    assert fe == pytest.approx(tim, rel=0.01)
    # seed 003's 24,221 Hz for mode 6 is Euler-Bernoulli (24,105 Hz for this uniform beam):
    # shear and rotary inertia make it >= 10 % too high (Timoshenko: 11.6 %)
    eb = euler_bernoulli_reference()
    assert fe[5] < 0.92 * eb[5]


def test_clamp_grading_halves_the_ciliary_beam_error_at_the_clamp():
    from modalfe.scene import load_scene
    from modalfe.solve.levels import solve_level

    # reference 21,541 +- 1.5 Hz: bending-z 6 of the short-circuited ciliary beam on meshes graded
    # toward the clamp and the sheet ends, 102k and 167k DOFs (21,542.9 and 21,542.0 Hz) extrapolated
    # at orders 2 to 4 (session log in docs/benchmark_peer.md); its uncertainty (0.007 %) is small
    # beside the errors compared here (0.1-0.3 %)
    reference = 21541.0
    errors = {}
    for layers in (0, 4):
        scene = load_scene("ciliary_beam", **{"mesh.clamp_grading": layers, "analysis.near": 21.7e3})
        modes = solve_level(scene, scene.analysis, size_factor=2 / 3, solver="auto")
        errors[layers] = modes.labelled("bending-z 6").frequency / reference - 1
    # conforming elements converge from above, graded or not
    assert errors[0] > 0 and errors[4] > 0
    # the clamp's singular edges dominate the uniform mesh's error: measured 0.30 % uniform, 0.13 %
    # graded at this size; at least halved, with margin for the reference's uncertainty
    assert errors[4] < 0.5 * errors[0]


def test_cantilever_mode1_matches_euler_bernoulli():
    modes = cantilever_modes(2.5e-3)
    eb = euler_bernoulli_reference()
    fe = bending(modes, 1, eb[0]).frequency
    # slender limit (L/h = 20, mode 1: h / wavelength = 0.015): Euler-Bernoulli's model error is
    # the Timoshenko correction -0.20 %, the 3-D root restraint adds +0.31 %, discretization at
    # this mesh +0.15 %: |FE/EB - 1| <= 0.5 % (measured +0.26 %)
    assert fe == pytest.approx(eb[0], rel=0.005)


@pytest.mark.slow
def test_cantilever_refined_converges_to_timoshenko():
    tim = timoshenko_reference()
    levels = [cantilever_modes(1.25e-3), cantilever_modes(0.625e-3)]
    fe = [np.array([bending(m, n, tim[n - 1]).frequency for n in range(1, 7)]) for m in levels]
    # the edges of the clamped face are singular in 3-D elasticity, so convergence is ~h^2
    # here, not h^4 (measured change ratio 4.4 between the last two halvings): the last
    # refinement (21,600 -> 146,880 DOFs) changed the frequencies by 0.04-0.05 %, so the finest
    # mesh is within ~0.02 % of the 3-D limit; 0.1 % bounds the change
    assert fe[1] == pytest.approx(fe[0], rel=1e-3)
    # converged 3-D vs Timoshenko: +0.31 % .. +0.44 % (clamp restraint, see above): 0.5 %
    assert fe[1] == pytest.approx(tim, rel=0.005)


# ---------------------------------------------------------------------------------------------
# simply supported (diaphragm) plates


def _plate_references(dims):
    a, b, h = dims
    out = {}
    for mn in PLATE_MODES:
        out[mn] = {
            "kirchhoff": analytic.kirchhoff_plate_ss(*mn, a=a, b=b, h=h, **CUBE),
            "mindlin": analytic.mindlin_plate_ss(*mn, a=a, b=b, h=h, **CUBE),
            "exact": analytic.rayleigh_lamb_plate_ss(*mn, a=a, b=b, h=h, **CUBE),
        }
    return out


def test_thin_plate_matches_kirchhoff():
    modes = plate_modes(THIN, THIN[0] / 24)
    assert modes.model.mesh.nelements == 24 * 18 * 1
    for mn, ref in _plate_references(THIN).items():
        fe = modes.labelled(plate_label(*mn), near=ref["exact"]).frequency
        # conforming elements with exact integration bound the exact 3-D frequency from above
        # (min-max); at 24 x 18 x 1 elements the excess is 0.04 % (1,1) .. 0.25 % (3,1)
        # (halving the in-plane size divides it by 3.7-5.5, slow test below)
        assert ref["exact"] * (1 - 1e-9) <= fe <= ref["exact"] * 1.003, mn
        # Kirchhoff (h/a = 0.0125, kh <= 0.13) overestimates the exact frequency by 0.08 % (1,1)
        # .. 0.30 % (2,2) (shear and rotary inertia, Rayleigh-Lamb): FE and Kirchhoff both lie
        # above the exact value, so |FE/K - 1| <= max of the two excesses <= 0.30 %: 0.35 %
        assert fe == pytest.approx(ref["kirchhoff"], rel=0.0035), mn


def test_thick_plate_matches_mindlin():
    modes = plate_modes(THICK, 2e-3, 0.5)
    assert modes.model.mesh.nelements == 20 * 16 * 2
    for mn, ref in _plate_references(THICK).items():
        fe = modes.labelled(plate_label(*mn), near=ref["exact"]).frequency
        # 20 x 16 x 2 elements: 0.03 % (1,1) .. 0.11 % (3,1) above the exact 3-D value (a
        # uniform halving, 71,943 DOFs, leaves 1/16 of this: 0.002 .. 0.007 %)
        assert ref["exact"] * (1 - 1e-9) <= fe <= ref["exact"] * 1.0015, mn
        # Mindlin (kappa^2 = pi^2/12) at h/a = 0.1 (kh = 0.5 .. 1.0) lies 0.21 % (1,1) ..
        # 0.68 % (3,1) below the exact 3-D value; with the FE excess, |FE/M - 1| <= 0.8 %: 1 %.
        # Kirchhoff is 4-16 % off here, so this separates the thick-plate theories
        assert fe == pytest.approx(ref["mindlin"], rel=0.01), mn
        assert abs(fe / ref["kirchhoff"] - 1) > 0.03, mn


@pytest.mark.slow
def test_thin_plate_refined_converges_to_exact_3d():
    modes = plate_modes(THIN, THIN[0] / 48)
    assert modes.model.mesh.nelements == 48 * 36 * 1
    for mn, ref in _plate_references(THIN).items():
        fe = modes.labelled(plate_label(*mn), near=ref["exact"]).frequency
        # half the in-plane size (still one layer through the 0.5 mm): the 0.04-0.25 % excess
        # drops 3.7-5.5x, to 0.010 % (1,1) .. 0.048 % (3,1); the single layer sets the floor
        # (two layers give 0.003-0.021 %); 0.06 %
        assert ref["exact"] * (1 - 1e-9) <= fe <= ref["exact"] * 1.0006, mn
        assert fe == pytest.approx(ref["kirchhoff"], rel=0.0035), mn


# ---------------------------------------------------------------------------------------------
# observed convergence order


def _observed_orders(size_factors):
    refs = _plate_references(CONVERGENCE)
    errors = []
    for sf in size_factors:
        modes = plate_modes(CONVERGENCE, 2e-3, sf)
        assert modes.model.mesh.nelements == round(30 / sf**3)  # 6 x 5 x 1 at size factor 1
        errors.append([modes.labelled(plate_label(*mn), near=refs[mn]["exact"]).frequency
                       / refs[mn]["exact"] - 1 for mn in [(1, 1), (2, 1)]])
    errors = np.array(errors)
    assert np.all(errors > 0)  # upper bounds (min-max), so the errors have one sign
    return np.log(errors[:-1] / errors[1:]) / np.log(2.0)


def test_observed_convergence_order_of_quadratic_elements():
    # uniform refinement (h, h/2, h/4 in every direction: 572 / 3,779 / 26,735 DOFs) of a
    # 12 x 10 x 2 mm diaphragm plate, against its exact 3-D frequency (Rayleigh-Lamb, to 1e-14):
    # the mode is analytic (sin/cos in x, y, hyperbolic in z), so the eigenvalue error of p = 2
    # elements is O(h^(2p)) = O(h^4) (Strang & Fix, An Analysis of the Finite Element Method
    # (1973), ch. 6). The coarsest level has 6 x 5 x 1 elements (pre-asymptotic: measured
    # 3.74-3.86 for the first pair, 3.93-3.97 for the second); [3.5, 4.5] and then [3.8, 4.2]
    # exclude the rate 2 of linear elements or of an inconsistent mass matrix
    orders = _observed_orders([1.0, 0.5, 0.25])
    assert np.all((orders[0] > 3.5) & (orders[0] < 4.5)), orders
    assert np.all((orders[1] > 3.8) & (orders[1] < 4.2)), orders


# ---------------------------------------------------------------------------------------------
# piezoelectric k31 bar


def _rayleigh_lateral_inertia() -> float:
    """Relative frequency shift -k^2 (nu12^2 w^2 + nu13^2 t^2) / 24 of a bar's first extensional
    mode from the kinetic energy of its Poisson contraction (Rayleigh, The Theory of Sound,
    vol. 1 (1894), sec. 157), nu1j = -s1j^E / s11^E, k = pi / L."""
    s = np.linalg.inv(MATERIALS["PZT-5A"].C)
    nu12, nu13 = -s[0, 1] / s[0, 0], -s[0, 2] / s[0, 0]
    k = math.pi / 30e-3
    return -(k**2) * (nu12**2 * 2e-3**2 + nu13**2 * 1e-3**2) / 24


def test_k31_bar_resonance_and_antiresonance():
    ref = k31_reference()
    short, open_ = bar_modes("short"), bar_modes("open")
    assert short.model.mesh.nelements == 30 * 2 * 2
    fr = axial(short, ref.fr).frequency
    fa = axial(open_, ref.fa).frequency
    # 1-D theory (IEEE Std 176) assumes T1 only: its model error is the lateral inertia of the
    # Poisson contraction, -(nu pi r / L)^2 / 2 ~ -3.1e-4 here (r^2 = (w^2 + t^2)/12), plus
    # O((w/L)^4) end effects; the mesh is converged (half the size changes fr by 1.4e-7).
    # Issue 3 asks for 0.5 %, which bounds these by a factor of 10
    assert fr == pytest.approx(ref.fr, rel=0.005)
    assert fa == pytest.approx(ref.fa, rel=0.005)
    # sharper: the short-circuit difference is Rayleigh's lateral-inertia correction (measured
    # -3.122e-4 vs -3.116e-4); its next order is O((k r)^4) ~ 1e-7 and the piezo field's own
    # lateral variation is second order too: 10 % of the correction (3e-5)
    correction = _rayleigh_lateral_inertia()
    assert fr / ref.fr - 1 == pytest.approx(correction, abs=0.1 * abs(correction))
    # k_eff^2 = 1 - (fr/fa)^2: a relative error d of fa/fr becomes (1 - k^2)/k^2 d ~ 9.4 d in
    # k_eff; fa/fr differs from 1-D by 1.7e-4 (the open-circuit Poisson ratios differ), so
    # k_eff by 0.16 %: 1 % allows fa/fr to be off by 1e-3 at most
    assert analytic.k_eff(fr, fa) == pytest.approx(ref.k_eff, rel=0.01)


# ---------------------------------------------------------------------------------------------
# rotation invariance


@pytest.mark.parametrize("case", ["k31 bar short", "k31 bar open", "cantilever"])
def test_frequencies_invariant_under_rotation(case):
    if case == "cantilever":
        plain, rotated = cantilever_modes(2.5e-3), cantilever_modes(2.5e-3, rotated=True)
    else:
        circuit = case.split()[-1]
        plain, rotated = bar_modes(circuit), bar_modes(circuit, rotated=True)
    assert np.allclose(ROTATION @ ROTATION.T, np.eye(3), atol=1e-15)
    # the rotated model is the same discrete problem written in another frame (mesh, c^E, e,
    # eps^S and the clamp all rotate): only round-off (1e-16 x the conditioning) and the
    # eigensolver's tolerance (ARPACK tol 1e-10 on the shift-inverted values) separate the two.
    # Measured with PARDISO and SuperLU alike: <= 1.2e-11 for the bar, <= 9e-10 for the
    # cantilever's 284 Hz pair (40x below its 11 kHz shift, where shift-invert resolves least).
    # 1e-8 keeps a 10x margin; materials rotated by R^T instead of R (mesh by R) change the
    # bar's frequencies by up to 25 % (measured by patching PiezoMaterial.rotated)
    assert len(rotated) == len(plain)
    assert rotated.frequencies == pytest.approx(plain.frequencies, rel=1e-8)


# ---------------------------------------------------------------------------------------------
# stated against actual error (issue 16 item 3): studies/verification_errors.py tabulates every case


def _case_params():
    from tests.helpers import load_study

    study = load_study("verification_errors")
    return [pytest.param(name, marks=[pytest.mark.slow] if name in study.SLOW else []) for name in study.CASES]


@pytest.mark.parametrize("case", _case_params())
def test_stated_error_covers_the_actual_error(case):
    from tests.helpers import load_study

    # a stated error is a promise: estimate >= actual on every mode of every verification case (the
    # reference's own uncertainty allowed: the study's docstring states each reference and its bound)
    rows = load_study("verification_errors").CASES[case]()
    assert rows, case
    assert all(r.covered for r in rows), [(r.mode, r.fidelity, r.actual, r.stated) for r in rows if not r.covered]
