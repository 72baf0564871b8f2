"""``modalfe friction SCENE`` and ``modalfe finger SCENE``: the chain from the scene's working mode to the felt
outcome (``modalfe.contact.chain``): outcomes per voltage, the voltage for a required reduction and the haptic map.
A thin layer: parse, call, print."""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import numpy as np

from modalfe.errors import ContactError
from modalfe.progress import is_shown

MAP_LEVELS = (0.1, 0.25, 0.5)  # reductions whose area fractions a map prints beside --required


def add_options(p: argparse.ArgumentParser) -> None:
    """The flags of the scene form (``SCENE`` given): the mode, the contact's output, the outcome targets, the map."""
    from modalfe.cli.options import frequency, positive_float, solve_options

    g = p.add_argument_group("with a SCENE: the chain from its working mode (docs/haptics.md)")
    g.add_argument("--mode", help="working-mode label or family (default: the scene's)")
    g.add_argument("--near", type=frequency, help="frequency [Hz] the working mode is sought near")
    g.add_argument("--damping", help="zeta=Z, Q=Q or rayleigh=ALPHA,BETA (default: the scene's)")
    g.add_argument("--output", help="output of the reduced model where the contact sits (default: its reference)")
    g.add_argument("--reduction", type=positive_float, help="required friction reduction (0-1): print the voltage")
    g.add_argument("--map", action="store_true", help="the reduction over the touch surface (finger) or at the feet")
    g.add_argument("--points", type=int, default=400, help="points of the touch surface map (default 400)")
    g.add_argument("--required", type=positive_float, help="reduction (0-1) whose area fraction the map reports")
    g.add_argument("--map-dir", metavar="DIR", help="directory for the map's CSV, VTU and PNG (made if missing)")
    solve_options(p)


def run(args, contact, volts: np.ndarray | None, *, feet_map: bool) -> int:
    """Outcomes of ``args.scene``'s chain with ``contact`` at each of ``volts`` (``--voltage``, parsed); ``feet_map``:
    the map is at the reduced model's foot outputs, else over the main part's top face."""
    from modalfe.cli.options import solve_keywords
    from modalfe.contact.chain import haptic_chain, haptic_map, surface_points
    from modalfe.response.forced import Damping
    from modalfe.scene import load_scene

    if volts is None:
        raise ContactError("--voltage: give the drive voltage [V] with a scene")
    if args.map and len(volts) != 1:
        raise ContactError("--voltage: --map takes one voltage")
    if args.map and args.points < 1:
        raise ContactError(f"--points: at least 1, got {args.points}")
    for name in ("reduction", "required"):
        value = getattr(args, name)
        if value is not None and not value < 1:
            raise ContactError(f"--{name}: a fraction strictly between 0 and 1, got {value:g}")
    scene = load_scene(args.scene)
    damping = Damping.parse(args.damping) if args.damping is not None else None
    chain = haptic_chain(scene, contact, output=args.output, selector=args.mode, near=args.near, damping=damping,
                         **solve_keywords(args))
    outcomes = [chain.outcome(v) for v in volts]
    needed = chain.voltage_for(args.reduction) if args.reduction is not None else None
    hmap = None
    if args.map:
        if feet_map:
            from modalfe.contact.chain import foot_outputs
            from modalfe.response.loads import output_points

            feet = foot_outputs(chain.rom.shapes) or [chain.output]
            points, weights = np.array(list(output_points(scene, feet).values())), None
        else:
            points, weights = surface_points(scene, count=args.points)
        hmap = haptic_map(chain, points, float(volts[0]), weights=weights, progress=is_shown())
    required = args.required if args.required is not None else args.reduction
    written = _write_map(hmap, scene, chain, required, args.map_dir) if hmap is not None and args.map_dir else []
    if args.json:
        print(json.dumps(_json(scene, chain, outcomes, needed, hmap, required, written), indent=2))
        return 0
    _print(scene, chain, outcomes, needed, hmap, required, written)
    return 0


def _levels(required: float | None) -> list[float]:
    return sorted({*MAP_LEVELS, *([required] if required is not None else [])})


