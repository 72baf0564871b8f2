"""The axisymmetric model (modalfe.models.axisymmetric, fidelity "axisymmetric") against analytic theory and the 3-D
solid: a thin PZT-5A disc's radial mode in both circuits, an aluminium disc's radial mode, a steel ring's in-plane
flexural modes, a radially poled ring's breathing mode, the thickness mode of a laterally constrained plate, the axis
regularity conditions through the rigid motions of each harmonic, and the refusals of scenes that are no body of
revolution."""

from dataclasses import replace

import numpy as np
import pytest
import scipy.optimize as so
import scipy.special as ss

from modalfe.errors import SceneError
from modalfe.models.axisymmetric import assemble_axisymmetric, meridian_section
from modalfe.scene.loading import load_scene, scene_from_dict
from modalfe.solve.api import OWN_MESH, solve_modes
from tests.oracles.cases import stack_scene
from tests.oracles.discs import (
    PZT5A_DISC,
    SOLID_FA,
    SOLID_FR,
    SOLID_FR_ERROR,
    STEEL_RING,
    compliances,
    laterally_held,
    radial_ring_scene,
    ring_inplane_frequency,
    steel_ring_scene,
    thickness_resonator,
    thin_disc,
    thin_ring_breathing,
)

DISC = PZT5A_DISC


def _disc(radius_mm: float, height_mm: float, material_name: str, near: float, poling: int = 0):
    part = {"name": "disc", "shape": "cylinder", "material": material_name, "centre": [0, 0, 0], "axis": "z",
            "radius": radius_mm, "height": height_mm, "poling": poling}
    extra = {"faces": {"electrode_a": ["disc.top"], "electrode_b": ["disc.bottom"]},
             "electrodes": {"electrode_a": "drive", "electrode_b": "ground"}} if poling else {}
    return scene_from_dict({"units": "mm", "parts": [part], "analysis": {"near": near, "count": 8}, **extra})


def test_thin_pzt5a_disc_radial_mode_matches_the_3d_solid_in_both_circuits():
    """R1 of the 20 x 1 mm PZT-5A disc, short circuit: within the two models' stated errors of the 3-D solid's
    99,365 Hz (its 0.001 %, plus 0.5 Hz of rounding); open circuit fa within 1e-4 of the solid's 117,317 Hz (a fifth
    of the fa - fr gap's resolution that k_p needs: k_p moves ~3x the fa error) and k_p through the IEEE Std 176-1987
    planar relation within 0.02 of the thin-disc theory's 0.603 (as the 3-D test; the theory neglects (t/D)^2)."""
    short = solve_modes(DISC, fidelity="axisymmetric", mode="R1", tol=1e-5)
    fr = short.labelled("R1")
    assert short.model.harmonic_of(fr.shape) == 0
    assert abs(fr.frequency - SOLID_FR) / SOLID_FR <= fr.error_estimate + SOLID_FR_ERROR + 0.5 / SOLID_FR
    fa = solve_modes(DISC, fidelity="axisymmetric", mode="R1", circuit="open", tol=1e-5).labelled("R1")
    assert fa.frequency == pytest.approx(SOLID_FA, rel=1e-4)
    s, d, eps_T, _ = compliances("PZT-5A")
    sigma = -s[0, 1] / s[0, 0]

    def planar(x):
        return (1 - sigma) * ss.j1(x) - x * ss.j0(x)

    eta = so.brentq(planar, 1.5, 2.5)
    ratio = planar(eta * fa.frequency / fr.frequency) / ((1 + sigma) * ss.j1(eta * fa.frequency / fr.frequency))
    kp2 = 2 * d[2, 0] ** 2 / (eps_T[2, 2] * (s[0, 0] + s[0, 1]))
    assert np.sqrt(ratio / (1 + ratio)) == pytest.approx(np.sqrt(kp2), abs=0.02)
    fr_theory, _ = thin_disc("PZT-5A", 0.01)
    # the thin-disc theory's own finite-thickness gap: -0.114 % (docs/studies.md); 0.2 % allows for it
    assert fr.frequency == pytest.approx(fr_theory, rel=2e-3)


