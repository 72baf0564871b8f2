"""Frequency and k_eff sensitivities (modalfe/response/sensitivity.py): exact identities of the discrete model,
Kirchhoff scaling of a thin plate, and central finite differences of full solves on the moved mesh, the modes
paired by shape (MAC), for a dimension, a material constant, a spring stiffness and an attached mass.

Error budget in d ln f / d ln p (an O(1) number, so errors are compared in it, not relative to a derivative that
may be near 0): the sensitivities' central differences of the matrices (``RELATIVE_STEP``) err by up to 6e-6 on
these cases (the ciliary beam's first mode against its sheets' position; below 1e-6 elsewhere); the references,
central differences of full solves at p +- 1e-3 |p|, by their truncation (H^2 / 6) f''' / f' < 1e-6 (measured by
halving H) plus the eigen solve's round-off (~1e-12 of f) over 2H, 1e-9. Hence LOG_ERROR = 2e-5.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from modalfe.errors import SceneError
from modalfe.response.sensitivity import frequency_sensitivities, perturbed_model
from modalfe.results.coupling import k_eff
from modalfe.scene import load_scene, scene_from_dict
from modalfe.solve.estimates import shape_partners
from modalfe.solve.levels import modes_of, solve_level

REFERENCE_STEP = 1e-3  # relative step of the finite differences of full solves (module docstring)
LOG_ERROR = 2e-5  # bound on the difference in d ln f / d ln p (module docstring)
STEEL = {"E": 200e9, "nu": 0.3, "rho": 7800.0}
BRASS = {"E": 105e9, "nu": 0.34, "rho": 8500.0}  # the library's brass-seed003, copied into the scene


def _plate(size_mm: tuple[float, float, float], near: float, count: int, max_size: float, **extra):
    """A free steel plate of ``size_mm`` [mm] on a uniform structured mesh of ``max_size`` [m]."""
    return scene_from_dict({
        "name": "plate", "units": "mm", "kind": "plate", "materials": {"steel": STEEL},
        "parts": [{"name": "plate", "material": "steel", "origin": [0, 0, 0], "size": list(size_mm)}],
        "analysis": {"near": near, "count": count},
        "mesh": {"elements_per_wavelength": 1.0, "max_size": max_size, "min_layers": 2}, **extra,
    })


def _reference(modes, parameter: str, value: float, circuit: str = "short") -> tuple[np.ndarray, dict]:
    """(df/dp [Hz per unit] of every mode by central differences of full solves of the moved mesh at p +- H,
    p = ``value``, the ``circuit`` solves' partners {mode index: (mode at p + H, mode at p - H)} paired by MAC)."""
    model, analysis = modes.model, modes.model.scene.analysis
    H = REFERENCE_STEP * abs(value)
    wider = replace(analysis, count=len(modes) + 2, circuit=circuit)
    plus, minus = (modes_of(perturbed_model(model, parameter, value + s * H), wider, fidelity="solid")
                   for s in (1, -1))
    up, down = shape_partners(modes, plus), shape_partners(modes, minus)
    assert set(up) == set(down) == {m.index for m in modes}  # every mode found again by its shape
    pairs = {i: (up[i][0], down[i][0]) for i in up}
    return np.array([(pairs[i][0].frequency - pairs[i][1].frequency) / (2 * H) for i in sorted(pairs)]), pairs


# ---------------------------------------------------------------------------------------------
# exact identities of the discrete model


@pytest.fixture(scope="module")
def free_plate():
    """Three elastic modes (no rigid body mode: those sit 15 kHz below the shift) of a free 40 x 10 x 2 mm plate."""
    scene = _plate((40, 10, 2), 15e3, 3, 2.5e-3)
    return solve_level(scene, scene.analysis)


# rotated (25 s: every element through the general path) with -m slow; tests/models/test_fast_assembly.py checks
# the general path against the fast one by default
@pytest.mark.parametrize("rotated", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_discrete_scaling_identities(free_plate, rotated):
    """K = E K1(nu) and M = rho M1, so f ~ sqrt(E / rho) exactly; and scaling every side of a box by s scales K by
    s and M by s^3 (f ~ 1/s), so by Euler's theorem the log-derivatives over the three sides sum to -1. Also with
    the device rotated (its elements assembled by the general path, the moved nodes rotated back and forth)."""
    modes = free_plate
    if rotated:
        c, s = np.cos(0.7), np.sin(0.7)
        frame = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, c, s], [0, -s, c]])
        modes = solve_level(free_plate.model.scene, free_plate.model.scene.analysis, frame=frame)
    names = ["materials.steel.E", "materials.steel.rho", "parts.plate.size.x", "parts.plate.size.y",
             "parts.plate.size.z"]
    d = frequency_sensitivities(modes, names).relative
    assert np.all(modes.frequencies > 1e3)
    # K is linear in E: no truncation; what is left is round-off of the matrices' difference, 2e-8 measured
    assert np.abs(d[:, 0] - 0.5).max() < 1e-6
    # M is linear in rho and K does not depend on it: round-off only, 1.5e-13 measured
    assert np.abs(d[:, 1] + 0.5).max() < 1e-10
    # truncation ~200 (h/|p|)^2 through the 2 mm thickness (RELATIVE_STEP) plus round-off: 3e-7 measured
    assert np.abs(d[:, 2:].sum(axis=1) + 1).max() < 2e-6