def _write_map(hmap, scene, chain, required: float | None, out: str) -> list[str]:
    """The map's CSV, VTU and PNG in ``out``; their paths."""
    from modalfe.plot.contact import haptic_map_figure

    d = Path(out)
    d.mkdir(parents=True, exist_ok=True)
    stem = d / re.sub(r"[^\w.-]+", "_", f"{scene.name} {chain.rom.label} {hmap.voltage:g}V").replace("__", "_")
    paths = [f"{stem}.csv", f"{stem}.vtu", f"{stem}.png"]
    hmap.write_csv(paths[0])
    hmap.write_vtu(paths[1])
    outline = [(p.name, p.lo[:2], p.hi[:2]) for p in scene.full_assembly().parts]
    title = (f"{scene.name} {chain.rom.label} at {chain.frequency / 1e3:.1f} kHz, {hmap.voltage:g} V: "
             f"friction reduction")
    haptic_map_figure(hmap, outline, required=required, title=title).savefig(paths[2], dpi=120)
    return paths


def _json(scene, chain, outcomes, needed, hmap, required, written) -> dict:
    out = {"scene": scene.name, "mode": chain.rom.label, "frequency_hz": chain.frequency, "output": chain.output,
           "contact": chain.contact.describe(), "amplitude_per_volt_m": chain.amplitude_per_volt(),
           "outcomes": [o.to_json() for o in outcomes],
           "voltage_for": None if needed is None else {
               "reduction": needed.reduction, "voltage_v": needed.voltage, "amplitude_m": needed.amplitude,
               "voltage_error": None if not np.isfinite(needed.voltage_error) else needed.voltage_error}}
    if hmap is not None:
        out["map"] = {"voltage_v": hmap.voltage, "points": len(hmap.points),
                      "reduction_max": float(hmap.reduction.max()), "reduction_min": float(hmap.reduction.min()),
                      "interpolation_bound": float(hmap.bracket.max()),
                      "area_fraction": {f"{x:g}": hmap.area_fraction(x) for x in _levels(required)},
                      "files": written}
    return out


def _print(scene, chain, outcomes, needed, hmap, required, written) -> None:
    from modalfe.cli.options import stated

    rom = chain.rom
    print(f"{scene.name}: mode {rom.label} at {chain.frequency:.2f} Hz, contact at {chain.output}: "
          f"{chain.contact.describe()}")
    print(f"  amplitude per volt {1e9 * chain.amplitude_per_volt():.3f} nm/V 0-peak "
          f"[{stated(chain.error(f'amplitude:{chain.output}'))}]; amplitude rise time Q / (pi f) "
          f"{1e3 * rom.envelope_time_constant:.3f} ms [{stated(chain.error('time_constant'))}] "
          f"({rom.damping_description})")
    print(f"  {'V [V]':>7} {'W [um]':>8} {'reduction [%]':>14} {'range [%]':>15} {'+-contact':>9} {'flight [%]':>10} "
          f"{'I [mA]':>8} {'+-':>8} {'P [mW]':>8} {'+-':>8}")
    for o in outcomes:
        lo, hi = o.reduction_range
        print(f"  {o.voltage:7.2f} {1e6 * o.amplitude:8.4f} {100 * o.reduction:14.2f} "
              f"{100 * lo:7.2f}-{100 * hi:<7.2f} {100 * o.contact_uncertainty:9.2f} {o.flight_ratio:10.2f} "
              f"{1e3 * o.current:8.4g} {stated(o.current_error):>8} {1e3 * o.power:8.4g} {stated(o.power_error):>8}")
    print("  [range: the reduction at the amplitude -+ its stated error; +-contact: uncertainty of a time average "
          "(95 % bound)]")
    if needed is not None:
        print(f"  voltage for a {100 * needed.reduction:g} % reduction: {needed.voltage:.3f} V "
              f"[{stated(needed.voltage_error)}] (W = {1e6 * needed.amplitude:.4f} um 0-peak)")
    if hmap is not None:
        print(f"  map at {hmap.voltage:g} V over {len(hmap.points)} points: reduction {100 * hmap.reduction.min():.2f} "
              f"to {100 * hmap.reduction.max():.2f} % (table of {len(hmap.table)} contact states, interpolation "
              f"within {100 * hmap.bracket.max():.2f} %)")
        for x in _levels(required):
            mid, low, high = hmap.area_fraction(x)
            print(f"    area reaching {100 * x:g} %: {100 * mid:.1f} % (amplitude -+ error: {100 * low:.1f} to "
                  f"{100 * high:.1f} %)")
        for path in written:
            print(f"  written {path}")
