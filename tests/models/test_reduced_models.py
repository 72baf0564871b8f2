"""The reduced rungs of the fidelity ladder: the 1-D layered Timoshenko beam (``modalfe.models.beam``) and the
2-D Reissner-Mindlin laminate plate (``modalfe.models.plate``) against the analytic theory they implement, then
against the 3-D solid, and ``fidelity="auto"`` choosing between them.

Against its own theory a reduced model differs only by discretization, so those tolerances are a few
times the discretization error measured by refinement (numbers quoted in each test). Against the solid
the difference is model error, which ``auto`` estimates; the tests check that the estimate covers it.
"""

import functools
import math
from dataclasses import replace

import numpy as np
import pytest

from modalfe import load_scene
from modalfe.models.plate import Layer, shear_stiffness
from modalfe.scene import scene_from_dict
from modalfe.scene.materials import MATERIALS
from modalfe.solve.api import OWN_MESH, solve_modes
from tests.oracles import analytic
from tests.oracles.cases import cantilever_scene, diaphragm_plate_scene, k31_bar_scene, reference_mesh

CUBE = {"E": 123e9, "nu": 0.30, "rho": 8250.0}  # modalfe.scene.materials "CuBe" (seed 001)
BRASS = {"E": 105e9, "nu": 0.34, "rho": 8500.0}  # modalfe.scene.materials "brass-seed003" (seed 003)
THICK = (0.020, 0.016, 2.0e-3)  # h/a = 0.1: shear and rotary inertia matter (Kirchhoff is 4-16 % off)


@functools.cache
def thick_plate_modes(max_size: float):
    return solve_modes(diaphragm_plate_scene(*THICK, max_size), near=60e3, count=10, fidelity="plate",
                       error_estimate=False)


@pytest.mark.parametrize("mn", [(1, 1), (2, 1), (1, 2), (2, 2), (3, 1)])
def test_plate_matches_mindlin_navier_solution(mn):
    a, b, h = THICK
    # the plate model is Mindlin's theory with the energy-consistent shear factor, 5/6 for one layer
    ref = analytic.mindlin_plate_ss(*mn, a=a, b=b, h=h, **CUBE, shear_factor=5 / 6)
    fe = thick_plate_modes(1e-3).labelled(f"({mn[1] - 1},{mn[0] - 1})", near=ref).frequency
    # conforming elements, exact integration: an upper bound (min-max). Measured excess with 1 mm
    # elements 0.001 % (1,1) .. 0.015 % (3,1); with 2 mm 0.02 .. 0.22 %: ratio ~15, the h^4 of quadratic
    # elements, so no locking at h / l_e = 2. 0.05 % is three times the largest
    assert ref * (1 - 1e-9) <= fe <= ref * 1.0005, mn


def test_shear_correction_one_layer_and_sandwich():
    E, nu = 100e9, 0.3
    G = E / (2 * (1 + nu))
    Q = E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    one = (Layer("p", 0.0, 2e-3, Q, (G, G), 1.0, np.zeros(3), 0.0),)
    # a homogeneous layer: the parabolic shear stress gives exactly 5/6 G h
    assert shear_stiffness(one, 0) == pytest.approx(5 / 6 * G * 2e-3, rel=1e-10)
    # thin stiff facings on a core with no membrane stiffness: the sandwich shear stiffness G_c d^2 / c
    # (Allen, Analysis and Design of Structural Sandwich Panels, 1969, ch. 2), d the facings' centroid
    # distance; with facings 1 % of the core the facing terms are O(t_f / c): within 1 %
    c, t, Gc = 20e-3, 0.2e-3, 200e6
    core = Layer("core", t, t + c, Q * 1e-9, (Gc, Gc), 1.0, np.zeros(3), 0.0)
    sandwich = (Layer("bottom", 0.0, t, Q, (G, G), 1.0, np.zeros(3), 0.0), core,
                Layer("top", t + c, 2 * t + c, Q, (G, G), 1.0, np.zeros(3), 0.0))
    assert shear_stiffness(sandwich, 1) == pytest.approx(Gc * (c + t) ** 2 / c, rel=0.01)
    # the per-layer sum 5/6 sum G h would be 4 times stiffer here: the correction matters for the tile
    assert 5 / 6 * (2 * G * t + Gc * c) > 3 * shear_stiffness(sandwich, 1)


