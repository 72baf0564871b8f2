"""Sensitivities of a working mode's amplitude per volt at resonance (``amplitude_sensitivities`` in
modalfe/response/sensitivity.py): exact scaling identities of the discrete piezoelectric model, and central finite
differences of full solves (eigen solve of the moved mesh, the mode paired by shape, then ``reduce``) for a
dimension, a material constant, a spring stiffness and a piezo patch's thickness, with modal and Rayleigh damping.

The device: a steel cantilever 30 x 6 x 1 mm with a PZT-5A patch (12 x 6 x 0.5 mm, poled through its thickness,
driven on its top face, grounded on its bottom) near the root and a 10 kN/m spring under its free end; outputs the
free end's face centre (it moves with the length) and a point fixed in space mid-element on the top face (the mesh
moves under it). 1500 unknowns, a solve in ~0.3 s.

Error budget in d ln A / d ln p (an O(1) number): the references, central differences of full solves at
p +- H with H = 3e-4 |p|, err by their truncation (H^2 / 6) A''' / A': measured at H = 1e-3 |p| by halving H (the
difference fell by 3/4, as an H^2 term does), at most 6.2e-5 (the fixed point against the length, Rayleigh
damping), so 5.6e-6 at H = 3e-4; plus the solves' round-off (~1e-10 of A) over 2H, 2e-7. The sensitivities' own
central differences of the matrices (``RELATIVE_STEP``) are 1e-2 of that (Richardson-extrapolated references agree
to 2e-7). Hence LOG_ERROR = 2e-5.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp

from modalfe.errors import SceneError, SolverError
from modalfe.response.forced import Damping, reduce
from modalfe.response.losses import mode_damping, resolve_losses
from modalfe.response.sensitivity import amplitude_derivatives, amplitude_sensitivities, perturbed_model
from modalfe.scene import scene_from_dict
from modalfe.solve.estimates import shape_partners
from modalfe.solve.levels import modes_of, solve_level

REFERENCE_STEP = 3e-4  # relative step of the finite differences of full solves (module docstring)
LOG_ERROR = 2e-5  # bound on the difference in d ln A / d ln p (module docstring)
OUTPUTS = ("tip", ("mid", (0.021, 0.003, 0.001)))
STEEL = {"E": 200e9, "nu": 0.3, "rho": 7800.0}


def _cantilever(**extra):
    return scene_from_dict({
        "name": "patch-cantilever", "units": "mm", "kind": "beam", "materials": {"steel": STEEL},
        "parts": [{"name": "plate", "material": "steel", "origin": [0, 0, 0], "size": [30, 6, 1]},
                  {"name": "patch", "region": "piezo", "material": "PZT-5A", "origin": [2, 0, 1],
                   "size": [12, 6, 0.5], "poling": 1}],
        "faces": {"root": ["plate.xmin"], "tip": ["plate.xmax"], "top": ["patch.zmax"], "bottom": ["patch.zmin"]},
        "clamps": {"root": "xyz"}, "springs": {"tip": [0.0, 0.0, 1e4]},
        "electrodes": {"top": "drive", "bottom": "ground"},
        "analysis": {"near": 30e3, "count": 4},
        "mesh": {"elements_per_wavelength": 1.0, "max_size": 2e-3, "min_layers": 1}, **extra,
    })


@pytest.fixture(scope="module")
def cantilever():
    """The cantilever's modes; the first (bending, 16.3 kHz) is the working mode."""
    scene = _cantilever()
    return solve_level(scene, scene.analysis)


def _amplitudes(mode, damping: Damping) -> np.ndarray:
    rom = reduce(mode, outputs=OUTPUTS, damping=damping)
    return np.array([rom.amplitude_per_volt(name) for name in ("tip", "mid")])


def test_amplitude_is_the_reduced_models(cantilever):
    """The amplitude the derivative is of is ``ReducedModel.amplitude_per_volt``, to round-off."""
    mode = cantilever[0]
    for damping in (Damping(Q=100), Damping(alpha=2e3, beta=2e-8)):
        found = amplitude_sensitivities(cantilever, [], mode=mode, outputs=OUTPUTS, damping=damping)
        assert found.outputs == ("tip", "mid")
        np.testing.assert_allclose(found.amplitude, _amplitudes(mode, damping), rtol=1e-10)


