"""How long meshing and the whole `modalfe report` take on this machine (issues 2 and 3).

Prints medians of several runs, each in a fresh process with an empty mesh cache (cold) and then
with the cache filled (warm), and the meshing time of every scene at its default resolution.

    python studies/benchmark_report.py [--runs 3]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def time_meshing(runs: int) -> dict[str, tuple[float, int]]:
    """Median seconds to mesh each built-in scene without the cache, and its element count."""
    from modalfe.models.mesh import build_mesh, element_sizes
    from modalfe.scene import load_scene
    from modalfe.scene.builtin import BUILTIN

    out = {}
    for name in BUILTIN:
        scene = load_scene(name)
        samples = []
        for _ in range(runs):
            start = time.perf_counter()
            dm = build_mesh(scene.assembly(), size=element_sizes(scene), min_layers=scene.mesh.min_layers,
                            use_cache=False)
            samples.append(time.perf_counter() - start)
        out[name] = (statistics.median(samples), dm.nelements)
    return out


def time_report(runs: int) -> dict[str, list[float]]:
    """Wall time of `modalfe report --json` in fresh processes, cold and warm mesh cache."""
    out = {"cold": [], "warm": []}
    per_scene = []
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, MODALFE_CACHE=cache)
            for kind in ("cold", "warm"):
                start = time.perf_counter()
                done = subprocess.run([sys.executable, "-m", "modalfe.cli.main", "report", "--json"], env=env,
                                      capture_output=True, text=True, check=True)
                out[kind].append(time.perf_counter() - start)
                if kind == "warm":
                    per_scene.append({r["scene"]: r["seconds"] for r in json.loads(done.stdout)})
    out["per_scene_warm"] = {k: statistics.median(d[k] for d in per_scene) for k in per_scene[0]}
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    print(f"meshing at default resolution (median of {args.runs}, no cache):")
    for name, (seconds, n) in time_meshing(args.runs).items():
        print(f"  {name:<16} {seconds:6.2f} s  {n:6d} elements")
    result = time_report(args.runs)
    print(f"modalfe report, all devices (median of {args.runs} fresh processes):")
    for kind in ("cold", "warm"):
        runs = [round(x, 1) for x in result[kind]]
        print(f"  {kind} mesh cache {statistics.median(result[kind]):6.1f} s   runs {runs}")
    for name, seconds in result["per_scene_warm"].items():
        print(f"    {name:<16} {seconds:6.1f} s")


if __name__ == "__main__":
    main()
