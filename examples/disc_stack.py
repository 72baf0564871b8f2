"""A composite disc stack (disc_stack.toml: an aluminium disc, a 50 um epoxy film and a PZT-5A disc bonded on one
axis) on its meridian plane: its axisymmetric modes (harmonic n = 0) from 50 to 300 kHz with their stated errors, and
the coupling of each to the ceramic's electrodes: fa of the open-circuit mode of the same shape, k_eff^2 = 1 - fr^2 /
fa^2 (IEEE Std 176-1987). Full-face electrodes drive only n = 0: the other harmonics carry no net charge.

    python examples/disc_stack.py [--quick]

--quick states the frequencies to 1 % instead of 0.1 %.
"""

import argparse
from pathlib import Path

from modalfe import solve_modes
from modalfe.response.forced import open_circuit

SCENE = Path(__file__).with_name("disc_stack.toml")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="a coarse tolerance, for the tests")
    tol = 1e-2 if parser.parse_args().quick else 1e-3
    short = solve_modes(SCENE, fidelity="axisymmetric", harmonics=0, band=(50e3, 300e3), tol=tol)
    print(f"{'mode':<6} {'fr [Hz]':>11} {'stated':>8} {'fa [Hz]':>11} {'k_eff':>7}   ({short.dofs} DOFs)")
    for mode in short:
        both = open_circuit(mode, among=short, near=mode.frequency)
        print(f"{mode.label:<6} {mode.frequency:>11,.1f} {100 * mode.error_estimate:>7.3f}% {both.fa:>11,.1f} "
              f"{both.k_eff:>7.4f}")

if __name__ == "__main__":
    main()
