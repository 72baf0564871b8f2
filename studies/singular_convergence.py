"""Nested uniform refinement of a working mode's grid, to tell a singular field's convergence from a smooth one:
``python studies/singular_convergence.py [--case cube|glass]`` (~2.5 min for the Cu-Be plate, ~1.5 for the glass).

The report's grids (``modalfe.solve.fidelity.refined_to_tol``) scale the element size, and every grid interval gets
ceil(length / size) elements: an interval shorter than the size (the 0.4 mm gaps between the Cu-Be plate's ceramics,
the glass plate's 1 mm margins) keeps one element on every grid, so the ratio between two grids differs from
interval to interval and an order observed through them is blurred. Here every interval of the mode's default grid
(the scene's mesh on its mirror family, as the report solves it) is split into k elements per element, thickness
layers too (``modalfe.models.mesh.divisions`` wrapped, the mesh cache off): the grids are nested and their ratios
exact, so the order seen through k = 1, 2, 3 and k = 2, 3, 4 is the field's own. A singular field (bonded ceramics
and feet over most of the Cu-Be plate) shows an order that falls as k grows, toward 2 alpha >= 1; a smooth one
stays at or above 2.

Prints each grid's frequency, the order of each triple, and the limit extrapolated from the last two grids at the
last order, with its uncertainty: how far the limit moves if the order falls to ``MIN_ORDER`` beyond the last grid
(the slowest any elasticity singularity converges; modalfe/solve/estimates.py). These limits are the references
of studies/report_tolerance.py for the Cu-Be plate's (0,6) and the glass plate's (0,16).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

os.environ["MODALFE_CACHE"] = "off"  # the meshes differ from the scene's own: never cache them under its key

import modalfe.caches as caches
import modalfe.models.mesh as mesh_module
from modalfe.report.report import working_windows
from modalfe.results.modes import select
from modalfe.scene import load_scene
from modalfe.solve.api import solve_modes
from modalfe.solve.estimates import MIN_ORDER, observed_order

CASES = {"cube": ("cube_plate", 0, (1, 2, 3, 4)), "glass": ("glass_plate", 1, (1, 2, 3))}
_grid_divisions = mesh_module.divisions


def nested_frequency(window, split: int) -> tuple[float, int]:
    """(frequency [Hz] of the window's first working mode, DOFs) with every grid interval split ``split`` times."""
    mesh_module.divisions = lambda *args, **kwargs: _grid_divisions(*args, **kwargs) * split
    mesh_module._memory_cache.clear()
    caches.clear()
    try:
        modes = solve_modes(window.scene, near=window.near, count=6, fidelity="solid", error_estimate=False)
    finally:
        mesh_module.divisions = _grid_divisions
    member = window.members[0]
    return select(modes, member.selector, member.near).frequency, modes.dofs


def limit(f_coarse: float, f_fine: float, ratio: float, order: float) -> float:
    """Richardson's limit of two grids ``ratio`` apart at ``order``."""
    return f_fine - (f_coarse - f_fine) / (ratio**order - 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=sorted(CASES), action="append")
    for case in parser.parse_args().case or sorted(CASES):
        name, index, splits = CASES[case]
        window = working_windows(load_scene(name))[index]
        print(f"{name} {window.members[0].selector} on its {window.scene.mirror_family or 'whole'} model")
        results = []
        for k in splits:
            start = time.perf_counter()
            f, dofs = nested_frequency(window, k)
            results.append((k, f))
            print(f"  split {k}: {dofs:>7} DOFs  {f:.3f} Hz  ({time.perf_counter() - start:.1f} s)", flush=True)
        for (k0, f0), (k1, f1), (k2, f2) in zip(results, results[1:], results[2:]):
            q = observed_order(f2, f1, f0, k2 / k1, k2 / k0)
            print(f"  order through splits {k0}-{k1}-{k2}: {q:.2f}")
        (k1, f1), (k2, f2) = results[-2:]
        ratio = k2 / k1
        reference = limit(f1, f2, ratio, q)
        floor = limit(f1, f2, ratio, MIN_ORDER)
        print(f"  limit at order {q:.2f}: {reference:.1f} Hz; at order {MIN_ORDER:g}: {floor:.1f} Hz "
              f"(uncertainty {abs(reference - floor) / reference:.3%})")


if __name__ == "__main__":
    main()
