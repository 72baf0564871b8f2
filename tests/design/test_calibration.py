"""Model updating (modalfe/design/calibration.py): synthetic truth recovered from exact and noisy data, the
unidentifiable pair named, the covariance's sigma scaling, and refusals of bad measurement files."""

import math

import numpy as np
import pytest

from modalfe.design.calibration import (
    calibrate,
)
from modalfe.design.measurements import Measurement, measurements_from_dict, read_measurements
from modalfe.design.multistart import latin_hypercube
from modalfe.errors import SceneError, SolverError
from modalfe.response.sensitivity import with_values
from modalfe.scene import scene_from_dict
from modalfe.solve.api import solve_modes

E, NU, RHO = 200e9, 0.3, 7850.0
LENGTH = 59e-3  # not a multiple of the 3 mm elements: the element count does not jump at the truth


def _strip(E: float = E, nu: float = NU, length: float = LENGTH):
    """A free 59 x 10 x 1 mm steel strip, 3 mm elements (2049 DOFs): (0,2) ~1492 Hz, (0,3) ~4127 Hz,
    (1,1) ~5200 Hz (torsion)."""
    return scene_from_dict({
        "name": "strip", "units": "mm", "kind": "plate",
        "materials": {"steel": {"E": E, "nu": nu, "rho": RHO}},
        "parts": [{"name": "strip", "material": "steel", "origin": [0, 0, 0], "size": [1e3 * length, 10, 1]}],
        "mesh": {"max_size": 3e-3, "elements_per_wavelength": 1, "min_layers": 1},
        "analysis": {"near": 3000.0, "count": 6},
    })


# the data of ``_truth`` are exact on the scene's own mesh: fitted there (the second stage on the same mesh), the
# algebra is checked without the discretization offset the resolved model would add
OWN_MESH = {"error_estimate": False}


def _truth(labels, *, relative_sigma=1e-3, wavelength_sigma=None, near=4000.0, count=10):
    """Exact measurements of the strip at the true parameters (same mesh generator, so zero residual there)."""
    modes = solve_modes(_strip(), near=near, count=count, fidelity="solid", error_estimate=False)
    out = []
    for label in labels:
        mode = modes.labelled(label)
        extra = {} if wavelength_sigma is None else {"wavelength": mode.wavelength,
                                                     "wavelength_sigma": wavelength_sigma * mode.wavelength}
        out.append(Measurement(label, mode.frequency, relative_sigma * mode.frequency, **extra))
    return out


def test_exact_frequencies_recover_modulus_and_poisson_ratio():
    """E and nu from the bending modes (0,2), (0,3) (f ~ sqrt(E / (1 - nu^2))) and the torsion mode (1,1)
    (f ~ sqrt(G) = sqrt(E / 2(1 + nu))): started 15 % and 13 % off, exact data give them back to the Gauss-Newton
    tolerance (relative 1e-5 on the step; the sensitivities' own error, 1e-4 relative, only slows convergence),
    and the truth lies within the posterior sd (here tiny: sigma 0.1 %)."""
    measured = _truth(["(0,2)", "(0,3)", "(1,1)"])
    steps = []
    result = calibrate(_strip(E=1.15 * E, nu=0.26), measured, ["materials.steel.E", "materials.steel.nu"],
                       progress=lambda k, it: steps.append(k))
    assert result.converged, result.reason
    assert result.values[0] == pytest.approx(E, rel=1e-4) and result.values[1] == pytest.approx(NU, rel=1e-4)
    assert np.all(np.abs(result.values - [E, NU]) <= np.maximum(result.sd, 1e-4 * np.abs(result.values)))
    assert np.max(np.abs(result.residuals)) < 0.1 and result.unidentified == ()
    assert steps == list(range(1, result.solves + 1)) and result.solves <= 8
    assert result.dof == 1 and result.covariance_basis.startswith("stated sigmas")


@pytest.mark.slow
def test_frequencies_and_wavelengths_recover_modulus_and_length():
    """f ~ sqrt(E) / L^2 for every bending mode, so frequencies alone fix only E^0.5 / L^2; the wavelengths
    (~ L) separate them. Started 15 % and 12 % off: back within 1e-4 (measured 4 solves, E within 1e-6)."""
    measured = _truth(["(0,2)", "(0,3)"], wavelength_sigma=0.01)
    start = with_values(_strip(E=1.15 * E), {"parts.strip.size.x": 0.88 * LENGTH})
    result = calibrate(start, measured, ["materials.steel.E", "parts.strip.size.x"])
    assert result.converged, result.reason
    assert result.values == pytest.approx([E, LENGTH], rel=1e-4)
    assert result.quantities[2:] == ("(0,2) wavelength", "(0,3) wavelength") and result.unidentified == ()


