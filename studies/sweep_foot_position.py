"""Foot position along the plate vs friction reduction per volt (issue 9).

All four feet move together by ``dx`` from the antinodes x = 20.35 / 43.65 mm (keeping the layout
symmetric); each point reduces the (0,6) mode at the feet and runs the foot contact simulator at
10 V, 3 N, 1 cm/s on steel (seed 001's conditions).

    python studies/sweep_foot_position.py [--quick] [--workers 2]
"""

from __future__ import annotations

import argparse

import numpy as np

from modalfe.design.sweep import friction_extra, sweep


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    base = {"mesh.elements_per_wavelength": 4.0} if args.quick else {}
    rows = []
    for dx in np.linspace(-4e-3, 4e-3, 3 if args.quick else 9):
        feet = [(20.35e-3 - dx, 6e-3), (43.65e-3 + dx, 6e-3), (20.35e-3 - dx, 32e-3), (43.65e-3 + dx, 32e-3)]
        rows += sweep("cube_plate", {"feet": [feet]}, out=f"studies/out/sweep_feet{'_quick' if args.quick else ''}.csv",
                      selector="(0,6)", near=40.7e3, base=base, workers=args.workers, extra=friction_extra,
                      progress=False)
    print("foot x [mm]     f (0,6) [Hz]   amplitude [nm/V]   friction reduction at 10 V")
    for r in rows:
        x = r["params"]["feet"][0][0]
        print(f"{1e3 * x:>11.2f}   {r['frequency_hz']:>14.1f}   {1e9 * r['extra']['amplitude_per_volt_m']:>16.1f}   "
              f"{100 * r['extra']['friction_reduction']:>10.1f} %")


if __name__ == "__main__":
    main()
