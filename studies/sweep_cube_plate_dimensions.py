"""Which Cu-Be plate length, and which thickness, put the (0,6) mode on the measured 40.7 kHz (issue 9).

Two one-parameter sweeps on dask (resumable tables under studies/out/), each interpolated for
40.7 kHz; the working mode is tracked by MAC along each sweep.

    python studies/sweep_cube_plate_dimensions.py [--quick] [--workers 2]
"""

from __future__ import annotations

import argparse

import numpy as np

from modalfe.design.sweep import sweep

TARGET = 40.7e3  # Hz, seed 001 measured


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse meshes, 4 points per sweep")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    base = {"mesh.elements_per_wavelength": 4.0} if args.quick else {}
    n = 4 if args.quick else 7
    for name, values in (("length", np.linspace(62e-3, 66e-3, n)), ("thickness", np.linspace(2.8e-3, 3.3e-3, n))):
        suffix = "_quick" if args.quick else ""
        rows = sweep("cube_plate", {name: list(values)}, out=f"studies/out/sweep_cube_{name}{suffix}.csv",
                     selector="(0,6)", near=TARGET, base=base, workers=args.workers, progress=True)
        x = np.array([r["params"][name] for r in rows])
        f = np.array([r["tracked_frequency_hz"] for r in rows])
        print(f"{name:>9} [mm]   f (0,6) [Hz]   MAC prev  crossing")
        for xi, r in zip(x, rows):
            print(f"{1e3 * xi:>14.3f}   {r['tracked_frequency_hz']:>12.1f}   {r['mac_previous']:>8.3f}  "
                  f"{r['crossing']}")
        order = np.argsort(f)
        if f.min() <= TARGET <= f.max():
            print(f"  (0,6) on {TARGET:.0f} Hz at {name} = {1e3 * np.interp(TARGET, f[order], x[order]):.3f} mm")
        else:
            print(f"  40.7 kHz lies outside {f.min():.0f}-{f.max():.0f} Hz for this {name} range")


if __name__ == "__main__":
    main()