def test_modulus_and_density_together_are_named_unidentifiable():
    """f ~ sqrt(E / rho) exactly (K linear in E, M in rho): the weighted Jacobian has rank 1, the pair is named
    and the combination the data fix is E^1 * rho^-1 (exponents normalised to the largest); the fit still meets
    the data (the minimum-norm step moves along the identified direction only)."""
    measured = _truth(["(0,2)", "(0,3)"])
    result = calibrate(_strip(E=1.1 * E), measured, ["materials.steel.E", "materials.steel.rho"])
    assert result.converged and np.max(np.abs(result.residuals)) < 0.1
    assert result.singular_values[1] < 1e-3 * result.singular_values[0]
    (statement,) = result.unidentified
    assert statement == ("materials.steel.E and materials.steel.rho are not separately identifiable: only "
                         "materials.steel.E*materials.steel.rho^-1 is")
    assert abs(result.correlation[0, 1]) > 0.999  # the pair moves together along the valley
    ratio = result.values[0] / result.values[1]
    assert ratio == pytest.approx(E / RHO, rel=1e-4)


def test_inconsistent_data_scale_the_covariance_by_the_residual_variance():
    """One parameter, three frequencies shifted by +1 %, -1 %, 0 with sigma 0.1 %: no E fits them all, so
    chi2 / dof >> 1 and the Gauss-Newton variance 1 / sum J_i^2 (J_i = d f_i / d ln E / sigma_i = f_i / 2 sigma_i)
    is multiplied by chi2 / dof; with sigma 5 % the same data are consistent and the variance is left alone."""
    exact = _truth(["(0,2)", "(0,3)", "(1,1)"])
    for sigma, scaled in ((1e-3, True), (5e-2, False)):
        measured = [Measurement(m.label, m.frequency * (1 + shift), sigma * m.frequency)
                    for m, shift in zip(exact, (0.01, -0.01, 0.0))]
        result = calibrate(_strip(E=1.1 * E), measured, ["materials.steel.E"], resolution=OWN_MESH)
        chi2_dof = result.chi2 / result.dof
        J = result.predicted * 0.5 / np.array([m.sigma for m in measured])  # d ln f / d ln E = 1/2
        expected = math.sqrt((chi2_dof if scaled else 1.0) / np.sum(J**2)) * result.values[0]
        assert result.dof == 2 and (chi2_dof > 1) == scaled
        assert result.scale == pytest.approx(chi2_dof if scaled else 1.0)
        assert result.covariance_basis.startswith("residual variance" if scaled else "stated sigmas")
        assert result.sd[0] == pytest.approx(expected, rel=1e-3)  # d ln f / d ln E = 1/2 to 1e-4 (sensitivity)
        assert result.values[0] == pytest.approx(E, rel=2e-3)  # shifts of +-1 % in f average out in ln E


def test_a_value_the_bounds_exclude_is_held_on_the_bound_and_said():
    """The (0,2) frequency of E = 220 GPa with E limited to 210 GPa: the fit stops on the bound, names it, and the
    model's frequency is that of 210 GPa (f ~ sqrt(E) exactly, K linear in E; to the sensitivities' 1e-4)."""
    (exact,) = _truth(["(0,2)"])
    measured = [Measurement("(0,2)", exact.frequency * math.sqrt(1.1), 1.0)]
    result = calibrate(_strip(), measured, ["materials.steel.E"], bounds={"materials.steel.E": (150e9, 210e9)},
                       resolution=OWN_MESH)
    assert result.converged and "held on their bounds (the data pull them beyond): materials.steel.E" in result.reason
    assert result.values[0] == pytest.approx(210e9, rel=1e-12)
    assert result.predicted[0] == pytest.approx(exact.frequency * math.sqrt(1.05), rel=1e-4)


def test_latin_hypercube_puts_one_start_in_each_slice():
    starts = latin_hypercube({"a": (1.0, 100.0), "b": (-8.0, -2.0)}, 5, seed=3)
    slices = sorted(int(5 * math.log(s["a"]) / math.log(100.0)) for s in starts)
    assert slices == [0, 1, 2, 3, 4] and all(-8.0 <= s["b"] <= -2.0 for s in starts)
    assert starts == latin_hypercube({"a": (1.0, 100.0), "b": (-8.0, -2.0)}, 5, seed=3)


GOOD = '[[mode]]\nlabel = "(0,6)"\nfrequency = 40.7e3\nsigma = 50.0\nwavelength = 7.5e-3\nwavelength_sigma = 0.05e-3\n'


