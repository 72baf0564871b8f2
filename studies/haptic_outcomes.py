"""The chain from the working mode to the felt friction (modalfe.contact.chain) on the seeds' two devices, against
the seeds' figures, with the uncertainty carried from the mode's stated error, and how the outcome moves with the
contact parameters the seeds do not give (issue 38, item 4). Writes the haptic maps (CSV, VTU, PNG).

Seed figures used (copied here with their sources):
- seed 001 (Cu-Be plate, section 7): friction 0.71 N -> 0.274 N, a 61.41 % reduction, at 3 N preload and 1 cm/s on
  steel; section 11: 0.65 um (0-peak) gave a "strong" sensation, 1.7 um available; section 6: ~1 ms response time.
- seed 004 (1.9 mm glass plate, sections II-III): working modes at 66 and 225 kHz; measured amplitudes 2.8 um pp at
  66 kHz and 194 nm pp at 225 kHz; amplitude response times 1.3 ms and 0.5 ms; the model's amplitude ratio
  A(225 kHz) / A(66 kHz) for equal friction about 0.12 (Fig. 7; 0.08 perceived).
- not given by the seeds: the feet's tangential contact stiffness kt (identified from the 61.41 % at an assumed
  0.65 um by studies/identify_kt.py, n = 3 feet), the plate's Q (the default damping: the materials' Qm where they
  give one, Q = 150 for the rest, docs/damping.md); seed 004's finger parameters (Table I) are for a 0.5 N normal
  force and one finger, and its K_Tsc is printed as 98120 N/mm.

Run:  python studies/haptic_outcomes.py [--quick] [--out studies/out/haptics]
(--quick: the Cu-Be plate only.) Solves (or reads from the cache) the two devices' working modes.
"""

from __future__ import annotations

import argparse
import logging
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from modalfe.contact.chain import FingerContact, FootContact, chain_from_rom, haptic_chain, haptic_map, surface_points
from modalfe.contact.finger import FingerParameters
from modalfe.contact.foot import FootParameters
from modalfe.response.loads import output_points
from modalfe.scene import load_scene

# seed 001, section 7: the measured reduction at 3 N, 1 cm/s, steel
PRELOAD, SPEED = 3.0, 0.01
MEASURED_REDUCTION = 1 - 0.274 / 0.71  # 61.41 %
STRONG_FEELING = 0.65e-6  # m 0-peak, seed 001 section 11
RESPONSE_TIME_001 = 1e-3  # s, seed 001 section 6
# seed 004: measured amplitudes (pp) and response times at the two working modes; the model's equal-friction ratio
GLASS = {66e3: (2.8e-6, 1.3e-3), 225e3: (194e-9, 0.5e-3)}
RATIO_004 = 0.12
EQUAL_LEVELS = (0.05, 0.1, 0.15, 0.2)  # friction reductions for the equal-friction ratio (mu_US / mu 0.95 .. 0.8)
MAP_POINTS = 400


def pm(x: float) -> str:
    return "unknown" if not np.isfinite(x) else f"{100 * x:.1f} %"


def outcome_line(name: str, o, seed: str = "") -> str:
    lo, hi = o.reduction_range
    return (f"| {name} | {o.voltage:.2f} V (+-{pm(o.amplitude_error)}) | {1e6 * o.amplitude:.3f} | "
            f"{100 * o.reduction:.1f} ({100 * lo:.1f}-{100 * hi:.1f}) | {o.flight_ratio:.1f} | "
            f"{1e3 * o.current:.1f} (+-{pm(o.current_error)}) | {1e3 * o.power:.1f} (+-{pm(o.power_error)}) | "
            f"{1e3 * o.rise_time:.3f} | {seed} |")


HEADER = ("| case | voltage | W [um 0-pk] | reduction [%] (range) | flight [%] | I [mA] | P [mW] | rise [ms] | seed |\n"
          "|---|---|---|---|---|---|---|---|---|")