def test_free_aluminium_disc_radial_mode_against_the_plane_stress_frequency_equation():
    """A free 20 x 0.1 mm Al-5052 disc: eta J0(eta) = (1 - nu) J1(eta), f = eta / (2 pi a) sqrt(E / (rho (1 -
    nu^2))) (plane stress; Leissa, NASA SP-160, in-plane modes). Tolerance 1e-4 plus the stated error: the theory's
    thickness effect is of order nu^2 (t/a)^2 / 12 ~ 1e-6 here; the stated error must cover the rest."""
    E, nu, rho, a = 70.3e9, 0.33, 2680.0, 0.01
    eta = so.brentq(lambda x: x * ss.j0(x) - (1 - nu) * ss.j1(x), 1, 3)
    f_theory = eta / (2 * np.pi * a) * np.sqrt(E / (rho * (1 - nu**2)))
    modes = solve_modes(_disc(10, 0.1, "Al-5052", f_theory), fidelity="axisymmetric", harmonics=0, mode="R1",
                        tol=1e-4)
    r1 = modes.labelled("R1")
    assert abs(r1.frequency / f_theory - 1) <= 1e-4 + r1.error_estimate


def test_free_thin_ring_in_plane_flexural_modes_against_hoppe():
    """Steel ring, mean radius 20 mm, wall 1 mm, height 2 mm: in-plane modes n = 2, 3 (the harmonics themselves)
    against Hoppe (1871) f_n = sqrt(E I / (rho A R^4)) n (n^2 - 1) / sqrt(n^2 + 1) / 2 pi (1555.7, 4400.1 Hz).
    Tolerance 0.5 %: the thin-ring theory leaves out shear and rotary inertia, relative corrections ~ (n^2 + 1)
    (t/R)^2 / 12 = 0.10 % (n = 2), 0.21 % (n = 3); measured -0.11 %, -0.30 % (the 3-D solid: -0.06 %, -0.22 %
    with its own mesh error)."""
    r = STEEL_RING
    scene = steel_ring_scene()
    for n in (2, 3):
        f_theory = ring_inplane_frequency(n, radius=r["radius"], E=r["E"], rho=r["rho"], area=r["height"] * r["wall"],
                                          inertia=r["height"] * r["wall"] ** 3 / 12)
        modes = solve_modes(scene, fidelity="axisymmetric", harmonics=3, mode=f"n={n}", near=f_theory, tol=1e-4)
        mode = modes.labelled(f"n={n}")
        assert modes.model.harmonic_of(mode.shape) == n
        assert mode.frequency == pytest.approx(f_theory, rel=5e-3)


def test_radially_poled_ring_breathing_mode_and_its_k31_coupling():
    """A thin PZT-4 ring (mean radius 10 mm, wall 0.5 mm, height 1 mm) poled radially, electrodes on its walls:
    fr = sqrt(1 / (rho s11^E)) / (2 pi R), fa = fr / sqrt(1 - k31^2) (Berlincourt, Curran & Jaffe 1964). Tolerance
    0.1 %: the thin-ring formula neglects the wall's curvature, (t/R)^2 / 12 ~ 2e-4 (measured +0.024 %, +0.009 %; the
    3-D solid +0.02 %, +0.01 %); axis poling instead would leave fa = fr, 6 % off."""
    s, d, eps_T, _ = compliances("PZT-4")
    fr_theory = thin_ring_breathing("PZT-4", 0.01)
    fa_theory = fr_theory / np.sqrt(1 - d[2, 0] ** 2 / (s[0, 0] * eps_T[2, 2]))
    scene = radial_ring_scene(fr_theory)
    for circuit, f_theory in (("short", fr_theory), ("open", fa_theory)):
        mode = solve_modes(scene, fidelity="axisymmetric", mode="R1", circuit=circuit, tol=1e-5).labelled("R1")
        assert mode.frequency == pytest.approx(f_theory, rel=1e-3)