def test_a_measurement_file_is_read(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(GOOD)
    (m,) = read_measurements(path)
    assert (m.label, m.frequency, m.sigma, m.wavelength, m.wavelength_sigma) == ("(0,6)", 40.7e3, 50.0, 7.5e-3,
                                                                                 0.05e-3)


@pytest.mark.parametrize(("text", "message"), [
    ('[[mode]]\nlabel = "(0,6)"\nfrequency = 40.7e3\n', "mode[0].sigma: required"),
    ('[[mode]]\nlabel = "(0,6)"\nfrequency = -1.0\nsigma = 50.0\n', "mode[0].frequency: must be a positive"),
    ('[[mode]]\nfrequency = 40.7e3\nsigma = 50.0\n', "mode[0].label: required"),
    ('[[mode]]\nlabel = "(0,6)"\nfrequency = 40.7e3\nsigma = 50.0\nwavelength = 7e-3\n',
     "mode[0].wavelength_sigma: required with wavelength"),
    ('[[mode]]\nlabel = "(0,6)"\nfrequency = 40.7e3\nsigma = 50.0\nfreq = 1.0\n', "mode[0].freq: unknown field"),
    ('[[mode]]\nlabel = "(0,6)"\nfrequency = "40 kHz"\nsigma = 50.0\n', "mode[0].frequency: must be a positive"),
    (GOOD + GOOD, "mode[1].label: '(0,6)' measured twice"),
    ('title = "x"\n', "title: expected only [[mode]] tables"),
    ("[[mode]\n", "not valid TOML"),
])
def test_bad_measurement_files_are_refused_in_one_line(tmp_path, text, message):
    path = tmp_path / "m.toml"
    path.write_text(text)
    with pytest.raises(SceneError, match=None) as info:
        read_measurements(path)
    assert message in str(info.value) and str(path) in str(info.value)


def test_refusals_name_the_field():
    measured = measurements_from_dict({"mode": [{"label": "(0,2)", "frequency": 1500.0, "sigma": 5.0}]})
    strip = _strip()
    cases = [
        (["materials.steel.E", "materials.steel.E"], {}, "vary: give one or more distinct"),
        (["materials.steel.E"], {"materials.steel.nu": (0.2, 0.4)}, "bounds: materials.steel.nu is not among"),
        (["materials.steel.E"], {"materials.steel.E": (3e11, 4e11)}, "materials.steel.E: 2e+11 lies outside"),
        (["materials.steel.E"], {"materials.steel.E": (-1e11, 4e11)}, "bounds materials.steel.E: needs LOW < HIGH"),
        (["springs.foot_*.z"], {}, "springs.foot_*.z: matches no springs group"),
        (["thickness"], {}, "thickness: not a parameter"),
    ]
    for names, bounds, message in cases:
        with pytest.raises(SceneError) as info:
            calibrate(strip, measured, names, bounds=bounds)
        assert message in str(info.value)
    from modalfe.scene import load_scene

    with pytest.raises(SceneError, match=r"^vary: width cannot change in 'cube_plate' \(symmetry: .*; solve the "
                                         r"whole device: --set 'symmetry=\[\]'$"):
        calibrate(load_scene("cube_plate"), measured, ["width"])


def test_the_step_holds_a_parameter_its_gauss_newton_step_pushes_off_its_bound():
    """One rule for bounds (_bounded_step, no solve): with J = [[1, 1], [0, 0.1]] and r = [-2, -0.3] the
    unconstrained Gauss-Newton step is -J^-1 r = (-1, 3); parameter 0 sits on its lower bound and the descent
    direction -J^T r = (2, 2.03) pulls it inward, yet the step pushes it outward: it is held and the step of
    parameter 1 alone is the one-column least squares -(J_1 . r) / |J_1|^2 = 2.03 / 1.01 (clipping (-1, 3)
    instead would keep parameter 1's 3, the wrong step for the held design)."""
    from modalfe.design.calibration import _bounded_step

    J, r = np.array([[1.0, 1.0], [0.0, 0.1]]), np.array([-2.0, -0.3])
    x, low, high = np.zeros(2), np.array([0.0, -5.0]), np.array([5.0, 5.0])
    step, held = _bounded_step(J, r, math.inf, x, low, high)
    assert held.tolist() == [True, False]
    assert step == pytest.approx([0.0, 2.03 / 1.01], rel=1e-12)
    step, held = _bounded_step(J, r, math.inf, np.array([1.0, 0.0]), low, high)  # off the bound: free
    assert not held.any() and step == pytest.approx([-1.0, 3.0], rel=1e-12)
    step, held = _bounded_step(J, r, math.inf, np.array([1.0, 0.0]), np.array([0.5, -5.0]), high)
    assert step[0] == pytest.approx(-0.5) and not held.any()  # a free step onto a bound is clipped there


def _strip_on_springs(k1: float, k2: float):
    """The strip with z springs [N/m] on its two end faces, groups foot_1 and foot_2."""
    return scene_from_dict({
        "name": "strip", "units": "mm", "kind": "plate",
        "materials": {"steel": {"E": E, "nu": NU, "rho": RHO}},
        "parts": [{"name": "strip", "material": "steel", "origin": [0, 0, 0], "size": [1e3 * LENGTH, 10, 1]}],
        "faces": {"foot_1": ["strip.xmin"], "foot_2": ["strip.xmax"]},
        "springs": {"foot_1": [0.0, 0.0, k1], "foot_2": [0.0, 0.0, k2]},
        "mesh": {"max_size": 3e-3, "elements_per_wavelength": 1, "min_layers": 1},
        "analysis": {"near": 3000.0, "count": 6},
    })


def test_a_pattern_ties_the_springs_to_one_value():
    """``springs.foot_*.z`` is one unknown for both end springs: the (0,2) frequency of the strip on 2e4 N/m
    springs (exact data, same mesh) gives 2e4 back from 1.5e4 on both, to the Gauss-Newton tolerance (1e-4
    relative, as the free strip's E), and the fitted scene carries the same value on both; springs that do not
    start equal are refused, naming the pattern."""
    truth = solve_modes(_strip_on_springs(2e4, 2e4), near=1500.0, count=8, fidelity="solid", error_estimate=False)
    mode = truth.labelled("(0,2)")
    measured = [Measurement("(0,2)", mode.frequency, 1e-3 * mode.frequency)]
    result = calibrate(_strip_on_springs(1.5e4, 1.5e4), measured, ["springs.foot_*.z"])
    assert result.converged, result.reason
    assert result.parameters == ("springs.foot_*.z",) and result.values[0] == pytest.approx(2e4, rel=1e-4)
    assert result.scene.springs["foot_1"] == result.scene.springs["foot_2"]
    with pytest.raises(SceneError, match=r"^springs\.foot_\*\.z: the tied parameters"):
        calibrate(_strip_on_springs(1.5e4, 1.6e4), measured, ["springs.foot_*.z"])


def test_a_mode_whose_label_vanishes_is_found_by_its_shape():
    """_solve's fallback: a measured label the solve does not hold (here "(5,5)", near the (0,2) mode) takes the
    mode most alike in shape (MAC) to the last point's mode, so a relabelled mode is still followed; without a last
    point the measurement is refused, naming it."""
    from modalfe.design.calibration import _solve

    scene = _strip()
    modes = solve_modes(scene, near=1500.0, count=6, fidelity="solid", error_estimate=False)
    previous = modes.labelled("(0,2)")
    lost = [Measurement("(5,5)", previous.frequency, 1.0)]
    point = _solve(scene, lost, [previous.frequency], np.zeros(1), previous=(previous,))
    assert point.modes[0].label == "(0,2)"
    assert point.modes[0].frequency == pytest.approx(previous.frequency, rel=1e-9)  # the same scene and mesh
    with pytest.raises(SolverError, match=r"^calibrate: the measured mode \(5,5\) is not found"):
        _solve(scene, lost, [previous.frequency], np.zeros(1))


def test_uncertainties_include_the_resolved_models_stated_error():
    """The second stage fits on the model resolved to 0.5 %: each frequency's sigma becomes sqrt(sigma_measured^2 +
    (stated error x f)^2), so a measurement far sharper than the model's error no longer claims a sharp E; on the
    scene's own mesh (no estimate) the sigma stays the measured one and the result says so."""
    measured = _truth(["(0,2)"], relative_sigma=1e-5)
    resolved = calibrate(_strip(E=1.1 * E), measured, ["materials.steel.E"])
    own = calibrate(_strip(E=1.1 * E), measured, ["materials.steel.E"], resolution=OWN_MESH)
    (mode_error,) = np.sqrt(resolved.sigma**2 - np.array([m.sigma for m in measured]) ** 2) / resolved.predicted
    assert 0 < mode_error <= 0.005 and "stated discretization error added" in resolved.reason
    assert own.sigma[0] == measured[0].sigma and "not estimated for (0,2)" in own.reason
    # sd of ln E ~ 2 sigma / f: the stated error dominates the 1e-5 measurement
    assert resolved.sd[0] / resolved.values[0] == pytest.approx(2 * mode_error, rel=0.05)
    assert resolved.sd[0] > 50 * own.sd[0]
