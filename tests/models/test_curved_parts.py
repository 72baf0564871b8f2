"""Curved parts through the solid model against analytic piezo theory: a thin disc's planar mode (IEEE Std 176-1987)
and a radially poled ring's breathing mode; the per-point radial poling tensors against axis poling."""

import numpy as np
import pytest
import scipy.optimize as so
import scipy.special as ss

from modalfe.geometry.shapes import Ring
from modalfe.scene.loading import scene_from_dict
from modalfe.scene.materials import material, poled_tensors, poling_frames
from modalfe.solve.api import solve_modes
from tests.oracles.discs import (
    axisymmetric,
    compliances,
    in_plane,
    ring_inplane_frequency,
    thin_disc,
    thin_ring_breathing,
)

ELEMENTS = ["hex", "tet"]  # swept hexahedra (modalfe.models.swept, the default for parts on one axis), tetrahedra


def _scene(part: dict, faces: dict, near: float, element: str = "tet"):
    return scene_from_dict({
        "units": "mm", "parts": [part], "faces": faces,
        "electrodes": {"electrode_a": "drive", "electrode_b": "ground"},
        "analysis": {"near": near, "count": 8}, "mesh": {"element": element, "order": 2, "min_layers": 1}})


def _planar(x, sigma):
    """(1 - sigma) J1(x) - x J0(x): zero at the planar resonance eta_1; IEEE Std 176-1987 planar coupling:
    k_p^2 / (1 - k_p^2) = _planar(eta_a) / ((1 + sigma) J1(eta_a)) at the antiresonance eta_a = eta_1 fa / fr."""
    return (1 - sigma) * ss.j1(x) - x * ss.j0(x)


@pytest.mark.slow
@pytest.mark.parametrize("element", ELEMENTS)
def test_thin_pzt5a_disc_planar_mode_fr_fa_kp_against_ieee176(element):
    """20 mm x 1 mm PZT-5A disc, free, electrodes on both faces. Thin-disc theory (IEEE Std 176-1987, planar mode;
    Meitzler et al. 1961): eta J0(eta) = (1 - sigma) J1(eta), sigma = -s12/s11, fr = eta_1 / (2 pi a) /
    sqrt(rho s11^E (1 - sigma^2)); k_p^2 = 2 d31^2 / (eps33^T (s11^E + s12^E)).

    Tolerance 0.5 % on fr and fa: the thin-disc theory neglects the thickness (t/D = 0.05; its first correction,
    rotary and shear terms, is of order (t/D)^2 ~ 0.25 %), and P2 on 6 elements per wavelength has an error of
    the same order (measured together: fr -0.11 %, fa -0.07 % on either mesh, docs/studies.md "Curved parts" and
    "Swept hexahedra": the FE values converge to -0.114 % and -0.068 %, the theory's own gap); k_p within 0.02
    absolute (it amplifies the frequency errors by ~ fr / (2 (fa - fr)) ~ 3)."""
    s, d, eps_T, _ = compliances("PZT-5A")
    sigma = -s[0, 1] / s[0, 0]
    eta = so.brentq(_planar, 1.5, 2.5, args=(sigma,))
    kp2 = 2 * d[2, 0] ** 2 / (eps_T[2, 2] * (s[0, 0] + s[0, 1]))
    fr_theory, fa_theory = thin_disc("PZT-5A", 0.01)
    disc = {"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [0, 0, 0], "axis": "z",
            "radius": 10, "height": 1, "poling": 1}
    scene = _scene(disc, {"electrode_a": ["disc.top"], "electrode_b": ["disc.bottom"]}, fr_theory, element)
    fr = axisymmetric(solve_modes(scene, near=fr_theory, error_estimate=False), 0.0098, 0.0005).frequency
    opened = solve_modes(scene, near=fa_theory, error_estimate=False, circuit="open")
    fa = axisymmetric(opened, 0.0098, 0.0005).frequency
    assert fr == pytest.approx(fr_theory, rel=5e-3)
    assert fa == pytest.approx(fa_theory, rel=5e-3)
    ratio = _planar(eta * fa / fr, sigma) / ((1 + sigma) * ss.j1(eta * fa / fr))
    assert np.sqrt(ratio / (1 + ratio)) == pytest.approx(np.sqrt(kp2), abs=0.02)