@pytest.mark.parametrize(("damping", "names"), [
    (Damping(Q=100), ["parts.plate.size.x", "materials.steel.E", "springs.tip.z", "parts.patch.size.z",
                      "materials.PZT-5A.d31"]),
    (Damping(alpha=2e3, beta=2e-8), ["parts.plate.size.x", "materials.steel.E"]),
], ids=["Q", "rayleigh"])
def test_against_full_solves(cantilever, damping, names):
    """The plate's length (moves the tip output and the mesh under the fixed one), the steel's modulus, the tip
    spring, the patch's thickness and its d31 (at fixed s^E, eps^T: e and eps^S change): d ln A / d ln p against
    central differences of full solves and reductions; with Rayleigh damping zeta moves with the frequency too."""
    mode = cantilever[0]
    found = amplitude_sensitivities(cantilever, names, mode=mode, outputs=OUTPUTS, damping=damping)
    wider = replace(cantilever.model.scene.analysis, count=len(cantilever) + 2)
    errors = []
    for j, name in enumerate(names):
        value = found.modal.values[j]
        H = REFERENCE_STEP * abs(value)
        amplitudes = []
        for sign in (1, -1):
            moved = modes_of(perturbed_model(mode.model, name, value + sign * H), wider, fidelity="solid")
            amplitudes.append(_amplitudes(shape_partners(cantilever, moved)[mode.index][0], damping))
        reference = (amplitudes[0] - amplitudes[1]) / (2 * H) * value / found.amplitude
        errors.append(np.abs(found.relative[:, j] - reference).max())
        # the frequency's derivative comes along from the same matrices: the modal one
        assert found.dfrequency[j] == pytest.approx(found.modal.dfrequency[mode.index, j], rel=1e-10)
    assert max(errors) < LOG_ERROR, f"largest difference in d ln A / d ln p {max(errors):.2e} ({names}: {errors})"
    assert np.abs(found.relative).max() > 0.1  # not a test of zeros: the length moves A by 0.8 p/|p|
    if "materials.PZT-5A.d31" in names:  # A ~ d31 when the coupling is weak: 1 + O(k^2), 0.986 measured
        assert np.abs(found.relative[:, names.index("materials.PZT-5A.d31")] - 1).max() < 0.05


def test_uniform_scaling_of_every_constant(cantilever):
    """Scaling every elastic, piezoelectric and dielectric constant (and the spring) by s scales K by s (its blocks
    are linear in c^E, e and eps^S) with M fixed: lambda -> s lambda, the mass-normalised shape unchanged, the voltage
    load -K x_V and theta -> s theta, the response beside resonance (A - 0.97^2 lambda B)^-1 F unchanged. So the
    resonant part theta phi / (2 zeta lambda) and the feedthrough D are unchanged at fixed zeta: d ln A / d ln s = 0.
    Under stiffness-proportional Rayleigh damping zeta = beta omega / 2 ~ s^(1/2) and A^2 = R^2 + D^2 with R ~ 1 /
    zeta: d ln A / d ln s = -(1/2) R^2 / A^2; mass-proportional, zeta = alpha / (2 omega): +(1/2) R^2 / A^2. Scaling M
    by s (every density, K fixed) gives the opposite signs. dK = K, dM = 0 (or 0, M) is d/ds at s = 1. Only
    round-off of Nelson's solve is left: 5.7e-10 measured in every case, bound 1e-8."""
    mode = cantilever[0]
    K, M = mode.model.K, mode.model.M
    zero = sp.csr_matrix(K.shape)
    for damping, slope in ((Damping(Q=100), 0.0), (Damping(beta=2e-8), -0.5), (Damping(alpha=2e3), 0.5)):
        rom = reduce(mode, outputs=OUTPUTS, damping=damping)
        A = np.array([rom.amplitude_per_volt(name) for name in ("tip", "mid")])
        D = np.array([rom.feedthrough[name][2] for name in ("tip", "mid")])
        expected = slope * (1 - (D / A) ** 2)
        stiffer = amplitude_derivatives(mode, K, zero, outputs=OUTPUTS, damping=damping) / A
        heavier = amplitude_derivatives(mode, zero, M, outputs=OUTPUTS, damping=damping) / A
        assert np.abs(stiffer - expected).max() < 1e-8, (damping.describe(), stiffer, expected)
        assert np.abs(heavier + expected).max() < 1e-8, (damping.describe(), heavier, -expected)


def test_refusals(cantilever):
    mode = cantilever[0]
    with pytest.raises(SceneError, match="mode: not one of the modes given"):
        amplitude_sensitivities(cantilever, ["springs.tip.z"], mode=replace(mode), outputs=OUTPUTS,
                                damping=Damping(Q=100))
    with pytest.raises(SceneError, match="damping: must be a Damping"):
        amplitude_sensitivities(cantilever, ["springs.tip.z"], mode=mode, outputs=OUTPUTS, damping="Q=100")
    with pytest.raises(SceneError, match="bogus: not a parameter"):
        amplitude_sensitivities(cantilever, ["bogus"], mode=mode, outputs=OUTPUTS, damping=Damping(Q=100))
    scene = cantilever.model.scene
    open_modes = solve_level(scene, replace(scene.analysis, circuit="open"))
    with pytest.raises(SolverError, match="needs a short-circuit mode"):
        amplitude_sensitivities(open_modes, ["springs.tip.z"], mode=open_modes[0], outputs=OUTPUTS,
                                damping=Damping(Q=100))