def test_beam_matches_timoshenko_cantilever():
    E, nu, rho = BRASS["E"], BRASS["nu"], BRASS["rho"]
    tim = analytic.timoshenko_cantilever(length=0.1, E=E, G=E / (2 * (1 + nu)), rho=rho, area=25e-6,
                                         inertia=5e-3**4 / 12, kappa=analytic.cowper_shear_coefficient_rectangle(nu))
    modes = solve_modes(cantilever_scene(2.5e-3), fidelity="beam", error_estimate=False)
    for n, ref in enumerate(tim, start=1):
        pair = [m for m in modes if m.label in (f"bending-y {n}", f"bending-z {n}")]
        # the square section's y and z bending come as a degenerate pair, both found
        assert len(pair) == 2, [m.label for m in modes]
        # same theory (Cowper's kappa): only discretization remains, measured 6e-5 at mode 6 with the
        # default mesh; 3e-4 is five times that
        for m in pair:
            assert m.frequency == pytest.approx(ref, rel=3e-4), n


def test_beam_piezo_sheet_matches_k31_bar():
    mat = MATERIALS["PZT-5A"]
    ref = analytic.k31_bar(length=0.03, c_E=mat.C, e=mat.e, eps_S=mat.eps_S, rho=mat.rho)
    short = solve_modes(k31_bar_scene(1e-3), fidelity="beam", error_estimate=False)
    open_ = solve_modes(k31_bar_scene(1e-3), circuit="open", fidelity="beam", error_estimate=False)
    fr = min((m for m in short if m.label.startswith("axial")), key=lambda m: abs(m.frequency - ref.fr))
    fa = min((m for m in open_ if m.label.startswith("axial")), key=lambda m: abs(m.frequency - ref.fa))
    # the beam's piezo layer is the 1-D theory of IEEE Std 176 (T1 only, E3 uniform): measured agreement
    # 1e-6 (discretization of a smooth mode); 1e-4 still catches a wrong e_b or eps_b (k31^2 ~ 0.1)
    assert fr.frequency == pytest.approx(ref.fr, rel=1e-4)
    assert fa.frequency == pytest.approx(ref.fa, rel=1e-4)


def test_plate_piezo_patch_couples_like_the_solid():
    """A thin PZT-5A strip as a plate: its length-extensional mode, short and open circuit."""
    scene = scene_from_dict({
        "name": "k31-strip", "units": "mm", "kind": "plate",
        "parts": [{"name": "bar", "region": "piezo", "material": "PZT-5A", "origin": [0, 0, 0],
                   "size": [30, 6, 0.5], "poling": 1}],
        "faces": {"top": ["bar.zmax"], "bottom": ["bar.zmin"]},
        "electrodes": {"top": "drive", "bottom": "ground"},
        "analysis": {"near": 50e3, "count": 6}, "mesh": reference_mesh(1e-3, 2),
    })
    ref = analytic.k31_bar(length=0.03, c_E=MATERIALS["PZT-5A"].C, e=MATERIALS["PZT-5A"].e,
                           eps_S=MATERIALS["PZT-5A"].eps_S, rho=MATERIALS["PZT-5A"].rho)
    found = {}
    for fidelity in ("plate", "solid"):
        for circuit, target in (("short", ref.fr), ("open", ref.fa)):
            modes = solve_modes(scene, near=target, count=6, circuit=circuit, fidelity=fidelity,
                                error_estimate=False)
            found[fidelity, circuit] = min((m for m in modes if m.label == "in-plane"),
                                           key=lambda m: abs(m.frequency - target)).frequency
    # in-plane extension of a thin layer: E3 is uniform through it in 3-D too, so plane stress is nearly the
    # whole model difference (thickness-direction Poisson inertia, (nu pi t / (2 L))^2 ~ 3e-4 on the bar's
    # lateral scale, smaller for the thin direction). Measured: 2e-5 short, 8e-6 open; 2e-4 is ten times
    for circuit in ("short", "open"):
        assert found["plate", circuit] == pytest.approx(found["solid", circuit], rel=2e-4), circuit
    k_plate = analytic.k_eff(found["plate", "short"], found["plate", "open"])
    k_solid = analytic.k_eff(found["solid", "short"], found["solid", "open"])
    # k_eff^2 = 1 - (fr/fa)^2 amplifies a frequency-ratio error by (1 - k^2)/k^2 ~ 9: 1 %
    assert k_plate == pytest.approx(k_solid, rel=0.01)
    # the 6 mm width couples the extension to width motion: the strip's mode sits 0.2 % below the 1-D bar's
    # fr (measured); a plane-strain error would put it ~10 % above. 1 %
    assert found["plate", "short"] == pytest.approx(ref.fr, rel=0.01)


