"""``modalfe tune``: change scene parameters until a mode sits on a target frequency (3-D solid)."""

from __future__ import annotations

import json
import math
import sys

from modalfe.cli.options import parse_overrides, positive_int
from modalfe.errors import SceneError


def register(sub) -> None:
    p = sub.add_parser("tune", help="change parameters until a mode reaches a target frequency (3-D solid)")
    p.add_argument("scene", help="built-in scene name or path to a .toml scene file")
    p.add_argument("--target", required=True, metavar="LABEL=HZ", help='the mode and its frequency, "(0,6)=40.7e3"')
    p.add_argument("--vary", required=True, metavar="P1,P2,...",
                   help="parameters changed (as for modalfe sensitivity): builder parameters, materials.NAME.KEY, "
                        "springs.GROUP, masses.GROUP, parts.NAME.origin|size.x|y|z")
    p.add_argument("--bounds", action="append", metavar="NAME=LOW:HIGH", help="limits of a parameter (repeatable)")
    p.add_argument("--tol", type=float, default=1e-3, help="relative distance to the target (default 1e-3)")
    p.add_argument("--max-iterations", type=positive_int, default=12, help="most solves (default 12)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter first")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_tune)


def _tune(args) -> int:
    from modalfe.response.sensitivity import check_parameters
    from modalfe.response.tuning import tune_frequency
    from modalfe.scene import load_scene

    label, target = _target(args.target)
    names = [name.strip() for name in args.vary.split(",") if name.strip()]
    bounds = dict(_bound(text) for text in args.bounds or [])
    scene = load_scene(args.scene, **parse_overrides(args.set))
    check_parameters(scene, names)  # before the header and any solve

    def progress(k, it) -> None:
        if not args.json:
            values = ", ".join(f"{n} = {v:.6g}" for n, v in it.values.items())
            slopes = ", ".join(f"{s:+.3f}" for s in it.relative_sensitivity.values())
            print(f"{k:>3}  {it.frequency:12.2f} Hz  {100 * (it.frequency / target - 1):+8.4f} %  {values}  "
                  f"(d ln f / d ln p {slopes}; {it.seconds:.1f} s)", flush=True)

    if not args.json:
        print(f"{scene.name}: tuning {label} to {target:.6g} Hz within {args.tol:.2%} by {', '.join(names)}")
    result = tune_frequency(scene, label, target, names, tol=args.tol, bounds=bounds,
                            max_iterations=args.max_iterations, progress=progress)
    final = result.final
    seconds = sum(it.seconds for it in result.iterates)
    if args.json:
        print(json.dumps({"scene": scene.name, "label": label, "target_hz": target, "tol": args.tol,
                          "converged": result.converged, "reason": result.reason, "solves": len(result.iterates),
                          "seconds": seconds, "parameters": final.values, "frequency_hz": final.frequency,
                          "iterates": [{"values": it.values, "frequency_hz": it.frequency,
                                        "dlnf_dlnp": it.relative_sensitivity, "seconds": it.seconds}
                                       for it in result.iterates]}, indent=2))
    else:
        verdict = "reached" if result.converged else "NOT reached"
        print(f"{verdict}: {label} at {final.frequency:.2f} Hz ({100 * (final.frequency / target - 1):+.4f} %) "
              f"after {len(result.iterates)} solves, {seconds:.1f} s ({result.reason})")
        print("parameters: " + " ".join(f"--set {n}={v:.9g}" for n, v in final.values.items()
                                         if not n.startswith("parts.")))
    if not result.converged:
        print(f"modalfe: tune: {label} not within {args.tol:.2%} of {target:.6g} Hz: {result.reason}", file=sys.stderr)
        return 1
    return 0


def _target(text: str) -> tuple[str, float]:
    label, sep, value = text.rpartition("=")
    try:
        hz = float(value)
    except ValueError:
        hz = math.nan
    if not sep or not label.strip() or not (math.isfinite(hz) and hz > 0):
        raise SceneError(f"--target: expected LABEL=HZ with a positive frequency, e.g. \"(0,6)=40.7e3\", got '{text}'")
    return label.strip(), hz


def _bound(text: str) -> tuple[str, tuple[float, float]]:
    name, sep, span = text.partition("=")
    low, colon, high = span.partition(":")
    try:
        lo, hi = float(low), float(high)
    except ValueError:
        lo = hi = math.nan
    if not sep or not colon or not name.strip() or not (lo < hi):
        raise SceneError(f"--bounds: expected NAME=LOW:HIGH with LOW < HIGH, got '{text}'")
    return name.strip(), (lo, hi)
