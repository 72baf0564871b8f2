"""A free steel ring (steel_ring.toml: mean radius 20 mm, wall 1 mm, height 2 mm) on its meridian plane: the in-plane
bending modes with n = 2 and 3 nodal diameters beside thin-ring theory,
f_n = n (n^2 - 1) / sqrt(n^2 + 1) sqrt(E I / (rho A R^4)) / (2 pi) (Hoppe 1871; Blevins 1979, Table 9-1).

    python examples/steel_ring.py [--quick]

--quick states the frequencies to 1 % instead of 0.01 %.
"""

import argparse
import math
from pathlib import Path

from modalfe import load_scene, solve_modes

SCENE = Path(__file__).with_name("steel_ring.toml")


def thin_ring(n: int, *, radius: float, wall: float, height: float, E: float, rho: float) -> float:
    """In-plane inextensional mode n >= 2 of a thin ring [Hz] (Blevins 1979, Table 9-1); I = height wall^3 / 12."""
    area, inertia = height * wall, height * wall**3 / 12
    return n * (n * n - 1) / math.sqrt(n * n + 1) * math.sqrt(E * inertia / (rho * area * radius**4)) / (2 * math.pi)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="a coarse tolerance, for the tests")
    tol = 1e-2 if parser.parse_args().quick else 1e-4
    scene = load_scene(SCENE)
    steel = scene.materials["steel"]
    for n in (2, 3):
        theory = thin_ring(n, radius=0.02, wall=0.001, height=0.002, E=steel["E"], rho=steel["rho"])
        # harmonics 0..3 in one solve; the mode asked about, labelled n=N by its harmonic, sets the refinement
        mode = solve_modes(scene, fidelity="axisymmetric", harmonics=3, mode=f"n={n}", near=theory,
                           tol=tol).labelled(f"n={n}")
        print(f"n={n}: {mode.frequency:,.1f} Hz (stated error {100 * mode.error_estimate:.3f} %), "
              f"thin-ring theory {theory:,.1f} Hz: {100 * (mode.frequency / theory - 1):+.2f} % "
              "(the theory leaves out shear and rotary inertia)")


if __name__ == "__main__":
    main()
