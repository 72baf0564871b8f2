"""Numerical stability table (issue 10): each stress case, its outcome and its numbers.

    python studies/stability.py [--quick]
"""

from __future__ import annotations

import argparse
import itertools
import logging
import math
import sys
from pathlib import Path

import numpy as np

from modalfe.errors import ModalfeError
from modalfe.solve.api import OWN_MESH

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests.oracles

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
    from modalfe.models.build import build_model
    from modalfe.scene import load_scene
    from modalfe.solve.linalg import condition_estimate, factorize

    model, _ = build_model(load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0}))
    a, b = model.shifted_matrix(20e3), model.shifted_matrix(20e3, scale=1.0)
    ca, cb = condition_estimate(a, factorize(a)[0]), condition_estimate(b, factorize(b)[0])
    return ca < 1e-6 * cb, f"scaled {ca:.2e}, unscaled {cb:.2e}"


@case("shift exactly on an eigenvalue")
def singular_shift(quick):
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    scene = load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0})
    f = solve_modes(scene, near=22e3, count=4, error_estimate=False).labelled("bending-z 6").frequency
    g = solve_modes(scene, near=f, count=4, error_estimate=False).labelled("bending-z 6").frequency
    return abs(g / f - 1) < 1e-5, f"moved shift, mode back within {abs(g / f - 1):.1e}"


@case("free-free plate: six rigid-body modes")
def rigid(quick):
    from modalfe.solve.api import solve_modes
    from tests.oracles.cases import free_plate_scene

    modes = solve_modes(free_plate_scene(), band=(0.0, 3000.0), error_estimate=False)
    rigid = [m for m in modes if m.frequency < 1.0]
    first = min(m.frequency for m in modes if m.frequency >= 1)
    return len(rigid) == 6, f"{len(rigid)} below 1 Hz, first elastic {first:.0f} Hz"


@case("band with no modes")
def empty_band(quick):
    from modalfe.solve.api import solve_modes
    from tests.oracles.cases import free_plate_scene

    solve_modes(free_plate_scene(), band=(500.0, 600.0), error_estimate=False)
    return False, "no error raised"


@case("coarse mesh (2 el./wavelength): estimate warns")
def coarse(quick):
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    mode = solve_modes(load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 2.0}), near=24e3, count=8,
                       fidelity="solid", tol=OWN_MESH).labelled("bending-z 6")
    return mode.error_estimate > 0.05, f"{mode.frequency:.0f} Hz, estimate {mode.error_estimate:.3g}"


@case("0.1 mm parameter step within the error estimate")
def continuity(quick):
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    a = solve_modes(load_scene("ciliary_beam"), near=22e3, count=4, fidelity="solid",
                    tol=OWN_MESH).labelled("bending-z 6")
    b = solve_modes(load_scene("ciliary_beam", x0=0.0681), near=22e3, count=4,
                    error_estimate=False).labelled("bending-z 6")
    jump = abs(b.frequency / a.frequency - 1)
    return jump < a.error_estimate, f"jump {jump:.2e} vs estimate {a.error_estimate:.2e}"


@case("sheets 0.3 / 0.1 / 0.03 mm on a 100 mm beam (1:333-1:3333)")
def thin_sheets(quick):
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    f = [solve_modes(load_scene("ciliary_beam", sheet_thickness=t), near=22e3, count=4,
                     error_estimate=False).labelled("bending-z 6").frequency for t in (0.3e-3, 0.1e-3, 0.03e-3)]
    ratio = (f[1] - f[2]) / (f[0] - f[1])  # 0.35 where the sheets act in proportion to their thickness
    return abs(ratio - 0.35) < 0.05, f"{f[0]:.0f} / {f[1]:.0f} / {f[2]:.0f} Hz, step ratio {ratio:.3f} (linear: 0.35)"