@pytest.mark.slow
@pytest.mark.parametrize("element", ELEMENTS)
def test_radially_poled_ring_breathing_mode_and_its_k31_coupling(element):
    """A thin PZT-4 ring (mean radius R = 10 mm, wall 0.5 mm, height 1 mm) poled radially, electrodes on its inner
    and outer walls. Its breathing mode is a uniform hoop strain normal to the poling: fr = sqrt(1 / (rho s11^E)) /
    (2 pi R), and open-circuited it stiffens to s11^D = s11^E (1 - k31^2), fa = fr / sqrt(1 - k31^2),
    k31^2 = d31^2 / (s11^E eps33^T) (Berlincourt, Curran & Jaffe 1964, thin-ring radial mode). Tolerance 1 %:
    the thin-ring formula neglects the wall's curvature (t/R)^2 / 12 ~ 2e-4 and the height's Poisson coupling
    (free faces: plane stress, none to first order); measured fr +0.02 %, fa +0.01 %. Axis poling instead of radial
    would leave the walls uncoupled (fa = fr): the check fails by k31^2 / 2 ~ 6 %."""
    s, d, eps_T, _ = compliances("PZT-4")
    R = 0.01
    fr_theory = thin_ring_breathing("PZT-4", R)
    k31 = np.sqrt(d[2, 0] ** 2 / (s[0, 0] * eps_T[2, 2]))
    ring = {"name": "ring", "shape": "ring", "material": "PZT-4", "centre": [0, 0, 0], "axis": "z",
            "inner": 9.75, "outer": 10.25, "height": 1, "poling": "radial"}
    scene = _scene(ring, {"electrode_a": ["ring.outer"], "electrode_b": ["ring.inner"]}, fr_theory, element)
    fr = axisymmetric(solve_modes(scene, near=fr_theory, error_estimate=False), R, 0.0005).frequency
    fa = axisymmetric(solve_modes(scene, near=fr_theory / np.sqrt(1 - k31**2), error_estimate=False,
                                  circuit="open"), R, 0.0005).frequency
    assert fr == pytest.approx(fr_theory, rel=0.01)
    assert fa == pytest.approx(fr_theory / np.sqrt(1 - k31**2), rel=0.01)


def test_radial_poling_tensors_at_a_point_equal_poling_along_that_radius():
    """At a point on the +y side of a radially poled ring the per-point tensors are those of a part poled +y
    (both through ``poling_frames``), and -z poling equals the existing half-turn ``PiezoMaterial.poled(-1)``."""
    mat = material("PZT-4")
    ring = Ring("r", "r", "PZT-4", (0.0, 0.0, 0.0), "z", 0.001, 0.002, 0.001, poling="radial")
    d = ring.poling_directions(np.array([[0.0], [0.0015], [0.0005]]))
    assert np.allclose(d, [[0, 1, 0]])
    C, e, eps = poled_tensors(mat, poling_frames(d))
    axis = mat.rotated(poling_frames(np.array([0.0, 1.0, 0.0])))
    assert np.allclose(C[0], axis.C) and np.allclose(e[0], axis.e) and np.allclose(eps[0], axis.eps_S)
    down = mat.poled(-1)
    flipped = mat.rotated(poling_frames(np.array([0.0, 0.0, -1.0])))
    assert np.allclose(flipped.C, down.C) and np.allclose(flipped.e, down.e)
    assert np.allclose(e[0][1, 1], mat.e[2, 2])  # e33 now acts along y: e_yy,yy


