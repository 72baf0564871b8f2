"""Ceramic pitch along the plate vs the (0,6) mode's k_eff (issue 9).

    python studies/sweep_ceramic_position.py [--quick] [--workers 2]
"""

from __future__ import annotations

import argparse

import numpy as np

from modalfe.design.sweep import coupling_extra, sweep


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    base = {"mesh.elements_per_wavelength": 4.0} if args.quick else {}
    pitches = np.linspace(12.1e-3, 12.6e-3, 3 if args.quick else 6)  # 12 mm ceramics, <= 64 mm in all
    rows = sweep("cube_plate", {"ceramic_pitch": list(pitches)},
                 out=f"studies/out/sweep_ceramic_pitch{'_quick' if args.quick else ''}.csv",
                 selector="(0,6)", near=40.7e3, base=base, workers=args.workers, extra=coupling_extra)
    print("pitch [mm]   f (0,6) [Hz]   k_eff   crossing")
    for r in rows:
        print(f"{1e3 * r['params']['ceramic_pitch']:>10.2f}   {r['frequency_hz']:>12.1f}   "
              f"{r['extra']['k_eff']:.4f}   {r['crossing']}")


if __name__ == "__main__":
    main()