def with_q(rom, q: float):
    """The reduced model with quality factor ``q`` (c = m omega_r / Q): the amplitude per volt at resonance scales
    with it."""
    zeta = 1 / (2 * q)
    return replace(rom, zeta=zeta, damping=2 * zeta * rom.omega * rom.modal_mass, damping_description=f"Q = {q:g}")


def cube_plate(out: Path) -> None:
    start = time.perf_counter()
    scene = load_scene("cube_plate")
    chain = haptic_chain(scene, FootContact(FootParameters(), PRELOAD, SPEED))
    print(f"## Cu-Be plate, {chain.rom.label} at {chain.frequency:.1f} Hz (chain built in "
          f"{time.perf_counter() - start:.1f} s): {chain.contact.describe()}\n")
    print(HEADER)
    needed = chain.voltage_for(MEASURED_REDUCTION)
    print(outcome_line("voltage for 61.41 % (n = 4 feet)", chain.outcome(needed.voltage),
                       "61.41 % measured at 'some ten volts' (seed 001)"))
    strong = STRONG_FEELING / chain.amplitude_per_volt()
    print(outcome_line("0.65 um at the feet", chain.outcome(strong), "0.65 um: strong feeling (seed 001)"))
    three = chain_from_rom(chain.rom, FootContact(FootParameters(), PRELOAD, SPEED), feet=3, errors=chain.errors)
    needed3 = three.voltage_for(MEASURED_REDUCTION)
    print(outcome_line("voltage for 61.41 %, n = 3 (kt's fit)", three.outcome(needed3.voltage),
                       "kt identified at 0.65 um, n = 3"))
    print(f"\nrise time {1e3 * chain.rom.envelope_time_constant:.3f} ms (+-{pm(chain.error('time_constant'))}, "
          f"Q {1 / (2 * chain.rom.zeta):.4g}, the default damping) vs seed 001's ~{1e3 * RESPONSE_TIME_001:g} ms\n")
    print("Sensitivity of the voltage for 61.41 % and of the reduction at the voltage above to the parameters the "
          "seeds do not give:\n")
    print("| parameter | value | voltage for 61.41 % [V] | reduction at "
          f"{needed.voltage:.2f} V [%] |\n|---|---|---|---|")
    base = FootParameters()
    variants = [("kt [N/m]", "kt", base.kt * f) for f in (0.5, 2.0)] + \
               [("kn [N/m]", "kn", base.kn * f) for f in (0.5, 2.0)] + \
               [("dn [N s/m]", "dn", base.dn * f) for f in (0.5, 2.0)]
    for label, name, value in variants:
        v = chain_from_rom(chain.rom, FootContact(base.with_(**{name: value}), PRELOAD, SPEED), errors=chain.errors)
        print(f"| {label} | {value:.3g} | {v.voltage_for(MEASURED_REDUCTION).voltage:.2f} | "
              f"{100 * v.outcome(needed.voltage).reduction:.1f} |")
    for q in (100.0, 300.0):
        v = chain_from_rom(with_q(chain.rom, q), chain.contact, errors=chain.errors)
        print(f"| Q | {q:g} | {v.voltage_for(MEASURED_REDUCTION).voltage:.2f} | "
              f"{100 * v.outcome(needed.voltage).reduction:.1f} |")
    feet = output_points(scene, [o for o in chain.rom.shapes if o.startswith("foot")])  # the foot tips' centres
    hmap = haptic_map(chain, np.array(list(feet.values())), needed.voltage)
    write_map(hmap, scene, chain, out / "cube_plate_feet", 0.6)