def test_thin_plate_follows_kirchhoff_scaling():
    """Bending of a long thin plate: f ~ t / L^2 (Kirchhoff). The 3-D solid departs from it through shear and
    rotary inertia, f = f_K (1 - delta) with delta = (k r)^2 (1 + 2 (1 + nu) / kappa) / 2 (Timoshenko beam,
    r^2 = t^2 / 12, k the bending wavenumber, kappa = 5/6), which grows like (t / L)^2, so d ln f / d ln t =
    1 - 2 delta and d ln f / d ln L = -2 + 2 delta; and through the anticlastic transition between beam and plate
    stiffness, which depends on t too (through W^2 / (R t), R the bending radius: Ashwell, Phil. Mag. 41 (1950) 820)
    and pulls the other way on L: measured |d ln f / d ln t - 1| = 1.3 and 1.4 times 2 delta, |d ln f / d ln L + 2|
    below 1e-4. The bound 4 delta holds both with a margin, and the sign of the shear correction is checked."""
    t, L = 1e-3, 60e-3
    scene = _plate((60, 10, 1), 5e3, 3, 2.5e-3)
    modes = solve_level(scene, scene.analysis)
    d = frequency_sensitivities(modes, ["parts.plate.size.z", "parts.plate.size.x"])
    for label, beta in (("(0,2)", 4.730), ("(0,3)", 7.853)):  # free-free beam: k L = beta
        thickness, length = d.relative[[m.label for m in modes].index(label)]
        delta = 0.5 * (beta / L) ** 2 * t**2 / 12 * (1 + 2 * 1.3 / (5 / 6))  # 1.1e-3 and 2.9e-3
        assert 0 < 1 - thickness < 4 * delta, (label, thickness, delta)
        assert abs(length + 2) < 4 * delta, (label, length, delta)


# ---------------------------------------------------------------------------------------------
# against central finite differences of full solves


@pytest.fixture(scope="module")
def ciliary():
    """The piezoelectric ciliary beam on a coarse mesh, short- and open-circuit modes of one model."""
    scene = load_scene("ciliary_beam").with_overrides(**{"materials.brass-seed003": BRASS})
    short = solve_level(scene, scene.analysis, size_factor=3.0)
    return short, solve_level(scene, replace(scene.analysis, circuit="open"), size_factor=3.0)


@pytest.mark.parametrize("parameter", ["x0", "materials.brass-seed003.E"])
def test_ciliary_beam_against_full_solves(ciliary, parameter):
    """The sheets' position (moves the mesh's interior breakpoints) and the beam's modulus: df/dp of every mode
    and dk_eff/dp of the coupled ones agree with central differences of full solves."""
    short, open_modes = ciliary
    d = frequency_sensitivities(short, [parameter], open_modes=open_modes)
    value, f = d.values[0], short.frequencies
    reference, pairs_short = _reference(short, parameter, value)
    error = np.abs(d.dfrequency[:, 0] - reference) * value / f  # in d ln f / d ln p
    assert error.max() < LOG_ERROR  # 5.4e-6 (x0), 1.7e-6 (E) measured
    _, pairs_open = _reference(open_modes, parameter, value, "open")
    partners = shape_partners(short, open_modes)
    H = REFERENCE_STEP * abs(value)
    coupled = [i for i in partners if d.k_eff[i] > 0.05]
    assert len(coupled) >= 3
    for i in coupled:
        j = partners[i][0].index
        k_up = k_eff(pairs_short[i][0].frequency, pairs_open[j][0].frequency)
        k_down = k_eff(pairs_short[i][1].frequency, pairs_open[j][1].frequency)
        dk = (k_up - k_down) / (2 * H)
        # an error e in d ln f becomes ~ e / k^2 in d ln k (the sensitivity's docstring); 7e-5 measured at most
        assert abs(d.dk_eff[i, 0] - dk) * value / d.k_eff[i] < LOG_ERROR / d.k_eff[i] ** 2


def test_springs_and_masses_against_full_solves():
    """A plate on face springs with a mass on its top face: its six suspension modes and its first elastic one against
    central differences of full solves, for the springs scaled together, one spring component and the mass."""
    scene = _plate((30, 10, 2), 800.0, 7, 2.5e-3, faces={"base": ["plate.zmin"], "top": ["plate.zmax"]},
                   springs={"base": [3e4, 5e4, 1e5]}, masses={"top": 0.01})
    modes = solve_level(scene, scene.analysis)
    names = ["springs.base", "springs.base.z", "masses.top"]
    d = frequency_sensitivities(modes, names)
    for j, name in enumerate(names):
        reference, _ = _reference(modes, name, d.values[j])
        error = np.abs(d.dfrequency[:, j] - reference) * d.values[j] / modes.frequencies
        assert error.max() < LOG_ERROR  # 8.8e-7, 6.4e-7, 1.4e-7 measured


