"""What sharing one PARDISO symbolic analysis saves (``modalfe.solve.linalg._Analysis``): the Cu-Be plate's resolved
short-circuit pencil (the answer ``modalfe modes cube_plate`` gives), factorized at a first shift, then at three more
shifts of the same pattern (a band's two Sturm counts and its residual) with the analysis shared and with a fresh
analysis each; medians of the three, seconds, in one process.

    python studies/pardiso_sharing.py [--scene cube_plate]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from modalfe.scene import load_scene
from modalfe.solve import linalg
from modalfe.solve.api import solve_modes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="cube_plate")
    scene = load_scene(parser.parse_args().scene)
    modes = solve_modes(scene)
    constraints = modes.model.constraints("short")
    A, B = constraints.project(modes.model.K), constraints.project(modes.model.M)
    f = modes[0].frequency
    shifts = [(2 * np.pi * f * r) ** 2 for r in (0.77, 1.3, 1.02)]
    kept = linalg.factorize((A - (2 * np.pi * f * 1.005) ** 2 * B).tocsr(), solver="pardiso")[0]  # the answer's
    times = {}
    for shared in (True, False):
        seconds = []
        for sigma in shifts:
            start = time.perf_counter()
            if shared:  # ``factorize`` finds the kept factorization's analysis and takes a free slot of it
                solve = linalg.factorize((A - sigma * B).tocsr(), solver="pardiso")[0]
            else:  # an analysis of its own, as before sharing
                upper = linalg.upper_triangle((A - sigma * B).tocsr())
                solve = linalg._Analysis(upper).factor(upper)
            seconds.append(time.perf_counter() - start)
            del solve
        times[shared] = statistics.median(seconds)
    del kept
    print(f"{scene.name}: {A.shape[0]} unknowns; a further shift factorized in {times[True]:.2f} s on the shared "
          f"analysis, {times[False]:.2f} s with its own (ratio {times[True] / times[False]:.2f})")


if __name__ == "__main__":
    main()