def test_thickness_mode_of_a_laterally_constrained_plate_is_the_1d_theory():
    """With no lateral motion a disc is the 1-D thickness resonator of IEEE Std 176-1987: open circuit fa =
    (1 / 2t) sqrt(c33^D / rho), c33^D = c33^E + e33^2 / eps33^S; short circuit fr from k_t^2 = (pi fr / 2 fa)
    tan(pi (fa - fr) / 2 fa), k_t^2 = e33^2 / (c33^D eps33^S). Exact for the model (e33, c33, eps33, the equipotential
    electrodes and the floating potential all enter); tolerance 1e-5, the quartic elements' error on ~4 elements
    through the thickness of a half wavelength being ~1e-8."""
    fr, fa = thickness_resonator("PZT-5A", 1e-3)
    scene = load_scene(DISC, **{"mesh.max_size": 2.5e-4})
    model = assemble_axisymmetric(scene, harmonics=(0,), order=4)
    assert laterally_held(model, "open", fa) == pytest.approx(fa, rel=1e-5)
    assert laterally_held(model, "short", fr) == pytest.approx(fr, rel=1e-5)


@pytest.mark.parametrize("grade", ["PZT-5H", "Sonox-P4"])
def test_thin_disc_frequency_constants_match_the_thin_disc_and_thickness_theories(grade):
    """The 20 x 1 mm disc of PZT-5H (Berlincourt's constants) and of Sonox-P4 (CeramTec's sheet, completed), short
    circuit, default tol. R1 against the thin-disc theory of IEEE Std 176-1987 (``thin_disc``) within 0.2 %: the
    theory neglects (t/D)^2, -0.10 to -0.13 % on the four grades (studies/frequency_constants.py). The thickness mode
    held laterally is the 1-D resonator (``thickness_resonator``) to 1e-5, as PZT-5A's above; free, within 1 % of it:
    the 1-D theory is the laterally infinite plate's, and the finite disc's lateral coupling with the radial
    overtones near the thickness mode moves it by -0.61 % to +0.78 % on the four grades (the same study)."""
    fr_r1, _ = thin_disc(grade, 0.01)
    r1 = solve_modes(_disc(10, 1, grade, fr_r1, poling=1), fidelity="axisymmetric", mode="R1").labelled("R1")
    assert r1.frequency == pytest.approx(fr_r1, rel=2e-3)
    fr, _ = thickness_resonator(grade, 1e-3)
    scene = _disc(10, 1, grade, fr, poling=1)
    held = assemble_axisymmetric(replace(scene, mesh=replace(scene.mesh, max_size=2.5e-4)), harmonics=(0,), order=4)
    assert laterally_held(held, "short", fr) == pytest.approx(fr, rel=1e-5)
    free = replace(scene, mesh=replace(scene.mesh, harmonics=0, max_frequency=1.15 * fr))
    thickness = solve_modes(free, fidelity="axisymmetric", near=fr, count=5).labelled("thickness")
    assert thickness.frequency == pytest.approx(fr, rel=1e-2)
    if grade == "Sonox-P4":
        # the same sheet's Np (CeramTec: 2210 Hz m) within 5 %, the frequency tolerance APC states for its typical
        # values (the stored CeramTec copy states none); measured -2.4 %. Its Nt (2000 Hz m) is not asserted: the
        # model's fr t is 11 % below it (docs/axisymmetric.md, "Frequency constants").
        assert r1.frequency * 0.02 == pytest.approx(2210.0, rel=0.05)


