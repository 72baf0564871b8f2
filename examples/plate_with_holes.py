"""A CAD part (plate_with_holes.toml, geometry from the gmsh script plate_holes_disc.geo): a Cu-Be plate with two
round holes and a bonded PZT-5A disc, clamped at one end. Prints its first modes with their stated errors, then the
first bending mode's response to the disc's drive voltage: the tip's amplitude per volt at resonance and k_eff.

    python examples/plate_with_holes.py [--quick]

Meshed with curved quadratic tetrahedra. --quick: elements of 4 mm, one layer through the plate and no error
estimate (a few seconds, for the tests); without it the mesh is refined to the default 0.5 % (a few minutes).
"""

import argparse
import math
from pathlib import Path

from modalfe import forced_response, load_scene, solve_modes
from modalfe.results.coupling import k_eff

SCENE = Path(__file__).with_name("plate_with_holes.toml")
COARSE = {"mesh.max_size": 4e-3, "mesh.min_layers": 1}  # [m], layers through the plate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="a coarse mesh without error estimate, for the tests")
    quick = parser.parse_args().quick
    scene = load_scene(SCENE, **(COARSE if quick else {}))
    modes = solve_modes(scene, error_estimate=not quick)
    print(f"{modes.dofs} DOFs, {modes.fidelity}")
    for mode in modes:
        error = "not estimated" if math.isnan(mode.error_estimate) else f"{100 * mode.error_estimate:.3f} %"
        print(f"{mode.label:<10} {mode.frequency:>10,.1f} Hz  stated error {error}")
    first = modes[0]
    figures = forced_response(scene, selector=first.label, near=first.frequency, error_estimate=not quick)
    rom, fa = figures.rom, figures.antiresonance
    print(f"{rom.label} driven by the disc, damping {rom.damping_description} ({figures.damping_source}):")
    print(f"  tip amplitude {1e6 * figures.amplitude_per_volt['tip']:.3f} um/V at resonance, "
          f"fa {fa:,.1f} Hz, k_eff {k_eff(rom.frequency, fa):.4f}")


if __name__ == "__main__":
    main()