def write_map(hmap, scene, chain, stem: Path, required: float) -> None:
    from modalfe.plot.contact import haptic_map_figure

    stem.parent.mkdir(parents=True, exist_ok=True)
    hmap.write_csv(f"{stem}.csv")
    hmap.write_vtu(f"{stem}.vtu")
    outline = [(p.name, p.lo[:2], p.hi[:2]) for p in scene.full_assembly().parts]
    title = f"{scene.name} {chain.rom.label}, {chain.frequency / 1e3:.1f} kHz, {hmap.voltage:.3g} V"
    haptic_map_figure(hmap, outline, required=required, title=title).savefig(f"{stem}.png", dpi=110)
    mid, low, high = hmap.area_fraction(required)
    print(f"\nmap {stem}.png: {len(hmap.points)} points, reduction {100 * hmap.reduction.min():.1f} to "
          f"{100 * hmap.reduction.max():.1f} %; area reaching {100 * required:.3g} %: {100 * mid:.1f} % "
          f"({100 * low:.1f} to {100 * high:.1f} % over the amplitude's error)\n")


def glass_plate(out: Path) -> None:
    scene = load_scene("glass_plate")
    chains = {}
    print("## Glass plate (seed 004), finger at the reduced model's reference output\n")
    print(HEADER)
    for near, (pp, tau) in GLASS.items():
        start = time.perf_counter()
        chain = chains[near] = haptic_chain(scene, FingerContact(FingerParameters()), near=near)
        built = time.perf_counter() - start
        volts = pp / 2 / chain.amplitude_per_volt()
        print(outcome_line(f"{chain.rom.label} {chain.frequency / 1e3:.1f} kHz at {chain.output}, {1e9 * pp:.0f} nm pp "
                           f"(chain {built:.0f} s)", chain.outcome(volts),
                           f"{1e9 * pp:.0f} nm pp measured; rise {1e3 * tau:g} ms"))
    low, high = chains[66e3], chains[225e3]
    print("\nEqual friction (the finger at each mode's frequency): amplitudes and voltages for the same reduction\n")
    print("| reduction | A low [nm pp] | A high [nm pp] | A_high / A_low | V low [V] | V high [V] | seed 004 |\n"
          "|---|---|---|---|---|---|---|")
    for r in EQUAL_LEVELS:
        a, b = low.voltage_for(r), high.voltage_for(r)
        print(f"| {100 * r:g} % | {2e9 * a.amplitude:.1f} | {2e9 * b.amplitude:.2f} | "
              f"{b.amplitude / a.amplitude:.3f} | {a.voltage:.2f} (+-{pm(a.voltage_error)}) | "
              f"{b.voltage:.2f} (+-{pm(b.voltage_error)}) | "
              f"ratio {RATIO_004} (model, at 66 and 225 kHz) |")
    print("\nSensitivity of the reduction at the measured amplitudes to the finger's parameters (seed 004 Table I "
          "values x0.5 and x2):\n")
    print("| parameter | value | reduction low [%] | reduction high [%] |\n|---|---|---|---|")
    base = FingerParameters()
    for name in ("K_sc", "K_Tsc", "M_sc", "damping_ratio", "preload"):
        for f in (0.5, 1.0, 2.0):
            if f == 1.0 and name != "K_sc":
                continue
            p = base.with_(**{name: getattr(base, name) * f})
            cells = []
            for near, chain in chains.items():
                c = chain_from_rom(chain.rom, FingerContact(p), errors=chain.errors)
                cells.append(f"{100 * c.reduction_at(GLASS[near][0] / 2).reduction:.1f}")
            print(f"| {name if f != 1.0 else 'Table I'} | {getattr(p, name):.3g} | {' | '.join(cells)} |")
    for near, chain in chains.items():
        points, weights = surface_points(scene, count=MAP_POINTS)
        volts = GLASS[near][0] / 2 / chain.amplitude_per_volt()
        start = time.perf_counter()
        hmap = haptic_map(chain, points, volts, weights=weights)
        print(f"\nmap of {len(points)} points in {time.perf_counter() - start:.2f} s")
        write_map(hmap, scene, chain, out / f"glass_plate_{near / 1e3:.0f}kHz", 0.1)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the Cu-Be plate only")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "out" / "haptics")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.ERROR)
    cube_plate(args.out)
    if not args.quick:
        glass_plate(args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