def test_repeated_eigenvalue_is_refused():
    """A cantilever of square section: its bending pairs (y and z) share an eigenvalue, to the mesh's asymmetry."""
    scene = _cantilever(parts=[{"name": "plate", "material": "steel", "origin": [0, 0, 0], "size": [30, 2, 2]}],
                        faces={"root": ["plate.xmin"]}, springs={}, electrodes={},
                        analysis={"near": 1e3, "count": 2})
    modes = solve_level(scene, scene.analysis)
    assert abs(modes[1].frequency / modes[0].frequency - 1) < 1e-6
    with pytest.raises(SolverError, match="its eigenvalue is repeated"):
        amplitude_sensitivities(modes, ["materials.steel.E"], mode=modes[0], outputs=["root"], damping=Damping(Q=100))


@pytest.mark.slow
def test_cube_plate_against_full_solves():
    """The Cu-Be plate's working mode (0,6) at its four feet (its default mesh, 11.9k unknowns) for its length, its
    ceramics' thickness and PZT-4's d31, against central differences of full solves at H = 3e-4 |p| and 1.5e-4 |p|
    and their Richardson extrapolation (4 D(H/2) - D(H)) / 3 (the measurement in docs/studies.md, "Amplitude
    sensitivities"; run with -m slow -s for the table). Here the truncation is larger than on the cantilever: the
    plain reference errs by 4.1e-5 at H = 3e-4 (length, foot_1: it moved by 3.1e-5 when H was halved) and the
    sensitivity itself by 1.4e-5 (it moved by 1.2e-5 from RELATIVE_STEP to 1e-5), both towards the same limit
    (0.9012733, to 2e-7). Against the extrapolation (its O(H^4) remainder < 1e-6) the bound is the sensitivity's
    own 1.4e-5 with a margin: EXTRAPOLATED_ERROR = 3e-5."""
    from modalfe.results.modes import select
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    scene = load_scene("cube_plate")
    wm = scene.working_modes[0]
    modes = solve_modes(scene, near=wm.near, fidelity="solid", error_estimate=False)
    mode = select(modes, wm.selector, wm.near)
    damping, outputs = mode_damping(mode, resolve_losses(scene))[0], scene.drive.outputs
    names = ["length", "ceramic_thickness", "materials.PZT-4.d31"]
    found = amplitude_sensitivities(modes, names, mode=mode, outputs=outputs, damping=damping)
    wider = replace(scene.analysis, count=len(modes) + 2)
    plain, extrapolated = np.zeros((len(outputs), len(names))), np.zeros((len(outputs), len(names)))
    print(f"\n{mode.label} at {mode.frequency:.1f} Hz, {found.damping}; d ln A / d ln p: sensitivity | full solves "
          f"at H = {REFERENCE_STEP:g} |p|, H / 2, extrapolated")
    for j, name in enumerate(names):
        value = found.modal.values[j]
        references = []
        for H in (REFERENCE_STEP * abs(value), 0.5 * REFERENCE_STEP * abs(value)):
            amplitudes = []
            for sign in (1, -1):
                moved = modes_of(perturbed_model(mode.model, name, value + sign * H), wider, fidelity="solid")
                rom = reduce(shape_partners(modes, moved)[mode.index][0], outputs=outputs, damping=damping)
                amplitudes.append(np.array([rom.amplitude_per_volt(o) for o in outputs]))
            references.append((amplitudes[0] - amplitudes[1]) / (2 * H) * value / found.amplitude)
        limit = (4 * references[1] - references[0]) / 3
        plain[:, j] = np.abs(found.relative[:, j] - references[0])
        extrapolated[:, j] = np.abs(found.relative[:, j] - limit)
        for i, output in enumerate(outputs):
            print(f"  {name:<20} {output:<7} A = {1e9 * found.amplitude[i]:.4g} nm/V  {found.relative[i, j]:+.7f} | "
                  f"{references[0][i]:+.7f} {references[1][i]:+.7f} {limit[i]:+.7f}")
    print(f"largest difference: {plain.max():.2e} (plain, H = {REFERENCE_STEP:g} |p|), {extrapolated.max():.2e} "
          f"(extrapolated)")
    assert extrapolated.max() < 3e-5, f"largest difference in d ln A / d ln p {extrapolated.max():.2e}"
