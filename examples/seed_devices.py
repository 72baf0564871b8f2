"""The four seed devices, built in (no scene file): the Cu-Be plate with PZT ceramics and feet (seeds 000, 001),
the 1.9 mm glass plate (seed 004), the honeycomb floor tile (seed 002) and the segmented piezo ciliary beam
(seed 003). For each device named, its working modes beside the seed's targets: the computed frequency with its
stated error, the fidelity that answered, fa and k_eff where the device is driven by piezo ceramics, and the
deviation from each measured or published value (the rows of `modalfe report`).

    python examples/seed_devices.py [--quick] [cube_plate glass_plate honeycomb_tile ciliary_beam]

--quick: a 5 % tolerance instead of the default 0.5 % (the reduced plate or beam model may then answer).
"""

import argparse

from modalfe import load_scene
from modalfe.report.report import device_report, format_rows
from modalfe.solve.api import DEFAULT_TOL

SEEDS = ("cube_plate", "glass_plate", "honeycomb_tile", "ciliary_beam")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("devices", nargs="*", metavar="DEVICE",
                        help=f"one or more of {', '.join(SEEDS)} (default: all)")
    parser.add_argument("--quick", action="store_true", help="a coarse tolerance, for the tests")
    args = parser.parse_args()
    unknown = sorted(set(args.devices) - set(SEEDS))
    if unknown:
        parser.error(f"DEVICE: {', '.join(unknown)} not among {', '.join(SEEDS)}")
    rows = [row for name in args.devices or SEEDS
            for row in device_report(load_scene(name), tol=0.05 if args.quick else DEFAULT_TOL)]
    print(format_rows(rows))


if __name__ == "__main__":
    main()
