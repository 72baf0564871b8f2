"""Run time against accuracy for every device at each fidelity that applies (issue 6, item 3).

For each device's working mode and each fidelity (solid always; beam or plate where the scene's kind
allows, ``modalfe.solve.fidelity.reduced_fidelities``) a refinement sweep over size factors records DOFs, wall
time per stage (mesh, assembly, factorization, eigen solve; ``other`` is the rest of the solve, mostly
labelling the modes), peak memory and the relative error of the working mode against a converged 3-D
reference.

How it is measured:
- every point runs in a fresh Python process with an empty mesh cache (MODALFE_CACHE in a temporary
  folder), so meshing is timed cold; ``--repeats`` processes per point, medians quoted;
- peak memory: ``resource.getrusage(RUSAGE_SELF).ru_maxrss`` read by that process at its end (the whole
  interpreter and its libraries), beside the same figure read after the imports, before the solve;
- solid levels refine uniformly: layers through the thickness are round(min_layers / size factor), at least 1;
- reference: Richardson extrapolation of the two finest solid levels at the assumed order
  ``modalfe.solve.estimates.CONVERGENCE_ORDER``, refinement ratio from the main part's element counts (as
  ``modalfe.solve.estimates.refinement_ratio``); its uncertainty is how far it moves over ``OBSERVED_ORDERS``;
- exponents: least-squares slope of log(stage seconds) against log(DOFs) over each sweep.

    python studies/benchmark_fidelity.py [--quick] [--repeats 3] [--devices cube_plate ...] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DEVICES = ("cube_plate", "glass_plate", "honeycomb_tile", "ciliary_beam")
# the tile's first working mode (heave, 45 Hz) is a rigid-body mode on the rubber mounts, set by the
# springs rather than the mesh: its first plate mode is the one a refinement sweep says something about
WORKING = {"honeycomb_tile": "(1,1)"}
STAGES = ("mesh", "assembly", "factorization", "eigensolve", "other")
FITTED = ("assembly", "factorization", "eigensolve")
MEDIANS = ("total", "peak_rss_mb", "rss_imports_mb")  # per-point figures quoted as medians over repeats
SIZE_FACTORS = {"solid": (2.25, 1.5, 1.0, 0.75), "beam": (2.0, 1.0, 0.5, 0.25, 0.125), "plate": (2.0, 1.0, 0.5, 0.25)}
QUICK_DEVICES = ("ciliary_beam",)
QUICK_FACTORS = {"solid": (2.25, 1.5), "beam": (2.0, 1.0, 0.5), "plate": (2.0, 1.0)}


def working_mode(scene) -> tuple[str, float]:
    """(selector, near [Hz]) of the working mode benchmarked for ``scene``."""
    wanted = WORKING.get(scene.name, scene.working_modes[0].selector)
    wm = next(w for w in scene.working_modes if w.selector == wanted)
    return wm.selector, wm.near


def level_scene(device: str, size_factor: float):
    """The built-in scene with layers through the thickness scaled like the element sizes."""
    from modalfe.scene import load_scene

    layers = load_scene(device).mesh.min_layers
    return load_scene(device, **{"mesh.min_layers": max(1, round(layers / size_factor))})


def measure(device: str, fidelity: str, size_factor: float, solver: str) -> dict:
    """One sweep point solved in this process, with a fresh mesh cache: DOFs, seconds per stage, the
    working mode's frequency [Hz], main-part element count (solid) and RSS peaks [MB]."""
    import resource

    from modalfe.results.modes import select
    from modalfe.solve.levels import solve_level

    with tempfile.TemporaryDirectory(prefix="modalfe-bench-") as cache:
        os.environ["MODALFE_CACHE"] = cache
        scene = level_scene(device, size_factor)
        rss_imports = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        start = time.perf_counter()
        modes = solve_level(scene, scene.analysis, fidelity=fidelity, size_factor=size_factor, solver=solver)
        total = time.perf_counter() - start
    selector, near = working_mode(scene)
    seconds = {k: float(modes.timings.get(k, 0.0)) for k in STAGES[:-1]}
    seconds["other"] = total - sum(seconds.values())
    main = scene.assembly().main_part.name
    picked = select(modes, selector, near)
    return {"dofs": modes.dofs, "seconds": seconds, "total": total, "solver": modes.timings["solver"],
            "frequency": picked.frequency, "mode": picked.label, "spectrum": [[m.label, m.frequency] for m in modes],
            "main_elements": len(modes.model.mesh.parts[main]) if fidelity == "solid" else 0,
            "rss_imports_mb": rss_imports, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def measure_in_child(device: str, fidelity: str, size_factor: float, solver: str) -> dict:
    """``measure`` in a fresh interpreter; RuntimeError with the child's last error line if it fails."""
    spec = json.dumps([device, fidelity, size_factor, solver])
    done = subprocess.run([sys.executable, __file__, "--point", spec], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or ["no output"]
        raise RuntimeError(lines[-1])
    return json.loads(done.stdout.strip().splitlines()[-1])


@dataclass(frozen=True)
class Point:
    """Medians over repeats of one (device, fidelity, size factor); seconds per stage, memory in MB."""

    device: str
    fidelity: str
    size_factor: float
    dofs: int
    seconds: dict
    total: float
    peak_rss_mb: float
    rss_imports_mb: float
    frequency: float
    main_elements: int
    mode: str  # label of the mode followed, e.g. (0,6) for the selector (0,n)
    solver: str
    repeats: int
    error: float = float("nan")  # relative, against the 3-D reference


def tracked(previous: Point | None, run: dict) -> tuple[str, float]:
    """(label, frequency [Hz]) of the working mode at a finer level: the mode of the same label nearest the
    coarser level's frequency, within 10 % (the sweep keeps labels and frequencies only, no shapes), else the
    selector's pick (the coarsest level, or no such mode: said)."""
    if previous is None:
        return run["mode"], run["frequency"]
    same = [(label, f) for label, f in run["spectrum"] if label == previous.mode
            and abs(f - previous.frequency) <= 0.1 * previous.frequency]
    if not same:
        print(f"  no partner of {previous.mode} at {previous.frequency:.1f} Hz: the selector picked "
              f"{run['mode']} at {run['frequency']:.1f} Hz")
        return run["mode"], run["frequency"]
    return min(same, key=lambda s: abs(s[1] - previous.frequency))


def sweep(device: str, fidelity: str, factors, repeats: int, solver: str) -> list[Point]:
    """The refinement sweep of one device at one fidelity, coarse to fine, the working mode followed
    from level to level (``tracked``); failed points are skipped with a printed reason."""
    points = []
    for factor in sorted(factors, reverse=True):
        try:
            runs = [measure_in_child(device, fidelity, factor, solver) for _ in range(repeats)]
        except RuntimeError as exc:
            print(f"  {device} {fidelity} size factor {factor:g}: failed: {exc}")
            continue
        label, frequency = tracked(points[-1] if points else None, runs[0])
        points.append(Point(device, fidelity, factor, runs[0]["dofs"],
                            {s: statistics.median(r["seconds"][s] for r in runs) for s in STAGES},
                            *(statistics.median(r[k] for r in runs) for k in MEDIANS), frequency,
                            runs[0]["main_elements"], label, runs[0]["solver"], repeats))
        print(f"  {device:<15} {fidelity:<6} x{factor:<6g} {points[-1].dofs:>7d} DOFs {points[-1].total:7.2f} s")
    return points


def reference(solid: list[Point]) -> tuple[float, float]:
    """(f_ref [Hz], relative uncertainty): Richardson from the two finest solid levels at
    CONVERGENCE_ORDER, uncertainty = largest move of f_ref over OBSERVED_ORDERS."""
    from modalfe.solve.estimates import CONVERGENCE_ORDER, OBSERVED_ORDERS

    coarse, fine = sorted(solid, key=lambda p: p.dofs)[-2:]
    ratio = (fine.main_elements / coarse.main_elements) ** (1 / 3)

    def extrapolated(order: float) -> float:
        return fine.frequency + (fine.frequency - coarse.frequency) / (ratio**order - 1)

    f_ref = extrapolated(CONVERGENCE_ORDER)
    return f_ref, max(abs(extrapolated(q) / f_ref - 1) for q in OBSERVED_ORDERS)


def power_law_exponent(dofs, seconds) -> float:
    """Least-squares slope of log(seconds) on log(dofs); NaN with fewer than two usable points."""
    x, y = np.asarray(dofs, float), np.asarray(seconds, float)
    keep = (x > 0) & (y > 0)
    if keep.sum() < 2 or np.ptp(np.log(x[keep])) == 0:
        return float("nan")
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def at_default(points: list[Point]) -> Point:
    """The point nearest size factor 1 (the default resolution)."""
    return min(points, key=lambda p: abs(math.log(p.size_factor)))


def write_csv(points: list[Point], path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(["device", "fidelity", "size_factor", "dofs", *(f"{s}_s" for s in STAGES), "total_s",
                      "peak_rss_mb", "rss_after_imports_mb", "mode", "frequency_hz", "relative_error", "solver",
                      "repeats"])
        for p in points:
            out.writerow([p.device, p.fidelity, p.size_factor, p.dofs, *(f"{p.seconds[s]:.4g}" for s in STAGES),
                          f"{p.total:.4g}", f"{p.peak_rss_mb:.0f}", f"{p.rss_imports_mb:.0f}", p.mode,
                          f"{p.frequency:.3f}", f"{p.error:.3e}", p.solver, p.repeats])


def plot(curves: dict[str, list[Point]], path: Path) -> None:
    """Total time vs relative error, log-log, one line per device and fidelity."""
    from modalfe.plot.figures import plot_time_vs_error

    curves = {k: [p for p in v if p.error > 0] for k, v in curves.items()}
    curves = {k: v for k, v in curves.items() if v}
    fig = plot_time_vs_error({k: np.array([p.total for p in v]) for k, v in curves.items()},
                             {k: np.array([p.error for p in v]) for k, v in curves.items()})
    fig.axes[0].legend(fontsize="small")  # eight curves: keep the legend off most of them
    fig.savefig(path, dpi=110)


@dataclass(frozen=True)
class Benchmark:
    """Everything measured: points, exponents per (device, fidelity) and stage, references [Hz]."""

    points: list[Point]
    exponents: dict[tuple[str, str], dict[str, float]]
    references: dict[str, tuple[float, float]]
    dominant: dict[tuple[str, str], str]


def run(devices, factors: dict, repeats: int, solver: str, out: Path) -> Benchmark:
    """Sweep every device and fidelity, write the CSV and the plot into ``out``."""
    from modalfe.scene import load_scene
    from modalfe.solve.fidelity import reduced_fidelities

    curves, references = {}, {}
    for device in devices:
        fidelities = ["solid", *reduced_fidelities(load_scene(device))]
        for fidelity in fidelities:
            curves[(device, fidelity)] = sweep(device, fidelity, factors[fidelity], repeats, solver)
        if len(curves[(device, "solid")]) < 2:
            print(f"{device}: fewer than two solid levels, no reference")
            continue
        references[device] = reference(curves[(device, "solid")])
        f_ref = references[device][0]
        for fidelity in fidelities:
            curves[(device, fidelity)] = [Point(**{**p.__dict__, "error": abs(p.frequency / f_ref - 1)})
                                          for p in curves[(device, fidelity)]]
    curves = {k: v for k, v in curves.items() if v}
    exponents = {k: {s: power_law_exponent([p.dofs for p in v], [p.seconds[s] for p in v]) for s in FITTED}
                 for k, v in curves.items()}
    dominant = {k: max(FITTED, key=lambda s: at_default(v).seconds[s]) for k, v in curves.items()}
    points = [p for v in curves.values() for p in v]
    out.mkdir(parents=True, exist_ok=True)
    write_csv(points, out / "benchmark_fidelity.csv")
    plot({f"{d} {f}": v for (d, f), v in curves.items()}, out / "benchmark_fidelity.png")
    return Benchmark(points, exponents, references, dominant)


def format_benchmark(result: Benchmark) -> str:
    """The printed table: one line per point, then references, exponents and the dominating stage."""
    lines = [f"{'device':<15} {'fidelity':<8} {'size':>5} {'DOFs':>7} {'mesh':>6} {'assem':>6} {'fact':>6} "
             f"{'eig':>6} {'other':>6} {'total':>7} {'peak MB':>8} {'mode':>12} {'f [Hz]':>10} {'rel err':>9}"]
    for p in result.points:
        s = p.seconds
        lines.append(f"{p.device:<15} {p.fidelity:<8} {p.size_factor:>5g} {p.dofs:>7d} {s['mesh']:>6.2f} "
                     f"{s['assembly']:>6.2f} {s['factorization']:>6.2f} {s['eigensolve']:>6.2f} {s['other']:>6.2f} "
                     f"{p.total:>7.2f} {p.peak_rss_mb:>8.0f} {p.mode:>12} {p.frequency:>10.1f} {p.error:>9.2e}")
    lines.append("reference (Richardson, two finest solid levels, order CONVERGENCE_ORDER):")
    for device, (f_ref, spread) in result.references.items():
        lines.append(f"  {device:<15} {f_ref:.1f} Hz, +-{spread:.1e} relative over the observed orders")
    lines.append("power-law exponent of stage time vs DOFs (least squares, log-log), dominant stage at size factor ~1:")
    for (device, fidelity), fit in result.exponents.items():
        default = at_default([p for p in result.points if (p.device, p.fidelity) == (device, fidelity)])
        text = "  ".join(f"{s} {fit[s]:.2f}" for s in FITTED)
        lines.append(f"  {device:<15} {fidelity:<6} {text}   dominant at x{default.size_factor:g}: "
                     f"{result.dominant[(device, fidelity)]}")
    return "\n".join(lines)


def positive_factor(text: str) -> float:
    """argparse type: a positive finite size factor."""
    value = float(text)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"size factors must be positive, got {text}")
    return value


def main(argv: list[str] | None = None) -> Benchmark | None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=f"{', '.join(QUICK_DEVICES)} only, coarse, 1 repeat")
    parser.add_argument("--repeats", type=int, help="fresh processes per point (default 3, 1 with --quick)")
    parser.add_argument("--devices", nargs="+", choices=DEVICES, help="default: all four")
    parser.add_argument("--solid-factors", nargs="+", type=positive_factor, help="solid size factors")
    parser.add_argument("--solver", default="auto", choices=("auto", "pardiso", "superlu"))
    parser.add_argument("--out", default="studies/out/benchmark_fidelity", help="folder for the CSV and the plot")
    parser.add_argument("--point", help=argparse.SUPPRESS)  # internal: one point, JSON on stdout
    args = parser.parse_args(argv)
    if args.point:
        print(json.dumps(measure(*json.loads(args.point))))
        return None
    repeats = args.repeats if args.repeats is not None else 1 if args.quick else 3
    if repeats < 1:
        parser.error(f"--repeats must be at least 1, got {repeats}")
    factors = dict(QUICK_FACTORS if args.quick else SIZE_FACTORS)
    if args.solid_factors:
        factors["solid"] = tuple(args.solid_factors)
    if len(factors["solid"]) < 2:
        parser.error("--solid-factors: give at least two, the reference needs the two finest")
    devices = args.devices or (QUICK_DEVICES if args.quick else DEVICES)
    print(f"fidelity benchmark: {', '.join(devices)}; medians of {repeats} fresh process(es) per point, "
          "cold mesh cache")
    result = run(devices, factors, repeats, args.solver, Path(args.out))
    print(format_benchmark(result))
    print(f"wrote {Path(args.out) / 'benchmark_fidelity.csv'} and {Path(args.out) / 'benchmark_fidelity.png'}")
    return result


if __name__ == "__main__":
    main()
