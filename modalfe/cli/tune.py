"""``modalfe tune``: change scene parameters until modes sit on target frequencies (3-D solid), optionally
maximizing k_eff or an outcome (``--objective``: the voltage for a friction reduction, the reduction at a voltage,
the share of the touch surface reaching a reduction), keeping a separation from neighbouring modes, modes above or
below a frequency (``--mode-bound``) and the feet on the antinodes; from one start or several on the sweep's Dask
cluster; the final design written as a scene file."""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import replace
from pathlib import Path

from modalfe.cli.options import (
    parse_bound,
    parse_fraction,
    parse_names,
    parse_outcome,
    parse_overrides,
    parse_positive,
    parse_target,
    positive_int,
    scene_options,
    solve_keywords,
    solve_options,
)
from modalfe.cli.page import add_html_option, scene_page
from modalfe.errors import SceneError
from modalfe.progress import is_shown


def register(sub) -> None:
    from modalfe.design.tuning import RESOLVED_SHARE
    from modalfe.solve.api import DEFAULT_TOL

    p = sub.add_parser("tune", help="change parameters until modes reach target frequencies (3-D solid)")
    p.add_argument("scene", help="built-in scene name or path to a .toml scene file")
    p.add_argument("--target", required=True, action="append", metavar="LABEL=HZ",
                   help='a mode and its frequency, "(0,6)=40.7e3" (repeatable, one per mode label)')
    p.add_argument("--vary", required=True, metavar="P1,P2,...",
                   help="parameters changed (as for modalfe sensitivity): builder parameters, materials.NAME.KEY, "
                        "springs.GROUP, masses.GROUP, parts.NAME.origin|size.x|y|z")
    p.add_argument("--bounds", action="append", metavar="NAME=LOW:HIGH", help="limits of a parameter (repeatable)")
    p.add_argument("--tol", type=float, default=DEFAULT_TOL,
                   help=f"relative distance to the targets, the resolved model's stated error included (default "
                        f"{DEFAULT_TOL:g}, as every command; the model is resolved to {RESOLVED_SHARE:g} of it)")
    p.add_argument("--maximize", choices=("k_eff",), help="maximize the first target mode's coupling k_eff")
    p.add_argument("--objective", metavar='"volts-for reduction=R | reduction-at volts=V | area reduction=R volts=V '
                                          '[width=S] [preload=N] [speed=M/S] [contact=foot|finger]"',
                   help="volts-for: minimize the drive voltage at which the first target mode gives the friction "
                        "reduction R (fraction or %%) at the output that moves most; reduction-at: maximize the "
                        "friction reduction there at the drive voltage V [V]; area: maximize the share of the touch "
                        "surface (finger: the main part's top face; foot: the feet) reaching R at V, smoothed over S "
                        "of reduction (default 0.02); through the contact model (foot: seed 000's, default; finger: "
                        "seed 004's) at that preload [N] and sliding speed [m/s]; the final design's outcome is "
                        "computed on the resolved model")
    p.add_argument("--mode-bound", action="append", metavar='"LABEL>=HZ" | "LABEL<=HZ"',
                   help='keep a mode\'s frequency above (or below) a limit, its stated error included on the resolved '
                        'model, e.g. "(0,6)>=20e3" above the audible range (repeatable)')
    p.add_argument("--separation", metavar="FRACTION|PERCENT%",
                   help="least relative distance of the first target mode to its neighbours, e.g. 3%%")
    p.add_argument("--replace-feet", action=argparse.BooleanOptionalAction, default=None,
                   help="re-place the feet on the first target mode's antinodes after each iterate (default: on "
                        "when the scene has feet)")
    p.add_argument("--max-iterations", type=positive_int, default=12, help="most evaluations (default 12)")
    p.add_argument("--starts", type=positive_int, default=1,
                   help="starting points spread inside --bounds (Latin hypercube; needs bounds for every "
                        "parameter when > 1); the best result is kept")
    p.add_argument("--seed", type=int, default=0, help="seed of the starting points (default 0)")
    p.add_argument("--scheduler", help="with --starts: address of an existing dask scheduler (default: a "
                   "LocalCluster); 'inline' runs the starts one after another in this process")
    p.add_argument("--workers", type=positive_int, help="with --starts: LocalCluster worker processes "
                                                        "(default: one per start, at most the CPU count)")
    p.add_argument("--out", metavar="DESIGN.toml", help="write the final design as a scene file")
    solve_options(p, tol=False)
    add_html_option(p)
    scene_options(p, _tune)


