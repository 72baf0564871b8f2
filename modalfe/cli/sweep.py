"""`modalfe sweep`: a resumable parameter sweep on dask.distributed."""

from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser("sweep", help="sweep scene parameters on dask (resumable, MAC-tracked)")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--param", action="append", required=True, metavar="NAME=START:STOP:COUNT",
                   help="a swept parameter (repeatable: the sweep is the Cartesian product)")
    p.add_argument("--out", required=True, help="results table (CSV); rerunning resumes it")
    p.add_argument("--scheduler", help="address of an existing dask scheduler (default: a LocalCluster)")
    p.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    p.add_argument("--mode", help="working-mode selector (default: the scene's first working mode)")
    p.add_argument("--near", type=float, help="frequency [Hz] to search near")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="fixed override for every point")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_sweep)


def _sweep(args) -> int:
    import json

    from modalfe.cli.options import parse_overrides
    from modalfe.errors import SceneError
    from modalfe.scene import load_scene
    from modalfe.sweeps.sweep import grid_values, sweep

    params = {}
    for item in args.param:
        name, sep, spec = item.partition("=")
        if not sep:
            raise SceneError(f"--param: expected NAME=START:STOP:COUNT, got '{item}'")
        params[name] = grid_values(spec)
    base = parse_overrides(args.set)
    scene = load_scene(args.scene, **base)
    wm = scene.working_modes[0] if scene.working_modes else None
    selector = args.mode or (wm.selector if wm else None)
    near = args.near or (wm.near if wm else None)
    if selector is None or near is None:
        raise SceneError("--mode/--near: the scene names no working mode")
    rows = sweep(args.scene, params, out=args.out, selector=selector, near=near, base=base,
                 scheduler=args.scheduler, workers=args.workers, progress=not args.json)
    if args.json:
        print(json.dumps([{k: r[k] for k in ("params", "label", "frequency_hz", "tracked_label", "mac_previous",
                                             "crossing", "dofs", "seconds")} for r in rows], indent=2))
        return 0
    names = list(params)
    print("  ".join(f"{n:>14}" for n in names) + f"  {'f [Hz]':>12} {'label':<12} {'MAC prev':>8}  crossing")
    for r in rows:
        values = "  ".join(f"{r['params'][n]:>14.6g}" for n in names)
        print(f"{values}  {r['frequency_hz']:>12.1f} {r['label']:<12} {r['mac_previous']:>8.3f}  "
              f"{'YES: ' + r['tracked_label'] if r['crossing'] else ''}")
    return 0