# ---------------------------------------------------------------------------------------------
# refusals


def test_unknown_and_unusable_parameters(free_plate, ciliary):
    for modes, name, message in (
        (free_plate, "bogus", "bogus: not a parameter"),
        (free_plate, "materials.steel.G", "materials.steel.G: the scene defines no such constant"),
        (free_plate, "springs.base", "springs.base: no such spring"),
        (free_plate, "parts.plate.size.w", "parts.plate.size.w: give parts.PART"),
        (ciliary[0], "beam_material", "beam_material: a str parameter"),
        (ciliary[0], "materials.PZT-5A.E", "materials.PZT-5A.E: the scene defines no such constant"),
        (ciliary[0], "materials.PZT-4.d31", r"materials.PZT-4.d31: no part is made of 'PZT-4'"),
        (free_plate, "materials.steel.e33", "materials.steel.e33: 'steel' is not piezoelectric"),
    ):
        with pytest.raises(SceneError, match=message):
            frequency_sensitivities(modes, [name])


def test_topology_change_is_refused():
    """A block on a plate moved so that its face crosses the plate's end (the breakpoints change order), or
    meets it (two breakpoints merge): no mesh of the same topology fits."""
    scene = scene_from_dict({
        "name": "two-boxes", "units": "mm", "kind": "plate", "materials": {"steel": STEEL},
        "parts": [{"name": "plate", "material": "steel", "origin": [0, 0, 0], "size": [6, 4, 1]},
                  {"name": "block", "material": "steel", "origin": [1, 1, 1], "size": [2, 2, 1]}],
        "analysis": {"near": 1e5, "count": 2},
        "mesh": {"elements_per_wavelength": 1.0, "max_size": 1e-3, "min_layers": 1},
    })
    model = solve_level(scene, scene.analysis).model
    moved = perturbed_model(model, "parts.block.origin.x", 1.5e-3)  # breakpoints 0, 1.5, 3.5, 6 mm: same order
    assert moved.K.shape == model.K.shape and abs(moved.mesh.mesh.p[0].max() - 6e-3) < 1e-15
    # 4.5 mm: the block (4.5..6.5) ends past the plate (0..6), breakpoints 0, 4.5, 6, 6.5 in another order;
    # 4 mm: its end meets the plate's, breakpoints 0, 4, 6 (one fewer)
    for x in (4.5e-3, 4e-3):
        with pytest.raises(SceneError, match=r"parts\.block\.origin\.x: changes the order of the part faces along x"):
            perturbed_model(model, "parts.block.origin.x", x)


def test_reduced_models_are_refused(ciliary):
    scene = ciliary[0].model.scene
    beam = solve_level(scene, scene.analysis, fidelity="beam")
    with pytest.raises(SceneError, match="need modes of the 3-D solid model"):
        frequency_sensitivities(beam, ["x0"])


def test_a_tie_moves_its_members_together_so_a_half_model_keeps_its_mirror_images():
    """issue 35: docs/calibration.md's `--vary springs.foot_*.z` on cube_plate (a half model about y) was refused:
    each foot's spring was moved alone, which leaves it without its mirror image; the tie moves them together."""
    from modalfe.design.tuning import check_variables
    from modalfe.response.sensitivity import parameter_value, with_values

    scene = load_scene("cube_plate", **{f"springs.foot_{i}": [0, 0, 1e6] for i in range(1, 5)})
    tied = with_values(scene, {"springs.foot_*.z": 2e6})
    assert set(tied.springs.values()) == {(0.0, 0.0, 2e6)} and tied.symmetry == ("y",)
    assert parameter_value(tied, "springs.foot_*.z") == 2e6
    check_variables(scene, ["springs.foot_*.z"])
    with pytest.raises(SceneError, match=r"^symmetry: springs\.foot_1 has no mirror image"):
        with_values(scene, {"springs.foot_1.z": 2e6})  # one foot alone: refused as before


def test_a_ties_derivative_is_the_sum_of_its_members():
    from modalfe.solve.api import solve_modes
    from tests.design.test_calibration import _strip_on_springs

    modes = solve_modes(_strip_on_springs(2e4, 2e4), near=1500.0, count=6, fidelity="solid", error_estimate=False)
    found = frequency_sensitivities(modes, ["springs.foot_*.z", "springs.foot_1.z", "springs.foot_2.z"])
    elastic = np.isfinite(found.dfrequency[:, 0])
    assert elastic.sum() >= 2 and len(modes) == 6
    # K is linear in each stiffness: the central differences are exact, one step of all equals the sum of each's
    np.testing.assert_allclose(found.dfrequency[elastic, 0], found.dfrequency[elastic, 1:].sum(axis=1), rtol=1e-8)