def _tune(args) -> int:
    from modalfe.design.feet import feet_text, has_feet
    from modalfe.design.multistart import latin_hypercube
    from modalfe.design.outcome import LargestArea, LeastVoltage
    from modalfe.design.tune_checks import check_variables
    from modalfe.design.tune_starts import TuneTask, best_result
    from modalfe.design.tuning import FrequencyTarget, tune
    from modalfe.scene import load_scene
    from modalfe.scene.writing import scene_to_toml

    targets = [parse_target(text) for text in args.target]
    names = parse_names(args.vary)
    bounds = dict(parse_bound(text) for text in args.bounds or [])
    separation = parse_fraction("--separation", args.separation) if args.separation is not None else None
    objective = parse_objective(args.objective) if args.objective is not None else None
    mode_bounds = tuple(parse_mode_bound(text) for text in args.mode_bound or [])
    if objective is not None and args.maximize:
        raise SceneError("--objective: give it or --maximize, not both")
    scene = load_scene(args.scene, **parse_overrides(args.set))
    check_variables(scene, names)  # before the header and any solve
    replace_feet = has_feet(scene) if args.replace_feet is None else args.replace_feet
    if args.out is not None:
        if Path(args.out).suffix.lower() != ".toml":
            raise SceneError(f"--out: '{args.out}' must end in .toml (a scene file)")
        scene_to_toml(scene)  # a device the file format cannot hold is refused before any solve
    if args.starts > 1:
        missing = [n for n in names if n not in bounds]
        if missing:
            raise SceneError(f"--bounds: --starts {args.starts} spreads the starts inside the bounds; give "
                             f"--bounds {missing[0]}=LOW:HIGH")
    options = {"tol": args.tol, "bounds": bounds, "maximize": objective or args.maximize, "separation": separation,
               "replace_feet": replace_feet, "max_iterations": args.max_iterations,
               "resolution": solve_keywords(args), "mode_bounds": mode_bounds}

    def progress(k, it) -> None:
        if not args.json:
            print(_line(k, it, targets), flush=True)

    if not args.json:
        goals = ", ".join(f"{label} to {hz:.6g} Hz" for label, hz in targets)
        extras = [f"maximizing {args.maximize}"] if args.maximize else []
        if objective:  # the contact as each design's is: at the target, the feet the outputs name sharing the load
            from modalfe.contact.chain import feet_among
            at = objective.contact.tuned(targets[0][1], feet_among(scene.drive.outputs))
            verb = "minimizing" if isinstance(objective, LeastVoltage) else "maximizing"
            extras.append(f"{verb} {replace(objective, contact=at).describe()}")
        extras += [f"separation >= {separation:.2%}"] if separation else []
        extras += [f"{b.describe()} (stated error included)" for b in mode_bounds]
        extras += ["feet re-placed on the antinodes"] if replace_feet else []
        print(f"{scene.name}: tuning {goals} within {args.tol:.2%} by {', '.join(names)}"
              + (f" ({'; '.join(extras)})" if extras else ""))
    goals = tuple(FrequencyTarget(label, hz) for label, hz in targets)
    table = None
    if args.starts == 1:
        result = tune(scene, goals, names, **options, progress=progress)
    else:
        from modalfe.design.multistart import run_starts

        starts = latin_hypercube({n: bounds[n] for n in names}, args.starts, seed=args.seed)
        results = run_starts(TuneTask(scene, goals, tuple(names), options), starts, scheduler=args.scheduler,
                             workers=args.workers, progress=is_shown())
        table = list(zip(starts, results))
        chosen = best_result(results)
        if not args.json:
            _print_starts(table, names, chosen)
        result = results[chosen]
        if isinstance(result, BaseException):
            raise result  # every start failed: the first's error
        if not args.json:
            print(f"best: start {chosen + 1}")
    final = result.final
    if args.out is not None:
        Path(args.out).write_text(scene_to_toml(result.scene), encoding="utf-8")
    scene_page(args, result.scene)  # the tuned design's
    if args.json:
        out = {"scene": scene.name, "targets": [{"label": t.label, "target_hz": t.frequency, "frequency_hz": f}
                                                for t, f in zip(goals, final.frequencies)],
               "tol": args.tol, "converged": result.converged, "reason": result.reason, "solves": result.solves,
               "seconds": result.seconds, "parameters": final.values, "frequency_hz": final.frequencies[0],
               "k_eff": _number(final.k_eff), "separation": _number(final.separation),
               "feet": [list(f) for f in final.feet], "out": args.out,
               "iterates": [_iterate_json(it) for it in result.iterates]}
        if result.mode_bounds:
            out["mode_bounds"] = [_bound_json(b, f, e) for b, f, e in zip(result.mode_bounds, final.bounded,
                                                                             final.bound_errors)]
        if isinstance(objective, LargestArea):
            out["verified"] = {"area": _area_json(result.verified, objective), "outcome": result.outcome.to_json()}
        elif result.verified is not None:
            out["verified"] = {"reduction": result.verified.reduction, "output": result.verified.output,
                               "voltage_v": result.verified.voltage, "amplitude_m": result.verified.amplitude,
                               "voltage_error": _number(result.verified.voltage_error),
                               "outcome": result.outcome.to_json()}
        elif result.outcome is not None:
            out["verified"] = {"outcome": result.outcome.to_json()}
        if table is not None:
            out["starts"] = [{"start": s, "error": str(r)} if isinstance(r, BaseException) else
                             {"start": s, "converged": r.converged, "reason": r.reason, "parameters": r.final.values,
                              "frequencies_hz": list(r.final.frequencies), "k_eff": _number(r.final.k_eff),
                              "solves": r.solves, "seconds": r.seconds} for s, r in table]
        print(json.dumps(out, indent=2))
    else:
        verdict = "reached" if result.converged else "NOT reached"
        reached = ", ".join(f"{t.label} at {f:.2f} Hz ({100 * (f / t.frequency - 1):+.4f} %{_stated(final, i)})"
                            for i, (t, f) in enumerate(zip(goals, final.frequencies)))
        print(f"{verdict}: {reached} after {result.solves} solves, {result.seconds:.1f} s ({result.reason})")
        if args.maximize:
            first = result.first_on_target
            start = "not reached" if first is None else f"{first.k_eff:.5f} at the first design on the targets"
            gain = "" if first is None else f" ({100 * (final.k_eff / first.k_eff - 1):+.2f} %)"
            print(f"k_eff {result.iterates[0].k_eff:.5f} at the start, {start}, {final.k_eff:.5f} final{gain}")
        for b, f, e in zip(result.mode_bounds, final.bounded, final.bound_errors):
            print(_bound_line(b, f, e))
        if result.outcome is not None:
            _print_verified(result)
        if final.feet:
            print(f"feet: {feet_text(final.feet)}")
        print("parameters: " + " ".join(_reproduce(final)))
        if args.out is not None:
            print(f"design written to {args.out}")
    if not result.converged:
        print(f"modalfe: tune: not converged (tol {args.tol:.2%}): {result.reason}", file=sys.stderr)
        return 1
    return 0


