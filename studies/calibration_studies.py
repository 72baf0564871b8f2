"""Calibration studies (docs/calibration.md): which uncertain parameters explain the measured modes of the Cu-Be
plate, the glass plate and the ciliary beam, fitted with ``modalfe.design.calibration.calibrate`` on the 3-D
solid at each scene's default mesh.

    python studies/calibration_studies.py [cube_plate|glass_plate|ciliary_beam ...]

prints one markdown table per study (estimate +- posterior sd, the model's value of each measured quantity, the
normalised residual, solves and seconds, the identifiability statements) and the default mesh's own estimated
discretization error of each measured mode (Richardson through three meshes), which every calibrated value
absorbs: a parameter fitted to a frequency the mesh gets 0.3 % wrong is off by 0.3 % / |d ln f / d ln p|.

Measured values (each with its source; sigma: none of the papers gives one, so half the last printed digit of
the reported value, a rounding uncertainty, except where said):
- Cu-Be plate, (0,6) 40.7 kHz: M'boungui, Lemaire-Semail & Giraud, "Vibration control and preliminary evaluation
  of a piezoelectric actuator for use as a force-feedback device" (measured resonance; their Abaqus model gave
  42.7 kHz with no bond layer); sigma 50 Hz.
- glass plate, 66 kHz with wavelength 15 mm and 225 kHz with 7.5 mm: Giraud, Hara, Giraud-Audine, Amberg,
  Lemaire-Semail & Takasaki, "Evaluation of a friction reduction based haptic surface at high frequency", IEEE
  Haptics Symposium 2018 (laser-interferometer cartography); sigma 500 Hz, 0.5 mm and 0.05 mm.
- ciliary beam, 6th bending mode ~23,200 Hz: Xing, Li & Howard, "Investigating vibration acceleration of a
  segmented piezoelectric ciliary-like body beam for a tactile feedback device", Appl. Sci. 10 (2020) 5362 (found
  by tuning between 20 and 24 kHz until the beam felt smooth: "~"); sigma 100 Hz, twice the rounding one, for
  the approximate reading.
Bounds are the plausible ranges named in each study; foot contact stiffness up to the 9.7e6 N/m contact
stiffness of the seed chapter's appendix (M'boungui et al., "Stateflow aided modelling and simulation of
friction", in MATLAB Applications for the Practical Engineer, InTech 2014).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from modalfe.design.calibration import CALIBRATE_COUNT, calibrate, posterior
from modalfe.design.measurements import Measurement
from modalfe.scene import load_scene
from modalfe.solve.api import OWN_MESH, solve_modes

CUBE = (Measurement("(0,6)", 40.7e3, 50.0),)
GLASS = (Measurement("(0,8)", 66e3, 500.0, 15e-3, 0.5e-3), Measurement("(0,16)", 225e3, 500.0, 7.5e-3, 0.05e-3))
CILIARY = (Measurement("bending-z 6", 23.2e3, 100.0),)
PZT_GRADES = ("PZT-4", "PZT-5A", "PZT-5H")  # every piezoceramic grade of the material library
FOOT_STIFFNESS = 1e6  # [N/m] per foot, z only: the start of the foot-contact fit (bounds 1e3 .. 9.7e6)
# the glass and brass of the built-in scenes as scene materials, so that their modulus can be varied
SODA_LIME = {"E": 70e9, "nu": 0.22, "rho": 2500.0}  # EN 572-1 (as the library's soda-lime-glass)
BRASS = {"E": 105e9, "nu": 0.34, "rho": 8500.0}  # Xing, Li & Howard 2020 (E, rho); nu of brass, ASM Handbook vol. 2


def discretization_errors(scene, measured) -> tuple[list[str], list[float]]:
    """The default mesh's estimated relative error of each measured mode (``solve_modes`` error estimate): lines
    saying so, and the errors."""
    out, errors = [], []
    for m in measured:
        modes = solve_modes(scene, near=m.frequency, count=CALIBRATE_COUNT, fidelity="solid", tol=OWN_MESH)
        mode = modes.labelled(m.label, near=m.frequency)
        out.append(f"{m.label}: {mode.frequency:.1f} Hz on {modes.dofs} DOFs, estimated discretization error "
                   f"{mode.error_estimate:.2%} ({modes.estimate_method})")
        errors.append(mode.error_estimate)
    return out, errors


def fit_row(title: str, scene, measured, names, bounds) -> tuple[list[str], object]:
    """One calibration as markdown table rows (one per parameter) plus its statements, and its result (None if
    it failed)."""
    start = time.perf_counter()
    try:
        result = calibrate(scene, measured, names, bounds=bounds, max_iterations=12)
    except Exception as exc:  # a study row reports a failed fit and goes on
        return [f"| {title} | failed: {exc} | | | |"], None
    seconds = time.perf_counter() - start
    model = ", ".join(f"{q} {y:.6g} ({r:+.2f})" for q, y, r in zip(result.quantities, result.predicted,
                                                                 result.residuals))
    rows = []
    for i, (name, value, sd) in enumerate(zip(result.parameters, result.values, result.sd)):
        head = (f"| {title} | {model} | {result.solves}, {seconds:.0f} s, {'converged' if result.converged else ''}"
                f" {result.reason} |") if i == 0 else "| | | |"
        spread = f"+- {sd:.2g} ({sd / abs(value):.1%})" if sd <= abs(value) else "(not identified: sd > value)"
        rows.append(f"{head} {name} | {value:.5g} {spread} |")
    rows += [f"| | | | {text} | |" for text in result.unidentified]
    if len(result.parameters) > 1:
        rows.append(f"| | | | correlation {result.correlation[0, 1]:+.3f}; covariance from the "
                    f"{result.covariance_basis} | |")
    return rows, result


HEADER = ["| fit | model (normalised residual) | solves, time | parameter / note | estimate +- sd |",
          "| --- | --- | --- | --- | --- |"]


def cube_plate() -> list[str]:
    base = load_scene("cube_plate")
    lines = ["## Cu-Be plate: (0,6) measured 40.7 kHz", *discretization_errors(base, CUBE)[0], "", *HEADER]
    ceramic = {"ceramic_thickness": (0.5e-3, 1.2e-3)}  # seed texts: 0.65 mm (appendix) and 1 mm (text)
    for grade in PZT_GRADES:
        scene = base.with_overrides(ceramic_material=grade)
        lines += fit_row(f"{grade}, ceramic thickness", scene, CUBE, ["ceramic_thickness"], ceramic)[0]
    bond = base.with_overrides(bond_thickness=20e-6)
    lines += fit_row("PZT-4, epoxy bond layer", bond, CUBE, ["bond_thickness"], {"bond_thickness": (2e-6, 200e-6)})[0]
    feet = base.with_overrides(**{f"springs.foot_{i}": (0.0, 0.0, FOOT_STIFFNESS) for i in range(1, 5)})
    contact = {"springs.foot_*.z": (1e3, 9.7e6)}
    lines += fit_row("PZT-4, foot contact (kz per foot)", feet, CUBE, ["springs.foot_*.z"], contact)[0]
    lines += fit_row("PZT-4, ceramic thickness and foot contact", feet, CUBE,
                     ["ceramic_thickness", "springs.foot_*.z"], {**ceramic, **contact})[0]
    return lines


def glass_plate() -> list[str]:
    base = load_scene("glass_plate").with_overrides(**{"materials.soda-lime": SODA_LIME, "glass_material": "soda-lime"})
    names = ["materials.soda-lime.E", "thickness", "length"]
    bounds = {"materials.soda-lime.E": (50e9, 90e9), "thickness": (1.5e-3, 2.3e-3), "length": (40e-3, 80e-3)}
    notes, errors = discretization_errors(base, GLASS)
    lines = ["## Glass plate: 66 kHz (15 mm) and 225 kHz (7.5 mm)", *notes, "", *HEADER]
    rows, result = fit_row("E, thickness, length from both frequencies and wavelengths", base, GLASS, names, bounds)
    lines += rows
    if result is not None:  # the same optimum, the mesh's own error added to each frequency's sigma
        mesh = np.array([m.frequency * e for m, e in zip(GLASS, errors)] + [0.0] * len(GLASS))
        sigma = np.hypot(result.sigma, mesh)
        found = posterior(result.jacobian, sigma, float(np.sum(((result.predicted - result.measured) / sigma) ** 2)))
        sd = np.sqrt(np.diag(found.covariance))
        title = f"same optimum, mesh error added to the frequency sigmas ({sigma[0]:.0f}, {sigma[1]:.0f} Hz)"
        lines += [f"| {title if i == 0 else ''} | | | {name} | {value:.5g} +- {abs(value) * s:.2g} ({s:.1%}) |"
                  for i, (name, value, s) in enumerate(zip(result.parameters, result.values, sd))]
        lines.append(f"| | | | correlation E-thickness {found.covariance[0, 1] / (sd[0] * sd[1]):+.3f} | |")
    lines += fit_row("E, thickness from the two frequencies only", base,
                     [Measurement(m.label, m.frequency, m.sigma) for m in GLASS], names[:2],
                     {k: bounds[k] for k in names[:2]})[0]
    return lines


def ciliary_beam() -> list[str]:
    base = load_scene("ciliary_beam").with_overrides(**{"materials.brass": BRASS, "beam_material": "brass"})
    bounds = {"materials.brass.E": (80e9, 130e9), "height": (4.5e-3, 5.5e-3), "length": (90e-3, 105e-3)}
    lines = ["## Ciliary beam: 6th bending mode measured ~23.2 kHz", *discretization_errors(base, CILIARY)[0], "",
             *HEADER]
    for name in bounds:
        lines += fit_row(name, base, CILIARY, [name], {name: bounds[name]})[0]
    lines += fit_row("E and height", base, CILIARY, ["materials.brass.E", "height"],
                     {k: bounds[k] for k in ("materials.brass.E", "height")})[0]
    return lines


STUDIES = {"cube_plate": cube_plate, "glass_plate": glass_plate, "ciliary_beam": ciliary_beam}


def main(argv: list[str]) -> int:
    chosen = argv or list(STUDIES)
    unknown = [name for name in chosen if name not in STUDIES]
    if unknown:
        print(f"calibration_studies: unknown study {unknown[0]}; known: {list(STUDIES)}", file=sys.stderr)
        return 2
    for name in chosen:
        start = time.perf_counter()
        print("\n".join(STUDIES[name]()) + f"\n\n({name}: {time.perf_counter() - start:.0f} s)\n", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