@pytest.mark.parametrize(("n", "rigid"), [(0, 2), (1, 2), (2, 0), (3, 0)])
def test_axis_conditions_keep_each_harmonics_rigid_motions(n, rigid):
    """A free body's six rigid motions are harmonics 0 (axial translation, turn about the axis) and 1 (lateral
    translation u_r = -u_theta, tilt); none above. The axis conditions of n = 1 (U_r + U_t = 0, U_z = Phi = 0) let
    the lateral translation through: wrong conditions (U_r = U_t = 0) would stiffen it to a finite frequency."""
    scene = _disc(10, 2, "Al-5052", 1e3)
    model = assemble_axisymmetric(scene, harmonics=(n,), order=3)
    T = model.constraints("short").T
    A, B = (T.T @ model.K @ T).toarray(), (T.T @ model.M @ T).toarray()
    from scipy.linalg import eigh

    f = np.sqrt(np.abs(eigh(A, B, eigvals_only=True, subset_by_index=[0, 3]))) / (2 * np.pi)
    assert np.sum(f < 1.0) == rigid  # elastic modes of this disc start above 10 kHz
    assert f[rigid] > 1e3


@pytest.mark.parametrize(("scene", "label", "harmonics"), [(DISC, "R1", 4), ("ring", "n=3", 3)])
def test_stated_error_covers_the_distance_from_a_finer_discretization(scene, label, harmonics):
    """The stated error by the order (order 3 against 2 on the scene's grid) covers the actual error, measured
    against order 4 on elements half as large (its own error orders of magnitude smaller: the stated errors fall
    ~10x per order here)."""
    if scene == "ring":
        scene = scene_from_dict({
            "units": "mm", "materials": {"steel": {"E": 200e9, "nu": 0.3, "rho": 7850.0}},
            "parts": [{"name": "ring", "shape": "ring", "material": "steel", "centre": [0, 0, 0], "axis": "z",
                       "inner": 19.5, "outer": 20.5, "height": 2}], "analysis": {"near": 4.4e3, "count": 6}})
    scene = load_scene(scene) if isinstance(scene, str) else scene
    stated = solve_modes(scene, fidelity="axisymmetric", harmonics=harmonics, tol=OWN_MESH).labelled(label)
    finer = solve_modes(_at_order(scene, order=4), fidelity="axisymmetric", harmonics=harmonics,
                        error_estimate=False, size_factor=0.5).labelled(label)
    assert abs(stated.frequency / finer.frequency - 1) <= stated.error_estimate


def _at_order(scene, *, order: int):
    """``scene`` with its elements of ``order``."""
    return replace(scene, mesh=replace(scene.mesh, order=order))


