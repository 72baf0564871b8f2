"""Sweep speed on this machine: 2 dask workers against 1, and cost against the number of points.

    python studies/benchmark_sweep.py [--points 4 8]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from modalfe.design.sweep import sweep


def run(points: int, workers: int) -> float:
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        sweep("ciliary_beam", {"x0": list(np.linspace(0.05, 0.08, points))}, out=Path(folder) / "t.csv",
              selector="bending-z 6", near=24.2e3, workers=workers, progress=False)
        return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, nargs="+", default=[4, 8, 16])
    args = parser.parse_args()
    run(2, 1)  # warm the mesh cache and imports
    print(f"{'points':>6} {'1 worker [s]':>13} {'2 workers [s]':>14} {'speed-up':>9}")
    for n in args.points:
        one, two = run(n, 1), run(n, 2)
        print(f"{n:>6} {one:>13.1f} {two:>14.1f} {one / two:>9.2f}")


if __name__ == "__main__":
    main()