def parse_objective(text: str):
    """``volts-for reduction=R [preload=N] [speed=M/S] [contact=foot|finger]`` -> ``LeastVoltage``,
    ``reduction-at volts=V [...]`` -> ``ReductionAt``, ``area reduction=R volts=V [width=S] [...]`` -> ``LargestArea``;
    SceneError naming --objective otherwise (before any solve)."""
    from modalfe.design.outcome import AREA_WIDTH, LargestArea, LeastVoltage, ReductionAt

    kind, given, contact = parse_outcome("--objective", text, {"volts-for": ("reduction",), "reduction-at": ("volts",),
                                                               "area": ("reduction", "volts")}, {"area": ("width",)})
    if kind == "volts-for":
        return LeastVoltage(given["reduction"], contact)
    if kind == "reduction-at":
        return ReductionAt(given["volts"], contact)
    return LargestArea(given["reduction"], given["volts"], contact, given.get("width", AREA_WIDTH))


def parse_mode_bound(text: str):
    """``LABEL>=HZ`` or ``LABEL<=HZ`` -> ``FrequencyBound``; SceneError naming --mode-bound otherwise (before any
    solve)."""
    from modalfe.design.tuning import FrequencyBound
    from modalfe.results.labels import check_selector

    form = 'expected "LABEL>=HZ" or "LABEL<=HZ", e.g. "(0,6)>=20e3"'
    op = next((o for o in (">=", "<=") if o in text), None)
    if op is None:
        raise SceneError(f"--mode-bound: {form}, got '{text}'")
    label, _, value = text.partition(op)
    check_selector(label, "--mode-bound")
    if not value.strip():
        raise SceneError(f"--mode-bound: '{text}' has no frequency after {op}; {form}")
    return FrequencyBound(label.strip(), parse_positive("--mode-bound", "the frequency", value.strip()), op == ">=")