@pytest.mark.parametrize("name, check", [
    ("tile_eq5", (("(0,0)", 845.0),)),
    pytest.param("honeycomb_tile", (("heave", 45.0), ("(1,1)", 896.0)), marks=pytest.mark.slow),
])
def test_plate_model_error_estimate_covers_the_solid_difference(name, check):
    scene = load_scene(name)
    auto = solve_modes(scene, fidelity="auto", check=check, tol=0.02)  # at 2 % the plate answers
    assert auto.fidelity == "plate"
    assert "plate answered" in auto.fidelity_note
    solid = solve_modes(scene, fidelity="solid", tol=OWN_MESH)  # the scene's own mesh, as the cross-check's
    for label, near in check:
        reduced, reference = auto.labelled(label, near=near), solid.labelled(label, near=near)
        # the plate's stated total error must cover its distance from the solid at default resolution,
        # allowing for the solid's own discretization estimate
        assert math.isfinite(reduced.model_error) and reduced.model_error > 0
        distance = abs(reduced.frequency / reference.frequency - 1)
        assert distance <= reduced.error_estimate + reference.error_estimate, label


def test_auto_says_why_the_solid_answered_when_the_tolerance_is_tight():
    modes = solve_modes(load_scene("tile_eq5"), fidelity="auto", tol=1e-5, check=(("(0,0)", 845.0),))
    assert modes.fidelity == "solid"
    assert "plate model: model error" in modes.fidelity_note and "> tol 0.0010%" in modes.fidelity_note


def test_reduced_models_refuse_what_they_cannot_represent():
    from modalfe.errors import SceneError

    with pytest.raises(SceneError, match="fidelity: 'beam' does not apply"):
        solve_modes(load_scene("cube_plate"), fidelity="beam")
    with pytest.raises(SceneError, match="not a plate"):
        solve_modes(replace(cantilever_scene(2.5e-3), kind="plate"), fidelity="plate")


def test_report_takes_k_eff_from_the_solid_when_the_plate_answers():
    from modalfe.report.report import device_report

    scene = load_scene("cube_plate")
    (row,) = device_report(scene, tol=0.02)  # the plate states 1.40 %: it answers at 2 %, not at the report's 0.5 %
    assert row.fidelity == "plate"

    def coupling(fidelity):
        fr = solve_modes(scene, fidelity=fidelity, error_estimate=False).labelled("(0,6)", near=40e3).frequency
        fa = solve_modes(scene, fidelity=fidelity, circuit="open", error_estimate=False).labelled(
            "(0,6)", near=fr).frequency
        return analytic.k_eff(fr, fa)

    solid, plate = coupling("solid"), coupling("plate")
    # the solid's fa / fr at the cross-check level (elements 1.5x larger) gives k_eff 0.1545 against 0.1509
    # on the default mesh (+2.4 %, measured): 5 % is twice that
    assert row.k_eff == pytest.approx(solid, rel=0.05)
    # why not the plate's own: its uniform-field, perfectly bonded ceramics give 0.173 (+15 %)
    assert abs(plate / solid - 1) > 0.10
