"""``modalfe calibrate``: the scene parameters that best explain measured frequencies and wavelengths (3-D solid),
with their posterior uncertainty, correlation and what the data cannot identify."""

from __future__ import annotations

import functools
import json
import math
import sys

from modalfe.cli.options import (
    parse_bound,
    parse_names,
    parse_overrides,
    positive_int,
    scene_options,
    solve_keywords,
    solve_options,
)
from modalfe.cli.page import add_html_option, scene_page
from modalfe.errors import ModalfeError, SceneError


def register(sub) -> None:
    p = sub.add_parser("calibrate", help="fit parameters to measured frequencies and wavelengths (3-D solid)")
    p.add_argument("scene", help="built-in scene name or path to a .toml scene file")
    p.add_argument("--measured", required=True, metavar="FILE.toml",
                   help='[[mode]] tables: label = "(0,6)", frequency, sigma [Hz], optional wavelength, '
                        "wavelength_sigma [m]")
    p.add_argument("--vary", required=True, metavar="P1,P2,...",
                   help="parameters fitted (as for modalfe sensitivity); a * in the group ties groups to one value "
                        "(springs.foot_*.z)")
    p.add_argument("--bounds", action="append", metavar="NAME=LOW:HIGH", help="limits of a parameter (repeatable)")
    p.add_argument("--max-iterations", type=positive_int, default=20, help="most solves per start (default 20)")
    p.add_argument("--starts", type=positive_int, default=1,
                   help="independent starts, Latin hypercube in ln p within --bounds (every varied parameter "
                        "needs them); the best (least chi2) is reported")
    p.add_argument("--scheduler", help="dask scheduler address for --starts (default: a LocalCluster); 'inline' "
                   "runs the starts one after another in this process")
    p.add_argument("--workers", type=positive_int, help="LocalCluster worker processes (default: one per start, at "
                   "most the CPU count)")
    solve_options(p)
    add_html_option(p)
    scene_options(p, _calibrate)


def _calibrate(args) -> int:
    from modalfe.design.calibration import calibrate
    from modalfe.design.measurements import read_measurements
    from modalfe.scene import load_scene

    names = parse_names(args.vary)
    bounds = dict(parse_bound(text) for text in args.bounds or [])
    measured = read_measurements(args.measured)
    scene = load_scene(args.scene, **parse_overrides(args.set))
    waves = sum(not math.isnan(m.wavelength) for m in measured)
    if not args.json:
        print(f"{scene.name}: calibrating {', '.join(names)} to {len(measured)} measured frequencies and {waves} "
              f"wavelengths (3-D solid, Levenberg-Marquardt in ln p)", flush=True)
    if args.starts == 1:
        result = calibrate(scene, measured, names, bounds=bounds, max_iterations=args.max_iterations,
                           progress=None if args.json else _iterate_line, resolution=solve_keywords(args))
        starts = [result]
    else:
        result, starts = _multistart(args, scene, measured, names, bounds)
    scene_page(args, result.scene)  # the calibrated scene's
    if args.json:
        print(json.dumps(_document(scene, result, starts), indent=2))
    else:
        _print(result)
    if not result.converged:
        print(f"modalfe: calibrate: not converged: {result.reason}", file=sys.stderr)
        return 1
    return 0


def _multistart(args, scene, measured, names, bounds):
    """``--starts N`` Latin-hypercube starts on dask (``modalfe.design.multistart.run_starts``): the best by chi2,
    and every start's result (an exception for a start that failed)."""
    from modalfe.design.multistart import latin_hypercube, run_starts

    missing = [name for name in names if name not in bounds]
    if missing:
        raise SceneError(f"--starts: needs --bounds for every varied parameter; {missing[0]} has none")
    starts = latin_hypercube({name: bounds[name] for name in names}, args.starts)
    task = functools.partial(_from_start, scene, measured, names, bounds, args.max_iterations, solve_keywords(args))

    def finished(i, outcome) -> None:
        if not args.json:
            text = (f"failed: {outcome}" if isinstance(outcome, Exception) else
                    f"chi2 {outcome.chi2:.4g} after {outcome.solves} solves ({outcome.reason})")
            print(f"start {i + 1}: " + ", ".join(f"{n} = {v:.4g}" for n, v in starts[i].items()) + f" -> {text}",
                  flush=True)

    results = run_starts(task, starts, scheduler=args.scheduler, workers=args.workers, progress=finished)
    done = [r for r in results if not isinstance(r, Exception)]
    if not done:
        first = results[0]
        raise first if isinstance(first, ModalfeError) else ModalfeError(f"calibrate: every start failed ({first})")
    return min(done, key=lambda r: r.chi2), results