def _bound_line(bound, frequency: float, error: float) -> str:
    """A mode bound at the final design: the frequency, its stated error and the bound with the error included."""
    sign = "-" if bound.above else "+"
    stated = f"stated error {100 * error:.3g} %, f (1 {sign} e) = {bound.edge(frequency, error):.2f} Hz"
    if math.isnan(error):
        stated = "no stated error (not estimated: the frequency alone is compared)"
    verdict = "met" if bound.met(frequency, error) else "NOT met"
    return f"bound {bound.describe()}: {frequency:.2f} Hz, {stated}: {verdict}"


def _bound_json(bound, frequency: float, error: float) -> dict:
    return {"label": bound.label, "limit_hz": bound.frequency, "above": bound.above, "frequency_hz": frequency,
            "stated_error": _number(error)}


def _area_json(hmap, objective) -> dict:
    mid, low, high = hmap.area_fraction(objective.required)
    return {"required": objective.required, "voltage_v": hmap.voltage, "points": len(hmap.points),
            "area_fraction": mid, "area_fraction_range": [low, high], "amplitude_error": hmap.amplitude_error}


def _print_verified(result) -> None:
    """The voltage for the required reduction at the first and final designs (own mesh) and verified at the final
    design on the resolved model, with the outcome there and its stated errors."""
    from modalfe.design.outcome import LargestArea

    v, o = result.verified, result.outcome
    first = result.iterates[0]
    last = next(it for it in reversed(result.iterates) if not it.resolved and it.accepted)
    if isinstance(result.maximize, LargestArea):  # the map on the resolved model
        required = result.maximize.required
        mid, low, high = v.area_fraction(required)
        print(f"area reaching {required:.2%} at {v.voltage:g} V: {first.area:.2%} at the start, {last.area:.2%} at the "
              f"last design on the scene's own mesh (smoothed {first.outcome_merit:.2%} -> {last.outcome_merit:.2%})")
        print(f"verified on the resolved model: {mid:.2%} of the touch surface ({len(v.points)} points) reaches "
              f"{required:.2%} at {v.voltage:g} V (range {low:.2%}-{high:.2%} from the amplitude's stated "
              f"{100 * v.amplitude_error:.3g} % and the contact states' uncertainty); reduction "
              f"{100 * v.reduction.min():.2f} to {100 * v.reduction.max():.2f} % over the surface")
        return
    if v is not None:
        print(f"voltage for {v.reduction:.2%} at {last.output}: {first.volts:.4g} V at the start, {last.volts:.4g} V "
              f"at the last design on the scene's own mesh ({100 * (last.volts / first.volts - 1):+.2f} %)")
        stated = f" [{100 * v.voltage_error:.3g} %]" if math.isfinite(v.voltage_error) else ""
        where = f"{v.voltage:.4g} V{stated} at {v.output} ({1e9 * v.amplitude:.4g} nm 0-peak); there"
    else:
        print(f"reduction at {o.voltage:.4g} V at {last.output}: {first.reduction:.2%} at the start, "
              f"{last.reduction:.2%} at the last design on the scene's own mesh")
        stated = f" [{100 * o.amplitude_error:.3g} %]" if math.isfinite(o.amplitude_error) else ""
        where = f"{o.voltage:.4g} V at {o.output} ({1e9 * o.amplitude:.4g} nm 0-peak{stated}):"
    print(f"verified on the resolved model: {where} reduction {o.reduction:.2%} (range {o.reduction_range[0]:.2%}-"
          f"{o.reduction_range[1]:.2%} from the amplitude's stated error), flight {o.flight_ratio:.3g} %, current "
          f"{1e3 * o.current:.4g} mA, power {1e3 * o.power:.4g} mW, rise time {1e3 * o.rise_time:.3g} ms")


