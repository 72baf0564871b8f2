"""The report's working modes at a tight tolerance, stated against actual error:
``python studies/report_tolerance.py [--tol 0.005] [--scene NAME ...]``.

Each working mode is solved as ``modalfe report --tol TOL`` solves it (``fidelity="auto"``: the reduced model if its
stated error meets TOL, else the 3-D solid, refined until its own estimate meets TOL,
``modalfe.solve.fidelity.refined_to_tol``), then against a reference of higher order, paired by shape (MAC over the
answering model's sample points, the most alike):
- the Cu-Be plate's (0,6) and the glass plate's (0,16): the limit of nested uniform refinement of the mode's grid
  (studies/singular_convergence.py, NESTED: 39,527.6 Hz at the order 1.34 its last three grids show, up to 307,966
  DOFs, +-0.040 %; 235,730.1 Hz at 2.41, +-0.100 %, the uncertainty how far the limit moves if the order falls to 1
  beyond the last grid). The Cu-Be plate's order-4 reference of before (39,588.9 Hz, stating 0.211 %) was itself
  short of it: order 4 on 4.5, 6 and 8 elements per wavelength gives 39,573.6, 39,563.3, 39,553.5 Hz;
- the glass plate's (0,8), the tile's heave and tile_eq5: the solid at order 4 (Lagrange) on a grid finer than
  the default's p-grid (REFERENCES), its own p-estimate (orders 2-3-4 on that grid) stated beside it;
- the tile's (1,1) and heave: quartic Lagrange elements at max_size 0.03 and 2 layers on the mode's quarter (the
  family the report solves; 53k DOFs for (1,1)), which agrees with max_size 0.02 (83k DOFs) to 0.00078 %
  (modalfe/scene/builtin.py, the tile's assumptions);
- the ciliary beam's bending-z 6: studies/benchmark_peer.py's reference, 21,541.98 Hz (modalfe's finest order-4 level,
  117,606 DOFs graded to the clamp; NGSolve's order 4 agrees to 0.0003 %), uncertainty 0.008 %.
A row is covered (``yes``) when stated >= actual + the reference's own error (whichever way the reference is off),
``?`` when only within the reference's error, else ``NO``. Prints one line per working mode and the wall time of
each scene's auto solve (one process, MKL as configured: quote it with the machine's load).
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from modalfe.report.report import window_modes, working_windows
from modalfe.results.modes import select
from modalfe.scene import load_scene
from modalfe.solve.api import OWN_MESH, solve_modes
from modalfe.solve.estimates import common_points, sample_points, sampled

# scene -> mesh settings of the reference solid (order 4 on finer grids than the p-grid of 2 elements per wavelength)
REFERENCES = {
    "cube_plate": {"order": 4, "elements_per_wavelength": 3.0, "min_layers": 2},
    "glass_plate": {"order": 4, "elements_per_wavelength": 4.0, "min_layers": 2},
    "tile_eq5": {"order": 4, "elements_per_wavelength": 3.0, "min_layers": 2},
    "honeycomb_tile": {"order": 4, "min_layers": 2, "max_size": 0.03},
}
# the tile's quartic reference on the twisting mode's antisymmetric quarter, 53k against 83k DOFs (max_size 0.02):
# 1118.0734 against 1118.0647 Hz
TILE_REFERENCE_ERROR = 7.8e-6
CILIARY_REFERENCE = (21541.98, 8e-5)  # Hz, relative uncertainty: docs/benchmark_peer.md, References
# (scene, working mode) -> (Hz, relative uncertainty): studies/singular_convergence.py
NESTED = {("cube_plate", "(0,6)"): (39527.6, 4.0e-4), ("glass_plate", "(0,16)"): (235730.1, 1.0e-3)}


def reference(scene, modes, mode, near: float) -> tuple[float, float]:
    """(frequency [Hz], its stated relative error) of ``mode``'s (one of ``modes``) partner by shape in the
    reference solid."""
    if scene.name == "ciliary_beam":
        return CILIARY_REFERENCE
    if (scene.name, mode.label) in NESTED:
        return NESTED[scene.name, mode.label]
    mesh = dataclasses.replace(scene.mesh, **{"family": "lagrange", **REFERENCES[scene.name]})
    fine = dataclasses.replace(scene, mesh=mesh)
    # the tile's quartic reference: its distance from the finer one (TILE_REFERENCE_ERROR) instead
    estimate = scene.name != "honeycomb_tile"
    solved = solve_modes(fine, near=near, count=10, fidelity="solid", error_estimate=estimate,
                         tol=OWN_MESH)
    # the reference mode most alike (MAC), not a one-to-one assignment of whole solves: on the tile two modes of the
    # answer resemble the reference's twisting mode and the assignment handed one of them the pad's local mode
    points = common_points(sample_points(modes), modes.model, solved.model)
    mac = (sampled(modes, points)[:, mode.index] @ sampled(solved, points)) ** 2
    partner = solved[int(np.argmax(mac))]
    return partner.frequency, (partner.error_estimate if estimate else TILE_REFERENCE_ERROR)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tol", type=float, default=0.005)
    parser.add_argument("--scene", nargs="*", default=["cube_plate", "glass_plate", "honeycomb_tile", "tile_eq5",
                                                        "ciliary_beam"])
    args = parser.parse_args()
    print(f"{'scene':<15} {'mode':<12} {'fidelity':<8} {'DOFs':>7} {'f [Hz]':>11} {'stated':>8} {'reference':>11} "
          f"{'ref err':>8} {'actual':>8} {'covered':>7} {'s':>6}")
    for name in args.scene:
        scene = load_scene(name)
        for window in working_windows(scene):  # each on its working modes' mirror family, as the report solves it
            start = time.perf_counter()
            modes = window_modes(window, fidelity="auto", tol=args.tol, error_estimate=True)
            seconds = time.perf_counter() - start
            for wm in window.members:
                mode = select(modes, wm.selector, wm.near)
                f_ref, ref_err = reference(window.scene, modes, mode, mode.frequency)
                actual = abs(mode.frequency / f_ref - 1)
                covered = ("yes" if mode.error_estimate >= actual + ref_err else
                           "?" if mode.error_estimate >= actual - ref_err else "NO")
                print(f"{name:<15} {mode.label:<12} {modes.fidelity:<8} {modes.dofs:>7} {mode.frequency:>11.2f} "
                      f"{100 * mode.error_estimate:>7.3f}% {f_ref:>11.2f} {100 * ref_err:>7.3f}% "
                      f"{100 * actual:>7.3f}% {covered:>7} {seconds:>6.1f}", flush=True)


if __name__ == "__main__":
    main()
