"""Stated against actual error where an estimate level may leave part of the device uncoarsened (issue 34, item 4):
``python studies/level_coverage.py [stack strip cantilever]``.

Cases (references of our own: the same scene at a higher element order, its change from the order below it given as
the reference's own uncertainty):
- ``stack``: a free aluminium disc (12 x 1.5 mm) with a PZT-5A disc (8 x 1.2 mm) bonded by 50 um of epoxy, its
  torsion mode T2 near 192 kHz, on 0.75 mm elements: the ceramic is 2 layers thick on the scene's grid and on the
  x1.5 level (ceil(1.2 / 0.75) = ceil(1.2 / 1.125) = 2), 1 on the x2.25 level;
- ``strip``: a 20 x 16 x 2 mm Cu-Be plate clamped on a 2 mm strip of its lower face (a face window);
- ``cantilever``: a 30 x 10 x 0.5 mm Cu-Be plate clamped on one end.
Each row: the scene's own grid with its estimate (``fidelity.solve_estimated``), the reference, actual, stated, and
the estimate method (which level was used as a step, and why one was not).
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from modalfe.results.modes import select
from modalfe.solve.fidelity import solve_estimated
from modalfe.solve.levels import solve_level
from tests.oracles.cases import cantilever_plate_scene, stack_scene, strip_scene


def at_order(scene, order: int):
    return dataclasses.replace(scene, mesh=dataclasses.replace(scene.mesh, order=order, family="lagrange"))


CASES = {"stack": (stack_scene, "T2"), "strip": (strip_scene, None), "cantilever": (cantilever_plate_scene, None)}


def rows(name: str) -> list[tuple]:
    """(case, label, f, reference, reference uncertainty, actual, stated, method, seconds) of every elastic mode of
    the case, or of its named mode."""
    build, label = CASES[name]
    scene = build()
    start = time.perf_counter()
    found = solve_estimated(scene, scene.analysis, "solid")
    seconds = time.perf_counter() - start
    refs = [solve_level(at_order(scene, order), scene.analysis) for order in (3, 4)]
    out = []
    for mode in found:
        if mode.frequency < 1.0 or (label is not None and mode.label != label):
            continue
        ref3, ref4 = (select(r, mode.label, mode.frequency).frequency for r in refs)
        out.append((name, mode.label, mode.frequency, ref4, abs(ref3 / ref4 - 1), abs(mode.frequency / ref4 - 1),
                    mode.error_estimate, found.estimate_method, seconds))
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=list(CASES))
    for name in parser.parse_args(argv).cases:
        found = rows(name)
        for case, label, f, ref, unc, actual, stated, _, seconds in found:
            print(f"{case:<10} {label:<10} {f:>12.3f} {ref:>12.3f} ref+-{unc:.1e} actual {actual:.2e} stated "
                  f"{stated:.2e} {'covers' if stated + unc >= actual else 'SHORT'} ({seconds:.1f} s)", flush=True)
        print(f"  {found[0][7] if found else 'no mode'}", flush=True)


if __name__ == "__main__":
    main()