def _reproduce(final) -> list[str]:
    """The ``--set`` options that give the final design: its parameters at full precision (``repr``: the design
    itself, not a rounding of it) and the feet it moved."""
    sets = [f"--set {n}={v!r}" for n, v in final.values.items() if not n.startswith("parts.")]
    if final.feet:
        sets.append("--set 'feet=[" + ", ".join(f"[{x!r}, {y!r}]" for x, y in final.feet) + "]'")
    return sets


def _line(k: int, it, targets) -> str:
    """One iterate of the progress log."""
    freqs = "  ".join(f"{f:11.2f} Hz {100 * (f / hz - 1):+8.4f} %{_stated(it, i)}"
                      for i, (f, (_, hz)) in enumerate(zip(it.frequencies, targets)))
    values = ", ".join(f"{n} = {v:.6g}" for n, v in it.values.items())
    slopes = "; ".join(", ".join(f"{s:+.3f}" for s in row.values()) for row in it.relative_sensitivity)
    text = f"{k:>3}  {freqs}  {values}  (d ln f / d ln p {slopes}; {it.solves} solves, {it.seconds:.1f} s)"
    if math.isfinite(it.k_eff):
        text += f"  k_eff {it.k_eff:.5f}"
    if math.isfinite(it.volts):
        text += f"  {1e9 * it.amplitude_per_volt:.4g} nm/V at {it.output}, {it.volts:.4g} V"
        text += f", reduction {it.reduction:.2%}" if math.isfinite(it.reduction) else ""
        text += f" (mean), area {it.area:.2%} (smoothed {it.outcome_merit:.2%})" if math.isfinite(it.area) else ""
    for f, e in zip(it.bounded, it.bound_errors):
        text += f"  bound mode {f:.2f} Hz" + (f" (stated error {100 * e:.3g} %)" if not math.isnan(e) else "")
    if math.isfinite(it.separation):
        text += f"  separation {it.separation:.2%}"
    if it.feet:
        from modalfe.design.feet import feet_text

        text += f"  feet {feet_text(it.feet)}"
    return "\n".join([text] + [f"     {note}" for note in it.notes])


def _stated(it, i: int) -> str:
    """The stated error of target ``i``'s mode in an iterate solved on the resolved model, else nothing."""
    return f", stated error {100 * it.errors[i]:.3g} %" if it.resolved and i < len(it.errors) else ""


def _print_starts(table, names, chosen: int) -> None:
    print(f"{'start':>5}  " + "  ".join(f"{n:>14}" for n in names) + "  result")
    for i, (start, r) in enumerate(table):
        values = "  ".join(f"{start[n]:>14.6g}" for n in names)
        if isinstance(r, BaseException):
            outcome = f"error: {r}"
        else:
            outcome = (("converged" if r.converged else "not converged") + f", residual {r.residual:.2e}"
                       + (f", k_eff {r.final.k_eff:.5f}" if r.maximize else "")
                       + f", {r.solves} solves, {r.seconds:.1f} s ({r.reason})")
        print(f"{i + 1:>5}{'*' if i == chosen else ' '} {values}  {outcome}")


def _iterate_json(it) -> dict:
    return {"values": it.values, "frequencies_hz": list(it.frequencies), "frequency_hz": it.frequencies[0],
            "dlnf_dlnp": list(it.relative_sensitivity), "k_eff": _number(it.k_eff),
            "separation": _number(it.separation), "feet": [list(f) for f in it.feet], "solves": it.solves,
            "seconds": it.seconds, "accepted": it.accepted, "notes": list(it.notes), "resolved": it.resolved,
            "stated_errors": [_number(e) for e in it.errors], "volts": _number(it.volts),
            "amplitude_per_volt_m": _number(it.amplitude_per_volt), "output": it.output or None,
            "reduction": _number(it.reduction), "area": _number(it.area),
            "area_smoothed": _number(it.outcome_merit) if math.isfinite(it.area) else None,
            "bound_frequencies_hz": list(it.bounded), "bound_stated_errors": [_number(e) for e in it.bound_errors]}


def _number(x: float) -> float | None:
    return x if math.isfinite(x) else None
