"""A free 20 x 1 mm PZT-5A disc with electrodes on both faces (pzt5a_disc.toml), solved on its meridian plane: the
planar mode R1 in short circuit (fr) and open circuit (fa), and its coupling k_eff, beside IEEE Std 176-1987's
thin-disc theory (fr = 99,478 Hz for PZT-5A's constants).

    python examples/pzt_disc.py [--quick]

--quick states the frequencies to 1 % instead of 0.01 %.
"""

import argparse
from pathlib import Path

from modalfe import solve_modes
from modalfe.results.coupling import k_eff

SCENE = Path(__file__).with_name("pzt5a_disc.toml")
THIN_DISC_FR = 99_478.0  # [Hz] IEEE Std 176-1987 planar mode of a thin disc, PZT-5A (Berlincourt 1964 constants)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="a coarse tolerance, for the tests")
    tol = 1e-2 if parser.parse_args().quick else 1e-4
    # the body of revolution on its (r, z) plane: one 2-D solve holds every circumferential harmonic asked for
    fr = solve_modes(SCENE, fidelity="axisymmetric", mode="R1", tol=tol).labelled("R1")
    fa = solve_modes(SCENE, fidelity="axisymmetric", mode="R1", circuit="open", tol=tol).labelled("R1")
    print(f"R1 short circuit fr = {fr.frequency:,.1f} Hz (stated error {100 * fr.error_estimate:.4f} %)")
    print(f"R1 open circuit  fa = {fa.frequency:,.1f} Hz (stated error {100 * fa.error_estimate:.4f} %)")
    print(f"k_eff = {k_eff(fr.frequency, fa.frequency):.4f}")
    print(f"thin-disc theory fr = {THIN_DISC_FR:,.0f} Hz: {100 * (fr.frequency / THIN_DISC_FR - 1):+.2f} % "
          "(the theory neglects the disc's thickness)")


if __name__ == "__main__":
    main()