def test_refuses_scenes_that_are_no_body_of_revolution():
    """One-line SceneErrors naming the field: a box part, a part off the common axis, poling across the axis."""
    box = scene_from_dict({"units": "mm", "kind": "solid", "analysis": {"near": 1e3}, "parts": [
        {"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [10, 10, 1]}]})
    with pytest.raises(SceneError, match=r"parts\.plate\.shape"):
        meridian_section(box)
    off = scene_from_dict({"units": "mm", "analysis": {"near": 1e3}, "parts": [
        {"name": "a", "shape": "cylinder", "material": "CuBe", "centre": [0, 0, 0], "axis": "z", "radius": 5,
         "height": 1},
        {"name": "b", "shape": "cylinder", "material": "CuBe", "centre": [1, 0, 1], "axis": "z", "radius": 2,
         "height": 1}]})
    with pytest.raises(SceneError, match=r"parts\.b\.centre"):
        meridian_section(off)
    across = scene_from_dict({"units": "mm", "analysis": {"near": 1e3}, "parts": [
        {"name": "a", "shape": "cylinder", "material": "PZT-5A", "centre": [0, 0, 0], "axis": "z", "radius": 5,
         "height": 1, "poling": "+x"}]})
    with pytest.raises(SceneError, match=r"parts\.a\.poling"):
        meridian_section(across)


# the disc stack (tests/oracles/cases.py ``stack_scene``) on the 3-D solid, label -> (frequency [Hz], stated error):
# solve_modes(stack_scene(), fidelity="solid", near=191.8e3, count=6, tol=1e-3), swept hexahedra x0.444, 7 layers,
# 139,473 DOFs, 204 s (2026-11-28; Richardson through three grids at order 1, bonded parts)
STACK_SOLID = {"n=2": (178_990.52, 1.99e-4), "T2": (191_627.69, 8.03e-4), "(4,0)": (192_752.50, 7.77e-4),
               "n=1 k=2": (194_923.60, 2.12e-4)}


def test_disc_stack_matches_the_3d_solid_within_their_stated_errors():
    """Al disc, epoxy film and PZT-5A disc bonded on one axis (three regions, a passive film 50 um thick): each mode
    the 3-D solid found near 192 kHz within the sum of the two models' stated errors (the solid's one of each
    degenerate pair: its twin differs by < 2e-6)."""
    modes = solve_modes(stack_scene(), fidelity="axisymmetric", near=191.8e3, count=8, tol=2e-4, harmonics=4)
    for label, (f_solid, stated) in STACK_SOLID.items():
        mode = modes.labelled(label)
        assert abs(mode.frequency / f_solid - 1) <= stated + mode.error_estimate, (label, mode.frequency)


def _unelectroded_disc():
    """A free 10 x 1 mm PZT-5A disc, poled, with no electrode: its n = 0 potential has no face held at zero."""
    part = {"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [0, 0, 0], "axis": "z",
            "radius": 5, "height": 1, "poling": 1}
    return scene_from_dict({"units": "mm", "parts": [part], "analysis": {"near": 230e3, "count": 4}})


# R1 of the unelectroded disc on the 3-D solid, quartic elements on the scene's own grid (its potential's constant
# fixed at one node, ``modalfe.models.solid.Model.constraints``): 244,656.81 Hz, 38 s; recomputed by the slow test
UNELECTRODED_SOLID_R1 = 244_656.81


def test_an_unelectroded_piezo_disc_is_solved_with_its_potential_gauged():
    """Without electrodes nothing held the n = 0 potential's constant: the matrix was singular ("no regular shift
    near 230000 Hz") and auto fell back to the solid. Gauged at one node (as the solid), R1 lies within its stated
    error of the quartic solid's (plus 0.01 Hz: the stored value's rounding)."""
    r1 = solve_modes(_unelectroded_disc(), fidelity="axisymmetric").labelled("R1")
    assert abs(r1.frequency - UNELECTRODED_SOLID_R1) <= r1.error_estimate * r1.frequency + 0.01


@pytest.mark.slow  # 38 s: the quartic solid
def test_the_unelectroded_discs_solid_r1_is_the_stored_one():
    solid = solve_modes(replace(_unelectroded_disc(), mesh=replace(_unelectroded_disc().mesh, order=4)),
                        fidelity="solid", error_estimate=False).labelled("R1")
    assert abs(solid.frequency - UNELECTRODED_SOLID_R1) <= 0.01  # the stored value's rounding


def test_a_probe_off_the_body_names_the_point_as_the_solid_does():
    """A point in a ring's hole (a face group's centre on the axis: a Langevin stack's electrode faces, forced
    --outputs) is refused naming the point, as the 3-D solid refuses it; before, the meridian mesh's point search
    failed inside scikit-fem ("Point is outside of the mesh.", an internal error). A point in the wall is read."""
    model = assemble_axisymmetric(steel_ring_scene(), harmonics=(0, 2), order=2)
    with pytest.raises(SceneError, match=r"^points: \(0, 0, 0\.001\) m lies outside the device's parts$"):
        model.displacement_probes(np.array([[0.0, 0.0, 0.001]]))
    assert model.displacement_probes(np.array([[0.02, 0.0, 0.001]])).shape == (3, model.ndofs)
