"""Identify the foot's tangential contact stiffness kt from seed 001's measured friction reduction.

kt is the one parameter of the Coulomb-Orowan friction model (seed 000 eqs 14-17) that the seeds do
not give.  Seed 001 (section 7) measured the friction falling from 0.71 N to 0.274 N (61.41 %) at
3 N preload, 1 cm/s, on steel.  The amplitude of that measurement is not stated; we take 0.65 um
(0-peak), the highest amplitude seed 001 used with its participants (section 11, "0.65 um on
1.7 um available") and the end of the amplitude axis of seed 000's Fig. 15 b), and show how the
identified kt moves if that assumption is changed.  The model's friction without vibration is
mu0 (Fn + m g) = 0.742 N against the 0.71 N measured, so the fit matches the *ratio* 0.274 / 0.71.

Run:  python studies/identify_kt.py [--amplitude 0.65e-6] [--out studies/out/identify_kt.png]
Prints the fit table and writes the figure (normalised friction against amplitude at 1, 2 and
5 cm/s with the measured point; identified kt against the assumed amplitude).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from modalfe.contact.foot import FootParameters, simulate_contact, steady_state

# Seed 001 section 7: measured reduction at 3 N preload, 1 cm/s, steel.
PRELOAD = 3.0  # N
SPEED = 0.01  # m/s
FRICTION_OFF = 0.71  # N, without vibration
FRICTION_ON = 0.274  # N, with vibration
TARGET_RATIO = FRICTION_ON / FRICTION_OFF  # 0.3859, i.e. a 61.41 % reduction


def friction_ratio(kt: float, amplitude: float) -> float:
    """Model friction with vibration over friction without, at the measurement's conditions."""
    p = FootParameters(kt=kt).on("steel")
    on = steady_state(amplitude, preload=PRELOAD, speed=SPEED, parameters=p).friction_force
    return on / (p.mu0 * p.total_load(PRELOAD))


def identify(amplitude: float) -> float:
    """kt [N/m] for which the model reproduces the measured ratio at ``amplitude`` [m, 0-peak]."""
    return math.exp(brentq(lambda s: friction_ratio(math.exp(s), amplitude) - TARGET_RATIO,
                           math.log(1e4), math.log(1e9), xtol=1e-10))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--amplitude", type=float, default=0.65e-6, help="amplitude of the measurement [m, 0-peak]")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "out" / "identify_kt.png")
    args = parser.parse_args(argv)

    kt = identify(args.amplitude)
    print(f"Seed 001: {FRICTION_OFF} N -> {FRICTION_ON} N at {PRELOAD} N, {SPEED * 100:g} cm/s, steel "
          f"(ratio {TARGET_RATIO:.4f}, reduction {100 * (1 - TARGET_RATIO):.2f} %)")
    print(f"assumed amplitude {args.amplitude * 1e6:.2f} um (0-peak)  ->  identified kt = {kt:.4g} N/m")
    print()
    print(f"{'kt [N/m]':>10} {'F(0) [N]':>9} {'F(W) [N]':>9} {'ratio':>7} {'reduction':>10}")
    p0 = FootParameters().on("steel")
    f_off = p0.mu0 * p0.total_load(PRELOAD)
    for k in sorted({2e6, 3e6, 4e6, kt, 6e6, 8e6, 1e7}):
        r = friction_ratio(k, args.amplitude)
        mark = "  <- fit" if k == kt else ""
        print(f"{k:10.4g} {f_off:9.4f} {r * f_off:9.4f} {r:7.4f} {100 * (1 - r):9.2f}%{mark}")
    print()
    print("sensitivity to the assumed amplitude:")
    print(f"{'W [um]':>7} {'kt [N/m]':>10}")
    sens = [(w, identify(w)) for w in (0.5e-6, 0.6e-6, 0.65e-6, 0.7e-6, 0.8e-6)]
    for w, k in sens:
        print(f"{w * 1e6:7.2f} {k:10.4g}")
    print()
    print("prediction with the identified kt, at the assumed amplitude (seed 001 Figs 9, 10 trends):")
    print(f"{'Fn [N]':>6} {'V [cm/s]':>8} {'F(0) [N]':>9} {'F(W) [N]':>9} {'reduction':>10}")
    p = FootParameters(kt=kt).on("steel")
    for fn, v in ((3.0, 0.01), (3.0, 0.02), (3.0, 0.05), (8.0, 0.02), (10.0, 0.02)):
        c = simulate_contact([0.0, args.amplitude], preload=fn, speed=v, parameters=p)
        print(f"{fn:6.1f} {v * 100:8.1f} {c.friction_force[0]:9.4f} {c.friction_force[1]:9.4f} "
              f"{100 * c.friction_reduction[1]:9.2f}%")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    W = np.linspace(0, 1e-6, 51)
    for v in (0.01, 0.02, 0.05):
        c = simulate_contact(W, preload=PRELOAD, speed=v, parameters=p)
        ax1.plot(W * 1e6, c.friction_force / c.static_friction, label=f"model, {v * 100:g} cm/s")
    ax1.plot([0, args.amplitude * 1e6], [1.0, TARGET_RATIO], "ko", label="seed 001, 1 cm/s (ratio)")
    ax1.set(xlabel="amplitude W [um, 0-peak]", ylabel="friction / friction without vibration",
            title=f"3 N preload, steel, kt = {kt:.3g} N/m")
    ax1.legend()
    ax2.plot([w * 1e6 for w, _ in sens], [k for _, k in sens], "o-")
    ax2.set(xlabel="assumed amplitude of the measurement [um]", ylabel="identified kt [N/m]",
            title="sensitivity of kt")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"\nfigure written to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
