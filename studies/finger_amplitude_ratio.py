"""Seed 004's bed-spring finger: friction against amplitude at 66 and 225 kHz, every point with its
method (a stable periodic orbit of period kT, or a time average with its standard error), and the
amplitude ratio A(225 kHz) / A(66 kHz) that gives equal friction at the levels 0.95 to 0.5 (seed 004
Figs 6, 7: about 0.12; equal velocity would give 0.29, equal acceleration 0.086).  Also eq. (1) read
literally (no friction reduction), and with ``--verify`` a comparison of chosen points against the
independent brute-force integration of tests/oracles/contact_brute_force.py (solve_ivp, DOP853,
rtol 1e-10, events), started from rest.

Run:  python studies/finger_amplitude_ratio.py [--quick] [--verify] [--out studies/out/finger_amplitude_ratio.png]
The full run solves 61 + 61 amplitudes (66 kHz: 0-8 um pp, 225 kHz: 0-0.9 um pp) in about 50 s;
--verify adds about 3 minutes of brute force.
"""

from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

import numpy as np

from modalfe.contact.finger import FingerParameters, equal_friction, finger_steady_state, simulate_finger
from modalfe.plot.contact import finger_figure

LEVELS = (0.95, 0.9, 0.85, 0.8, 0.75, 0.7, 0.65, 0.6, 0.55, 0.5)
# (amplitude pp [m], frequency [Hz], periods, skipped periods) for --verify: each kind of point
VERIFY = ((0.1333e-6, 66e3, 200, 100), (0.15e-6, 66e3, 600, 300), (0.6e-6, 66e3, 300, 150),
          (0.6667e-6, 66e3, 2500, 2000), (0.75e-6, 66e3, 1500, 1000), (1.6e-6, 66e3, 2200, 200),
          (3.2e-6, 66e3, 2200, 200), (0.2e-6, 225e3, 400, 200))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--verify", action="store_true", help="compare points against the brute-force oracle")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "out" / "finger_amplitude_ratio.png")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.ERROR)
    n = 21 if args.quick else 61
    low_a, high_a = np.linspace(0, 8e-6, n), np.linspace(0, 0.9e-6, n)
    t0 = time.perf_counter()
    low = simulate_finger(low_a, 66e3, progress=True)
    high = simulate_finger(high_a, 225e3, progress=True)
    elapsed = time.perf_counter() - t0
    p = low.parameters
    print(f"seed 004 Table I, {p.reading} layers, critical damping per layer, f_p = {p.preload} N, "
          f"V_F = {p.speed} m/s, mu = {p.mu}")
    for c in (low, high):
        print(f"\n{c.frequency / 1e3:g} kHz  {'A [um pp]':>10} {'mu_US/mu':>9} {'contact %':>9} "
              f"{'landings/T':>10}  method")
        for a, r, cr, k, m in zip(c.amplitude_pp, c.friction_ratio, c.contact_ratio, c.contacts_per_period,
                                  c.method):
            print(f"{'':9}{a * 1e6:10.3f} {r:9.4f} {cr:9.2f} {k:10.3g}  {m}")
    levels = [x for x in LEVELS if all(c.friction_ratio.min() <= x < c.friction_ratio[0] for c in (low, high))]
    eq = equal_friction(low, high, levels)
    print(f"\nequal friction (seed 004 model: 0.12; equal velocity {eq.velocity_ratio:.3f}, "
          f"equal acceleration {eq.acceleration_ratio:.3f}); first crossing of each level")
    print(f"{'mu_US/mu':>9} {'A 66 kHz':>10} {'A 225 kHz':>10} {'ratio':>7} {'+-':>7}")
    for x, lo, hi, r, u in zip(eq.level, eq.amplitude_low, eq.amplitude_high, eq.ratio, eq.ratio_uncertainty):
        print(f"{x:9.2f} {lo * 1e6:10.3f} {hi * 1e6:10.4f} {r:7.4f} {u:7.4f}")
    slope = np.sum(eq.amplitude_low * eq.amplitude_high) / np.sum(eq.amplitude_low ** 2)
    print(f"least-squares slope through the origin (the seed's Fig. 7 fit): {slope:.3f}")
    print(f"({elapsed:.1f} s for the two curves)")
    print("\neq. (1) read literally (dampers on absolute velocities):")
    literal = FingerParameters(reading="literal")
    for a in (0.6e-6, 1e-6, 3e-6):
        o = finger_steady_state(a, 66e3, parameters=literal)
        print(f"  66 kHz, {a * 1e6:g} um pp: in contact {o.contact_ratio:.1f} % of the time, mu_US/mu = "
              f"{o.friction_ratio:.6f} ({o.method})")
    if args.verify:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests.oracles
        from tests.oracles.contact_brute_force import brute_force_finger

        print("\nagainst the brute-force oracle (solve_ivp DOP853, rtol 1e-10, events; from rest, "
              "averaged after the skipped periods):")
        print(f"{'A [um pp]':>10} {'f [kHz]':>7} {'modalfe':>9} {'method':>20} {'brute':>9} {'+-':>8} {'diff':>9}")
        for a, f, periods, skip in VERIFY:
            o = finger_steady_state(a, f)
            b = brute_force_finger(a, f, periods=periods, skip=skip)
            print(f"{a * 1e6:10.4f} {f / 1e3:7g} {o.friction_ratio:9.6f} {o.method:>20} {b.friction_ratio:9.6f} "
                  f"{b.uncertainty:8.1e} {o.friction_ratio - b.friction_ratio:9.2e}")
    fig = finger_figure([low, high], eq)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"\nfigure written to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
