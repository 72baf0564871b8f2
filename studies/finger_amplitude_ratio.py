"""Seed 004's bed-spring finger: friction against amplitude at 66 and 225 kHz, and the amplitude
ratio A(225 kHz) / A(66 kHz) that gives equal friction (seed 004 Figs 6, 7: about 0.12; equal
velocity would give 0.29, equal acceleration 0.086).  Also shows that eq. (1) read literally
(dampers on absolute velocities) gives no friction reduction at all.

Run:  python studies/finger_amplitude_ratio.py [--quick] [--out studies/out/finger_amplitude_ratio.png]
The full run solves 33 + 41 amplitudes (most 66 kHz points are time averages: the finger bounces
irregularly there) and takes about a minute; --quick uses 13 + 11.
"""

from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

import numpy as np

from modalfe.contact.finger import FingerParameters, equal_friction, finger_steady_state, simulate_finger
from modalfe.contact.plots import finger_figure

LEVELS = (0.9, 0.85, 0.8, 0.75, 0.72)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "out" / "finger_amplitude_ratio.png")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.ERROR)  # the solver warns at every time-averaged point
    low_a = np.linspace(0, 3.2e-6, 13 if args.quick else 33)
    high_a = np.linspace(0, 0.4e-6, 11 if args.quick else 41)
    t0 = time.perf_counter()
    low = simulate_finger(low_a, 66e3, progress=True)
    high = simulate_finger(high_a, 225e3, progress=True)
    elapsed = time.perf_counter() - t0
    p = low.parameters
    print(f"seed 004 Table I, {p.reading} layers, critical damping per layer, f_p = {p.preload} N, "
          f"V_F = {p.speed} m/s, mu = {p.mu}")
    for c in (low, high):
        print(f"\n{c.frequency / 1e3:g} kHz  {'A [um pp]':>10} {'mu_US/mu':>9} {'contact %':>9} {'contacts/T':>10}")
        for a, r, cr, n, per in zip(c.amplitude_pp, c.friction_ratio, c.contact_ratio, c.contacts_per_period,
                                    c.periodic):
            print(f"{'':9}{a * 1e6:10.3f} {r:9.4f} {cr:9.2f} {n:10.3g}{'' if per else '  time average'}")
    levels = [x for x in LEVELS if all(c.friction_ratio.min() <= x < c.friction_ratio[0] for c in (low, high))]
    eq = equal_friction(low, high, levels)
    print(f"\nequal friction (seed 004 model: 0.12; equal velocity {eq.velocity_ratio:.3f}, "
          f"equal acceleration {eq.acceleration_ratio:.3f})")
    print(f"{'mu_US/mu':>9} {'A 66 kHz':>10} {'A 225 kHz':>10} {'ratio':>7}")
    for x, lo, hi, r in zip(eq.level, eq.amplitude_low, eq.amplitude_high, eq.ratio):
        print(f"{x:9.2f} {lo * 1e6:10.3f} {hi * 1e6:10.4f} {r:7.3f}")
    slope = np.sum(eq.amplitude_low * eq.amplitude_high) / np.sum(eq.amplitude_low ** 2)
    print(f"least-squares slope through the origin (the seed's Fig. 7 fit): {slope:.3f}")
    print(f"({elapsed:.0f} s for the two curves)")
    print("\neq. (1) read literally (dampers on absolute velocities):")
    literal = FingerParameters(reading="literal")
    for a in (1e-6, 3e-6):
        o = finger_steady_state(a, 66e3, parameters=literal)
        print(f"  66 kHz, {a * 1e6:g} um pp: in contact {o.contact_ratio:.1f} % of the time, mu_US/mu = "
              f"{o.friction_ratio:.6f}")
    fig = finger_figure([low, high], eq)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"\nfigure written to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
