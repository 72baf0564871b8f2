"""Numerical stability table (issue 10): each stress case, its outcome and its numbers.

    python studies/stability.py [--quick]
"""

from __future__ import annotations

import argparse
import itertools
import logging
import math

import numpy as np

from modalfe.errors import ModalfeError

ROWS: list[tuple[str, str, str]] = []


def case(name: str):
    def wrap(fn):
        def run(quick: bool):
            try:
                ok, numbers = fn(quick)
                ROWS.append((name, "pass" if ok else "FAIL", numbers))
            except ModalfeError as exc:
                ROWS.append((name, "error said", str(exc)[:90]))
        return run
    return wrap


@case("potential scaling: condition estimate")
def conditioning(quick):
    from modalfe.linalg import condition_estimate, factorize
    from modalfe.scene import load_scene
    from modalfe.solvers import assembled_model

    model, _, _ = assembled_model(load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0}))
    a, b = model.shifted_matrix(20e3), model.shifted_matrix(20e3, scale=1.0)
    ca, cb = condition_estimate(a, factorize(a)[0]), condition_estimate(b, factorize(b)[0])
    return ca < 1e-6 * cb, f"scaled {ca:.2e}, unscaled {cb:.2e}"


@case("shift exactly on an eigenvalue")
def singular_shift(quick):
    from modalfe.scene import load_scene
    from modalfe.solvers import solve_modes

    scene = load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0})
    f = solve_modes(scene, near=22e3, count=4, error_estimate=False).labelled("bending-z 6").frequency
    g = solve_modes(scene, near=f, count=4, error_estimate=False).labelled("bending-z 6").frequency
    return abs(g / f - 1) < 1e-5, f"moved shift, mode back within {abs(g / f - 1):.1e}"


@case("free-free plate: six rigid-body modes")
def rigid(quick):
    from modalfe.solvers import solve_modes
    from modalfe.verification_cases import free_plate_scene

    modes = solve_modes(free_plate_scene(), band=(0.0, 3000.0), error_estimate=False)
    rigid = [m for m in modes if m.frequency < 1.0]
    first = min(m.frequency for m in modes if m.frequency >= 1)
    return len(rigid) == 6, f"{len(rigid)} below 1 Hz, first elastic {first:.0f} Hz"


@case("band with no modes")
def empty_band(quick):
    from modalfe.solvers import solve_modes
    from modalfe.verification_cases import free_plate_scene

    solve_modes(free_plate_scene(), band=(500.0, 600.0), error_estimate=False)
    return False, "no error raised"


@case("coarse mesh (2 el./wavelength): estimate warns")
def coarse(quick):
    from modalfe.scene import load_scene
    from modalfe.solvers import solve_modes

    mode = solve_modes(load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 2.0}), near=24e3, count=8,
                       error_estimate=True).labelled("bending-z 6")
    return mode.error_estimate > 0.05, f"{mode.frequency:.0f} Hz, estimate {mode.error_estimate:.3g}"


@case("0.1 mm parameter step within the error estimate")
def continuity(quick):
    from modalfe.scene import load_scene
    from modalfe.solvers import solve_modes

    a = solve_modes(load_scene("ciliary_beam"), near=22e3, count=4).labelled("bending-z 6")
    b = solve_modes(load_scene("ciliary_beam", x0=0.0681), near=22e3, count=4,
                    error_estimate=False).labelled("bending-z 6")
    jump = abs(b.frequency / a.frequency - 1)
    return jump < a.error_estimate, f"jump {jump:.2e} vs estimate {a.error_estimate:.2e}"


@case("forced response energy balance")
def energy(quick):
    from modalfe.forced import Damping, harmonic_response
    from modalfe.scene import load_scene
    from modalfe.solvers import solve_modes

    scene = load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0})
    modes = solve_modes(scene, near=22e3, count=4, error_estimate=False)
    mode = modes.labelled("bending-z 6")
    r = harmonic_response(scene, modes, [mode.frequency], outputs=[("tip", (0.1, 0.0025, 0.005))],
                          damping=Damping(zeta=0.025), reference_omega=mode.omega)
    mismatch = abs(0.5 * r.admittance.real[0] / r.dissipated[0] - 1)
    return mismatch < 1e-8, f"input vs dissipated power {mismatch:.1e}"


@case("contact: kn 1e4-1e9, W 1e-12-1e-4 m, Fn 1e-3-1e3 N")
def contact(quick):
    from modalfe.contact import simulate_contact
    from modalfe.contact.foot import FootParameters

    worst, bad = 0.0, []
    for kn, w, fn in itertools.product([1e4, 1e6, 1e9], [1e-12, 1e-8, 1e-6, 1e-4], [1e-3, 1.0, 1e3]):
        p = FootParameters().with_(kn=kn)
        c = simulate_contact([w], preload=fn, speed=0.01, parameters=p)
        err = abs(c.normal_mean[0] / ((fn + p.mass * p.g) / p.n) - 1)
        worst = max(worst, err)
        if err > 1e-2 or not math.isfinite(err):
            bad.append(f"kn {kn:.0e} W {w:.0e} Fn {fn:.0e}: {100 * err:.1f}%")
    return not bad, f"worst momentum-balance error {worst:.1e}" + (f"; off: {', '.join(bad)}" if bad else "")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    logging.basicConfig(level=logging.ERROR)
    for run in (conditioning, singular_shift, rigid, empty_band, coarse, continuity, energy, contact):
        run(args.quick)
    width = max(len(r[0]) for r in ROWS)
    for name, outcome, numbers in ROWS:
        print(f"{name:<{width}}  {outcome:<10}  {numbers}")
    print(f"{sum(r[1] != 'FAIL' for r in ROWS)} of {len(ROWS)} cases stable or said why")
    if np.any([r[1] == "FAIL" for r in ROWS]):
        raise SystemExit(1)


if __name__ == "__main__":
    main()
