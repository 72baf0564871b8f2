"""`modalfe sweep`: a resumable parameter sweep on dask.distributed."""

from __future__ import annotations

from modalfe.cli.options import frequency, parse_params, positive_int, solve_keywords, solve_options
from modalfe.errors import SceneError
from modalfe.progress import is_shown


def register(subparsers) -> None:
    p = subparsers.add_parser("sweep", help="sweep scene parameters on dask (resumable, MAC-tracked)")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--param", action="append", required=True, metavar="NAME=START:STOP:COUNT",
                   help="a swept parameter (repeatable: the sweep is the Cartesian product)")
    p.add_argument("--out", required=True, help="results table (CSV); rerunning resumes it")
    p.add_argument("--scheduler", help="address of an existing dask scheduler (default: a LocalCluster); "
                   "'inline' computes the points one after another in this process")
    p.add_argument("--count", type=positive_int,
                   help="modes solved near --near at each point (default: the scene's analysis.count)")
    p.add_argument("--workers", type=positive_int, default=2, help="LocalCluster worker processes")
    p.add_argument("--mode", help="working-mode selector (default: the scene's first working mode)")
    p.add_argument("--near", type=frequency, help="frequency [Hz] to search near")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="fixed override for every point")
    p.add_argument("--outcome", metavar='"reduction volts=V [preload=N] [speed=M/S] [contact=foot|finger]"',
                   help="add the felt outcome at V volts as columns (as 'friction'/'finger' SCENE give it: the "
                        "friction reduction with its range from the amplitude's stated error, flight ratio, current, "
                        "power, rise time), through seed 000's foot (default) or seed 004's finger")
    p.add_argument("--json", action="store_true")
    solve_options(p)
    p.set_defaults(func=_sweep)


def _sweep(args) -> int:
    import json

    from modalfe.cli.options import parse_outcome, parse_overrides
    from modalfe.design.sweep import OutcomeColumns, sweep
    from modalfe.results.labels import check_selector
    from modalfe.scene import load_scene
    from modalfe.solve.api import seek

    params = parse_params(args.param)
    base = parse_overrides(args.set)
    outcome = parse_outcome("--outcome", args.outcome, {"reduction": ("volts",)}) if args.outcome else None
    scene = load_scene(args.scene, **base)
    selector, near = seek(scene, None if args.mode is None else check_selector(args.mode, "--mode"), args.near)
    if selector is None or near is None:
        raise SceneError("--mode/--near: the scene names no working mode")
    resolution = solve_keywords(args)
    extra = None
    if outcome is not None:
        _, given, contact = outcome
        extra = OutcomeColumns(given["volts"], contact, selector, near, tuple(sorted(resolution.items())))
    rows = sweep(args.scene, params, out=args.out, selector=selector, near=near, base=base,
                 scheduler=args.scheduler, workers=args.workers, count=args.count,
                 progress=is_shown(), resolution=resolution, extra=extra)
    if args.json:
        print(json.dumps([{k: r[k] for k in ("params", "status", "label", "frequency_hz", "error_estimate",
                                             "tracked_label",
                                             "tracked_frequency_hz", "mac_previous", "crossing", "dofs", "seconds",
                                             "extra")}
                          for r in rows], indent=2))
        return 0
    names = list(params)

    def number(value, spec: str) -> str:
        return format(value, spec) if value is not None else format("-", spec.split(".")[0].rstrip("fg"))

    felt = f"  {'reduction [%] (range)':>22} {'flight %':>8} {'P [mW]':>8}" if extra else ""
    print("  ".join(f"{n:>14}" for n in names) + f"  {'f [Hz]':>12} {'err est':>8} {'label':<12} {'tracked f':>12} "
          f"{'MAC prev':>8}{felt}  crossing")
    for r in rows:
        values = "  ".join(f"{r['params'][n]:>14.6g}" for n in names)
        note = ("YES: " + (r["tracked_label"] or "nothing to follow")) if r["crossing"] else ""
        if r["status"] != "ok":
            note += f" ({r['status']})"
        err = "unknown" if r.get("error_estimate") is None else f"{100 * r['error_estimate']:.3f}%"
        print(f"{values}  {number(r['frequency_hz'], '>12.1f')} {err:>8} {r['label'] or '-':<12} "
              f"{number(r['tracked_frequency_hz'], '>12.1f')} {number(r['mac_previous'], '>8.3f')}"
              f"{_felt(r['extra']) if extra else ''}  {note}")
    return 0


def _felt(o: dict) -> str:
    """The outcome's columns of a row (``Outcome.to_json``), blank where the point has none."""
    if "friction_reduction" not in o:
        return f"  {'-':>22} {'-':>8} {'-':>8}"
    low, high = o["friction_reduction_range"]
    power = "-" if o["power_w"] is None or o["power_w"] != o["power_w"] else f"{1e3 * o['power_w']:.4g}"
    reduction = f"{100 * o['friction_reduction']:.2f} ({100 * low:.2f}-{100 * high:.2f})"
    return f"  {reduction:>22} {o['flight_ratio_percent']:>8.3g} {power:>8}"
