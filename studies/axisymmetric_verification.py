"""The axisymmetric model (``fidelity="axisymmetric"``, ``modalfe.models.axisymmetric``) against theory and the 3-D
solid: the verification table, and a convergence study of the 20 x 1 mm PZT-5A disc's thickness mode.

Rows (each: the model's frequency with its stated error, DOFs, seconds, the reference and the deviation):
- the 20 x 1 mm PZT-5A disc (examples/pzt5a_disc.toml): R1 short circuit (fr) against the 3-D solid's
  99,365 Hz (0.001 % stated; docs/studies.md) and IEEE Std 176-1987 thin-disc theory; open circuit (fa) against the
  solid's 117,317 Hz and the theory; k_p through the IEEE 176 planar relation;
- a free 20 x 0.1 mm Al-5052 disc's R1 against the plane-stress frequency equation eta J0 = (1 - nu) J1;
- a free steel ring (R 20 mm, wall 1 mm, height 2 mm): in-plane n = 2, 3 against Hoppe (1871);
- a radially poled PZT-4 ring (R 10 mm, wall 0.5 mm, height 1 mm): breathing fr, fa against the thin-ring formula;
- thickness: the disc held laterally (u_r = u_theta = 0, the 1-D resonator: fa = sqrt(c33^D / rho) / 2t, fr from
  k_t) and the free disc's thickness mode (the n = 0 mode near 2 MHz with the largest modal force per volt), whose
  frequency constant N_t = fr t is compared with the 1-D theory's: the difference is the lateral modes' (the free disc's
  thickness resonance mixes with its high radial overtones), not a discretization error.

Convergence of the free disc's thickness mode: quartic elements (mesh.order 4, the estimate against order 3) on
element sizes x1, x1/1.5, x1/2.25, x1/3.375 of ``mesh.max_frequency`` 2.3 MHz at 2 elements per wavelength; the stated
error of each level against its distance from the finest.

Stated against actual error on bonded parts (``--stack``): the disc stack of tests/oracles/cases.py (Al, epoxy film,
PZT-5A; harmonics 0..2, its six modes near 192 kHz) on grids x1 to x1/5.1 at order 3, against order 4 on x1/17
(1.2 million unknowns, about two minutes), whose distance from order 4 on x1/7.6 is added to the actual errors as the
reference's own uncertainty.

    python studies/axisymmetric_verification.py [--quick] [--stack]   (--quick: the thickness mode on two levels)

Seconds are of solves, not of answers read back: the study turns modalfe's disk cache off (``MODALFE_CACHE=off``)
unless it is set; within the run a second circuit reuses the first's model, as a command does.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
import scipy.optimize as so
import scipy.special as ss

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests.oracles
from modalfe.results.coupling import k_eff
from modalfe.scene import load_scene
from modalfe.scene.loading import scene_from_dict
from modalfe.solve.api import OWN_MESH, solve_modes
from tests.oracles.discs import (
    PZT5A_DISC,
    SOLID_FA,
    SOLID_FR,
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
TOL = 1e-5  # the tolerance every row is solved to (the 3-D solid's stated error on the disc's R1)
THICKNESS = 1e-3  # m, the disc's
THICKNESS_MESH = {"mesh.order": 4, "mesh.max_frequency": 2.3e6, "mesh.elements_per_wavelength": 2.0,
                  "mesh.harmonics": 0}


def _row(case: str, mode, dofs: int, seconds: float, reference: float, source: str) -> tuple:
    return (case, mode.label, mode.frequency, mode.error_estimate, dofs, seconds, reference, source,
            mode.frequency / reference - 1)


def _timed(scene, label: str, **question):
    start = time.perf_counter()
    modes = solve_modes(scene, fidelity="axisymmetric", mode=label, tol=TOL, **question)
    return modes.labelled(label), modes, time.perf_counter() - start


def disc_rows() -> list[tuple]:
    fr_theory, fa_theory = thin_disc("PZT-5A", 0.01)
    fr, short, t_fr = _timed(DISC, "R1")
    fa, opened, t_fa = _timed(DISC, "R1", circuit="open")
    s, d, eps_T, _ = compliances("PZT-5A")
    sigma = -s[0, 1] / s[0, 0]
    eta = so.brentq(lambda x: (1 - sigma) * ss.j1(x) - x * ss.j0(x), 1.5, 2.5)

    def kp(fr_: float, fa_: float) -> float:
        x = eta * fa_ / fr_
        ratio = ((1 - sigma) * ss.j1(x) - x * ss.j0(x)) / ((1 + sigma) * ss.j1(x))
        return float(np.sqrt(ratio / (1 + ratio)))

    print(f"disc k_p (IEEE 176 planar relation): axisymmetric {kp(fr.frequency, fa.frequency):.4f}, 3-D solid "
          f"{kp(SOLID_FR, SOLID_FA):.4f}, theory {np.sqrt(2 * d[2, 0]**2 / (eps_T[2, 2] * (s[0, 0] + s[0, 1]))):.4f}")
    return [_row("PZT-5A disc 20x1 fr", fr, short.dofs, t_fr, SOLID_FR, "3-D solid (0.001 %)"),
            _row("PZT-5A disc 20x1 fr", fr, short.dofs, t_fr, fr_theory, "IEEE 176 thin disc"),
            _row("PZT-5A disc 20x1 fa", fa, opened.dofs, t_fa, SOLID_FA, "3-D solid"),
            _row("PZT-5A disc 20x1 fa", fa, opened.dofs, t_fa, fa_theory, "IEEE 176 thin disc")]


def elastic_rows() -> list[tuple]:
    E, nu, rho, a = 70.3e9, 0.33, 2680.0, 0.01
    eta = so.brentq(lambda x: x * ss.j0(x) - (1 - nu) * ss.j1(x), 1, 3)
    f_disc = eta / (2 * np.pi * a) * np.sqrt(E / (rho * (1 - nu**2)))
    al = scene_from_dict({"units": "mm", "analysis": {"near": f_disc, "count": 8}, "parts": [
        {"name": "disc", "shape": "cylinder", "material": "Al-5052", "centre": [0, 0, 0], "axis": "z",
         "radius": 10, "height": 0.1}]})
    mode, modes, t = _timed(al, "R1", harmonics=0)
    rows = [_row("Al-5052 disc 20x0.1 R1", mode, modes.dofs, t, f_disc, "plane-stress J1 equation")]
    r = STEEL_RING
    ring = steel_ring_scene()
    for n in (2, 3):
        f_ring = ring_inplane_frequency(n, radius=r["radius"], E=r["E"], rho=r["rho"], area=r["height"] * r["wall"],
                                        inertia=r["height"] * r["wall"] ** 3 / 12)
        mode, modes, t = _timed(ring, f"n={n}", harmonics=3, near=f_ring)
        rows.append(_row("steel ring R20 1x2", mode, modes.dofs, t, f_ring, "Hoppe 1871 thin ring"))
    return rows


def radial_ring_rows() -> list[tuple]:
    s, d, eps_T, _ = compliances("PZT-4")
    fr = thin_ring_breathing("PZT-4", 0.01)
    fa = fr / np.sqrt(1 - d[2, 0] ** 2 / (s[0, 0] * eps_T[2, 2]))
    ring = radial_ring_scene(fr)
    rows = []
    for circuit, reference in (("short", fr), ("open", fa)):
        mode, modes, t = _timed(ring, "R1", circuit=circuit)
        rows.append(_row(f"PZT-4 radial ring R10 ({circuit})", mode, modes.dofs, t, reference, "thin-ring formula"))
    return rows


def strongest(modes):
    """The mode of ``modes`` the electrodes couple to most: short circuit, the largest modal force per volt squared
    over the stiffness, (x . f_V)^2 / omega^2 (its share of the dynamic capacitance); open circuit, the largest
    floating potential per unit modal amplitude. In the free disc's dense spectrum near 2 MHz these are the thickness
    resonance and antiresonance an admittance curve shows (its largest peak and dip)."""
    if modes.circuit == "short":
        f = modes.model.voltage_load(1.0)
        return max(modes, key=lambda m: float(m.shape @ f) ** 2 / max(m.omega, 1.0) ** 2)
    on_drive = modes.model.prescribed_potential(1.0)
    return max(modes, key=lambda m: abs(float(m.shape @ on_drive)))


def thickness_rows(size_factors: tuple[float, ...]) -> list[tuple]:
    from modalfe.models.build import build_model

    fr_1d, fa_1d = thickness_resonator("PZT-5A", THICKNESS)
    scene = load_scene(DISC, **THICKNESS_MESH)
    model, _ = build_model(scene, "axisymmetric")
    start = time.perf_counter()
    held = {c: laterally_held(model, c, f) for c, f in (("short", fr_1d), ("open", fa_1d))}
    t_held = time.perf_counter() - start
    print(f"laterally held disc (1-D resonator), quartic elements, {model.ndofs} unknowns, {t_held:.2f} s: "
          f"fr {held['short']:.1f} Hz (1-D {fr_1d:.1f}, {held['short'] / fr_1d - 1:+.2e}), fa {held['open']:.1f} Hz "
          f"(1-D {fa_1d:.1f}, {held['open'] / fa_1d - 1:+.2e})")
    levels = []
    for factor in size_factors:
        start = time.perf_counter()
        short = solve_modes(scene, fidelity="axisymmetric", near=fr_1d, count=24, tol=OWN_MESH, size_factor=factor)
        mode = strongest(short)
        partner = strongest(solve_modes(scene, fidelity="axisymmetric", near=mode.frequency * fa_1d / fr_1d,
                                        count=24, tol=OWN_MESH, size_factor=factor, circuit="open"))
        levels.append((factor, mode, partner, short.dofs, time.perf_counter() - start))
    finest_r, finest_a = levels[-1][1].frequency, levels[-1][2].frequency
    print("\nfree disc thickness mode (the n = 0 modes near 2 MHz the electrodes couple to most, ``strongest``), "
          "quartic elements,\nstated error (order 4 against 3) against the distance from the finest level:")
    print(f"{'size':>7} {'DOFs':>7} {'fr [Hz]':>12} {'stated':>9} {'to finest':>9} {'fa [Hz]':>12} {'stated':>9} "
          f"{'to finest':>9} {'k_eff':>6} {'s':>6}")
    for factor, mode, partner, dofs, seconds in levels:
        print(f"x{factor:<6.3f} {dofs:7d} {mode.frequency:12.1f} {mode.error_estimate:9.2e} "
              f"{abs(mode.frequency / finest_r - 1):9.2e} {partner.frequency:12.1f} {partner.error_estimate:9.2e} "
              f"{abs(partner.frequency / finest_a - 1):9.2e} {k_eff(mode.frequency, partner.frequency):6.3f} "
              f"{seconds:6.2f}")
    _, mode, partner, dofs, seconds = levels[-2] if len(levels) > 1 else levels[-1]
    print(f"frequency constants: fr t {mode.frequency * THICKNESS:.0f} Hz m (1-D theory {fr_1d * THICKNESS:.0f}), "
          f"fa t {partner.frequency * THICKNESS:.0f} Hz m (1-D {fa_1d * THICKNESS:.0f}); k_eff "
          f"{k_eff(mode.frequency, partner.frequency):.3f} (1-D k_t {np.sqrt(1 - (fr_1d / fa_1d) ** 2):.3f} as k_eff)")
    return [_row("PZT-5A disc 20x1 thickness fr", mode, dofs, seconds, fr_1d, "1-D theory (lateral modes differ)"),
            _row("PZT-5A disc 20x1 thickness fa", partner, dofs, seconds, fa_1d, "1-D theory (lateral modes differ)")]


def stack_coverage() -> None:
    from dataclasses import replace

    from tests.oracles.cases import stack_scene

    scene = stack_scene()
    quartic = replace(scene, mesh=replace(scene.mesh, order=4))
    question = {"fidelity": "axisymmetric", "harmonics": 2, "near": 191.8e3, "count": 6}
    reference = {m.label: m.frequency for m in solve_modes(quartic, error_estimate=False, size_factor=1 / 1.5**7,
                                                           **question)}
    uncertainty = {m.label: abs(m.frequency / reference[m.label] - 1) for m in solve_modes(
        quartic, error_estimate=False, size_factor=1 / 1.5**5, **question) if m.label in reference}
    print("\ndisc stack, order 3: stated / actual (reference's uncertainty added) per mode and grid")
    worst = 0.0
    for k in range(5):
        modes = solve_modes(scene, tol=OWN_MESH, size_factor=1 / 1.5**k, **question)
        cells = []
        for m in modes:
            if m.label in reference:
                actual = abs(m.frequency / reference[m.label] - 1) + uncertainty[m.label]
                worst = max(worst, actual / m.error_estimate)
                cells.append(f"{m.label} {m.error_estimate:.1e}/{actual:.1e}")
        print(f"x1/{1.5**k:<5.3g} {modes.dofs:6d}  " + " | ".join(cells))
    print(f"largest actual / stated: {worst:.2f} ({modes.estimate_method})")


def main() -> None:
    os.environ.setdefault("MODALFE_CACHE", "off")
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the thickness mode on two levels only")
    parser.add_argument("--stack", action="store_true", help="stated against actual error on the disc stack")
    args = parser.parse_args()
    factors = (1.0, 1 / 1.5) if args.quick else (1.0, 1 / 1.5, 1 / 2.25, 1 / 3.375)
    rows = disc_rows() + elastic_rows() + radial_ring_rows()
    print(f"\n{'case':<32} {'mode':<8} {'f [Hz]':>12} {'stated':>9} {'DOFs':>6} {'s':>6} {'reference':>12} "
          f"{'source':<34} {'dev':>9}")
    for case, label, f, err, dofs, seconds, ref, source, dev in rows:
        print(f"{case:<32} {label:<8} {f:12.2f} {err:9.1e} {dofs:6d} {seconds:6.2f} {ref:12.2f} {source:<34} "
              f"{dev:+9.4%}")
    for case, label, f, err, dofs, seconds, ref, source, dev in thickness_rows(factors):
        print(f"{case:<32} {label:<8} {f:12.2f} {err:9.1e} {dofs:6d} {seconds:6.2f} {ref:12.2f} {source:<34} "
              f"{dev:+9.4%}")
    if args.stack:
        stack_coverage()


if __name__ == "__main__":
    main()