def _elastic(modes, skip: int = 6) -> np.ndarray:
    """Frequencies of a free body's elastic modes (the 6 rigid-body modes, ~0 Hz, dropped)."""
    f = np.sort(modes.frequencies)
    return f[skip:]


@pytest.mark.slow
@pytest.mark.parametrize("element", ELEMENTS)
def test_free_thin_ring_in_plane_flexural_modes_against_hoppe(element):
    """Steel ring, mean radius R = 20 mm, radial wall t = 1 mm, height h = 2 mm (in-plane bending stiffer out of
    plane: I_out / I_in = (h/t)^2 = 4). Hoppe (1871): f_n = sqrt(E I / (rho A R^4)) n (n^2 - 1) / sqrt(n^2 + 1) / 2 pi,
    I = h t^3 / 12, A = h t: 1555.7 Hz (n = 2), 4400.1 Hz (n = 3). Tolerance 1 %: the thin-ring theory leaves out
    shear and rotary inertia, relative corrections ~ (n^2 + 1) (t/R)^2 / 12 ~ 0.1 % (n = 3), and one P2 layer across
    the wall (elements 1 mm, the mesh's thickness cap) was measured -0.06 % (n = 2) and -0.22 % (n = 3) from
    the theory (swept hexahedra, elements as long as the wall is thick, modalfe.models.mesh.RING_WALL_ELEMENTS:
    -0.05 % and -0.2 %); modes picked by shape (u_z < 10 % of u_r, n from the Fourier harmonics of u_r on the
    mid-circle)."""
    E, nu, rho = 200e9, 0.3, 7850.0
    R, t, h = 0.02, 0.001, 0.002
    fn = {n: ring_inplane_frequency(n, radius=R, E=E, rho=rho, area=h * t, inertia=h * t**3 / 12) for n in (2, 3)}
    scene = scene_from_dict({
        "units": "mm", "materials": {"steel": {"E": E, "nu": nu, "rho": rho}},
        "parts": [{"name": "ring", "shape": "ring", "material": "steel", "centre": [0, 0, 0], "axis": "z",
                   "inner": 19.5, "outer": 20.5, "height": 2}],
        "analysis": {"near": fn[3], "count": 12}, "mesh": {"element": element, "min_layers": 1}})
    modes = solve_modes(scene, near=0.5 * (fn[2] + fn[3]), count=12, error_estimate=False)
    for n in (2, 3):
        pair = in_plane(modes, n, R, h / 2, every=True)
        assert len(pair) == 2, f"n = {n}: expected a pair of in-plane modes, got {[m.frequency for m in pair]}"
        assert np.allclose([m.frequency for m in pair], fn[n], rtol=0.01), (n, pair, fn[n])


@pytest.mark.slow
@pytest.mark.parametrize("element", ELEMENTS)
def test_plate_with_a_square_hole_equals_the_same_plate_of_four_boxes(element):
    """A free 40 x 30 x 2 mm Cu-Be plate with a 10 x 10 mm square hole in its middle, as one extruded outline and as
    four bonded boxes (the same solid): two different tetrahedral (or swept hexahedral) meshes of it, P2, elements
    ~2 mm. Measured on tetrahedra (on swept hexahedra against the structured grid: within 0.05 %): the
    first four elastic modes (3.69, 4.40, 8.29, 9.31 kHz) agree within 0.16 %; tolerance 0.5 %, the two meshes'
    own errors (each a few 0.1 % at one layer through the thickness, of one sign: conforming P2 is stiff) differ by
    less than either."""
    mesh = {"element": element, "min_layers": 1, "max_size": 0.002}  # metres; the tetrahedra's thickness cap too
    outline = [[0, 0], [40, 0], [40, 30], [0, 30]]
    hole = [[15, 10], [25, 10], [25, 20], [15, 20]]
    extruded = scene_from_dict({"units": "mm", "mesh": mesh, "analysis": {"near": 1.0}, "parts": [
        {"name": "plate", "shape": "extrusion", "material": "CuBe", "axis": "z", "base": 0, "height": 2,
         "outline": outline, "holes": [hole]}]})
    boxes = scene_from_dict({"units": "mm", "mesh": mesh, "analysis": {"near": 1.0}, "kind": "solid", "parts": [
        {"name": "left", "material": "CuBe", "origin": [0, 0, 0], "size": [15, 30, 2]},
        {"name": "right", "material": "CuBe", "origin": [25, 0, 0], "size": [15, 30, 2]},
        {"name": "low", "material": "CuBe", "origin": [15, 0, 0], "size": [10, 10, 2]},
        {"name": "high", "material": "CuBe", "origin": [15, 20, 0], "size": [10, 10, 2]}]})
    f1 = _elastic(solve_modes(extruded, near=1.0, count=10, error_estimate=False))
    f2 = _elastic(solve_modes(boxes, near=1.0, count=10, error_estimate=False))
    assert f1 == pytest.approx(f2, rel=5e-3)