def _from_start(scene, measured, names, bounds, max_iterations, resolution, start):
    """One start of ``--starts`` (a module-level function, so dask can send it to a worker)."""
    from modalfe.design.calibration import calibrate

    return calibrate(scene, measured, names, bounds=bounds, max_iterations=max_iterations, start=start,
                     resolution=resolution)


def _iterate_line(k: int, it) -> None:
    values = ", ".join(f"{n} = {v:.6g}" for n, v in it.values.items())
    verdict = "accepted" if it.accepted else "rejected"
    print(f"{k:>3}  chi2 {it.chi2:12.5g}  {verdict:<8}  {values}  (radius {it.radius:.3g}; {it.seconds:.1f} s)",
          flush=True)


def _print(result) -> None:
    seconds = sum(it.seconds for it in result.iterates)
    verdict = "converged" if result.converged else "NOT converged"
    print(f"{verdict} after {result.solves} solves, {seconds:.1f} s ({result.reason}); chi2 {result.chi2:.4g}, "
          f"{result.dof} residual dof; covariance from the {result.covariance_basis}")
    width = max(len(n) for n in result.parameters)
    print(f"\n{'parameter':<{width}} {'estimate':>13} {'sd':>11} {'sd/|p|':>8}")
    for name, value, sd in zip(result.parameters, result.values, result.sd):
        relative = f"{sd / abs(value):.2%}" if sd <= abs(value) else "> 100 %"  # not identified: said below
        print(f"{name:<{width}} {value:>13.6g} {sd:>11.3g} {relative:>8}")
    print(f"\n{'measured':<22} {'value':>12} {'sigma':>10} {'model':>12} {'(model-meas)/sigma':>19}")
    for q, d, s, y, r in zip(result.quantities, result.measured, result.sigma, result.predicted, result.residuals):
        print(f"{q:<22} {d:>12.6g} {s:>10.3g} {y:>12.6g} {r:>19.3f}")
    if len(result.parameters) > 1:
        print("\ncorrelation (of ln p)")
        for name, row in zip(result.parameters, result.correlation):
            print(f"{name:<{width}} " + " ".join(f"{c:+7.3f}" for c in row))
    print("\nsingular values of the weighted Jacobian: " + ", ".join(f"{s:.3g}" for s in result.singular_values))
    print("\n".join(result.unidentified) if result.unidentified else "every parameter is identified by the data")
    print("parameters: " + " ".join(_reproduce(result)))


def _reproduce(result) -> list[str]:
    """The ``--set`` options that give the fitted scene: every member of a tie (``springs.foot_*.z``: each foot's
    spring, whole, as ``--set`` takes it) at full precision (``repr``); box parts' sizes are in the scene written by
    ``tune --out``, not here."""
    from modalfe.response.sensitivity import parameter_value, tied_members

    scene, sets = result.scene, {}
    for name in result.parameters:
        for member in tied_members(scene, name):
            head, group = member.split(".")[:2]
            if head == "springs":
                sets[f"springs.{group}"] = "[" + ", ".join(repr(float(k)) for k in scene.springs[group]) + "]"
            elif head != "parts":
                sets[member] = repr(parameter_value(scene, member))
    return [f"--set '{k}={v}'" if v.startswith("[") else f"--set {k}={v}" for k, v in sets.items()]


def _document(scene, result, starts) -> dict:
    def number(x: float) -> float | None:
        return float(x) if math.isfinite(x) else None

    return {
        "scene": scene.name, "converged": result.converged, "reason": result.reason, "solves": result.solves,
        "seconds": sum(it.seconds for it in result.iterates), "chi2": result.chi2, "dof": result.dof,
        "covariance_scale": result.scale, "covariance_basis": result.covariance_basis,
        "parameters": {n: {"estimate": float(v), "sd": number(s)}
                       for n, v, s in zip(result.parameters, result.values, result.sd)},
        "correlation": [[number(c) for c in row] for row in result.correlation],
        "measurements": [{"quantity": q, "measured": float(d), "sigma": float(s), "predicted": float(y),
                          "normalised_residual": float(r)}
                         for q, d, s, y, r in zip(result.quantities, result.measured, result.sigma, result.predicted,
                                                  result.residuals)],
        "singular_values": [float(s) for s in result.singular_values],
        "directions": [[float(c) for c in row] for row in result.directions],
        "unidentified": list(result.unidentified),
        "iterates": [{"values": it.values, "chi2": it.chi2, "accepted": it.accepted, "radius": it.radius,
                      "seconds": it.seconds} for it in result.iterates],
        "starts": [{"error": str(r)} if isinstance(r, Exception) else
                   {"chi2": r.chi2, "solves": r.solves, "converged": r.converged,
                    "values": dict(zip(r.parameters, r.values.tolist()))} for r in starts],
    }