@case("nu 0.3 / 0.49 / 0.499: the estimate bounds the error")
def incompressible(quick):
    from modalfe.solve.api import solve_modes
    from tests.oracles.cases import clamped_bar_scene

    def mode(nu, size, estimate=True):
        return solve_modes(clamped_bar_scene(nu, size), error_estimate=estimate, fidelity="solid",
                           tol=OWN_MESH).labelled("bending-z 1")

    ok, parts = True, []
    for nu in (0.3, 0.499) if quick else (0.3, 0.49, 0.499):
        coarse = mode(nu, 2e-3)
        if quick:
            parts.append(f"nu {nu}: estimate {coarse.error_estimate:.2%}")
            continue
        f1, f2 = mode(nu, 1e-3, False).frequency, mode(nu, 0.5e-3, False).frequency
        error = abs(coarse.frequency / (f2 + (f2 - f1) / 3) - 1)
        ok &= error <= coarse.error_estimate
        parts.append(f"nu {nu}: error {error:.2%} <= estimate {coarse.error_estimate:.2%}")
    return ok, "; ".join(parts)


@case("flat tetrahedra vs hexahedra (glass plate, 66 kHz)")
def tetrahedra(quick):
    from modalfe.results.modes import select
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    if quick:
        return True, "skipped (--quick)"
    hexa = select(solve_modes(load_scene("glass_plate"), near=66e3, count=8, fidelity="solid", tol=OWN_MESH), "(0,n)",
                  66e3)
    tets = select(solve_modes(load_scene("glass_plate", **{"mesh.element": "tet"}), near=66e3, count=8,
                              error_estimate=False), "(0,n)", 66e3)
    gap = abs(tets.frequency / hexa.frequency - 1)
    return gap <= hexa.error_estimate and tets.label == hexa.label, \
        f"tet {tets.frequency:.0f} Hz vs hex {hexa.frequency:.0f} Hz: {gap:.2%} <= estimate {hexa.error_estimate:.2%}"


@case("forced response energy balance")
def energy(quick):
    from modalfe.response.forced import Damping, harmonic_response
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    scene = load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0})
    modes = solve_modes(scene, near=22e3, count=4, error_estimate=False)
    mode = modes.labelled("bending-z 6")
    r = harmonic_response(modes.model, [mode.frequency], outputs=[("tip", (0.1, 0.0025, 0.005))],
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


@case("contact vs brute force (RK23, 1e-7 s) across kn, W, Fn")
def brute_force(quick):
    from modalfe.contact.foot import FootParameters, steady_state
    from tests.oracles.contact_brute_force import brute_force_steady_state

    cases = [(1e7, 1e-6, 3.0)] if quick else [(1e5, 3e-6, 0.1), (1e7, 1e-7, 0.1), (1e7, 1e-6, 3.0), (1e7, 3e-6, 30.0),
                                              (1e9, 1e-7, 0.1), (1e7, 1e-6, 30.0)]
    worst_beta = worst_rt = 0.0
    for kn, w, fn in cases:
        p = FootParameters().with_(kn=kn)
        orbit = steady_state(w, preload=fn, speed=0.01, parameters=p)
        ref = brute_force_steady_state(w, preload=fn, speed=0.01, parameters=p, start="quasi-static",
                                       max_periods=3000)
        worst_beta = max(worst_beta, abs(orbit.flight_ratio - ref.flight_ratio))
        worst_rt = max(worst_rt, abs(orbit.friction_mean / ref.friction_mean - 1))
    return worst_beta <= 0.2 and worst_rt <= 5e-3, \
        f"{len(cases)} cases: worst beta {worst_beta:.1e} pp, <Rt> {worst_rt:.1e} (targets 0.2 pp, 0.5 %)"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    logging.basicConfig(level=logging.ERROR)
    for run in (conditioning, singular_shift, rigid, empty_band, coarse, continuity, thin_sheets, incompressible,
                tetrahedra, energy, contact, brute_force):
        run(args.quick)
    width = max(len(r[0]) for r in ROWS)
    for name, outcome, numbers in ROWS:
        print(f"{name:<{width}}  {outcome:<10}  {numbers}")
    print(f"{sum(r[1] != 'FAIL' for r in ROWS)} of {len(ROWS)} cases stable or said why")
    if np.any([r[1] == "FAIL" for r in ROWS]):
        raise SystemExit(1)


if __name__ == "__main__":
    main()