@pytest.mark.slow
@pytest.mark.parametrize("element", ELEMENTS)
def test_radially_poled_ring_is_frame_invariant(element):
    """The whole device turned by a rotation (mesh, material tensors, radial poling directions alike) has the same
    short- and open-circuit spectrum to round-off (measured 1.4e-13; tolerance 1e-9)."""
    from scipy.spatial.transform import Rotation

    ring = {"name": "ring", "shape": "ring", "material": "PZT-4", "centre": [0, 0, 0], "axis": "z",
            "inner": 9.75, "outer": 10.25, "height": 1, "poling": "radial"}
    scene = _scene(ring, {"electrode_a": ["ring.outer"], "electrode_b": ["ring.inner"]}, 55e3, element)
    R = Rotation.from_euler("xyz", [0.3, -0.7, 1.1]).as_matrix()
    for circuit in ("short", "open"):
        a = solve_modes(scene, near=54e3, count=6, error_estimate=False, circuit=circuit).frequencies
        b = solve_modes(scene, near=54e3, count=6, error_estimate=False, circuit=circuit, frame=R).frequencies
        assert b == pytest.approx(a, rel=1e-9)


def test_a_poled_disc_without_electrodes_is_solved_and_stiffer_than_short_circuited():
    # issue 35 (found beside it): a poled piezo part that no electrode touches left its potential's constant free,
    # and every solve failed with "no regular shift" (a singular matrix). Its potential is now fixed at one node
    # (only its gradient enters). Law: charge-free faces stiffen the disc against shorted electrodes, never soften
    # it (fr <= f_free <= fa, to the solver's round-off)
    disc = {"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [0, 0, 0], "axis": "z",
            "radius": 6, "height": 0.6, "poling": "+z"}
    bare = scene_from_dict({"units": "mm", "parts": [disc], "analysis": {"near": 30e3, "count": 8}})
    electroded = scene_from_dict({"units": "mm", "parts": [disc], "analysis": {"near": 30e3, "count": 8},
                                  "faces": {"top": ["disc.top"], "bottom": ["disc.bottom"]},
                                  "electrodes": {"top": "drive", "bottom": "ground"}})
    free = solve_modes(bare, near=30e3, count=8, error_estimate=False).frequencies
    short = solve_modes(electroded, near=30e3, count=8, error_estimate=False).frequencies
    # the elastic modes in order: the six rigid-body modes at 0 lie as far from 30 kHz as the window's edge, and a
    # single-vector Lanczos finds as many of their copies as rounding gives it (a farther elastic mode takes the place
    # of a missing one)
    free, short = free[free > 1.0], short[short > 1.0]
    n = min(len(free), len(short))
    assert n >= 5 and np.all(free[:n] >= short[:n] * (1 - 1e-9))
