"""Where auto starts refining, calibrated on scenes the report does not solve:
``python studies/forecast_calibration.py [--tol 0.005]``.

``modalfe.solve.fidelity.first_step`` skips the scene's own quadratic grid (and the first quartic step) when the
forecast its two coarse estimate levels give (``scene_grid_forecast``), times a ratio, still exceeds tol. The
ratios must come from scenes other than the report's timed windows. Here, on CALIBRATION_CASES (plates and beams
of quadratic box hexahedra at the report's mesh settings, modes other than the report's working modes, dimensions
changed), each case's estimate levels are solved, the forecast taken, then the scene's own grid and the first
refinement step (quartic on the grid 3x coarser) are solved and their stated error read (``worst_checked`` of the
mode nearest the case's frequency). Printed: stated / forecast for both, and their least values over the cases,
which are ``FORECAST_GRID`` and ``FORECAST_FIRST_STEP`` (rounded down to two digits). A case whose forecast is 0
(no estimate to go by) gives no ratio. Also printed: what the least ratios would decide for each case, against
what the stated errors say it should (a start past a grid that would have met tol costs time, never accuracy).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time

from modalfe.report.report import working_windows
from modalfe.scene import load_scene, scene_from_dict
from modalfe.scene.scene import Analysis
from modalfe.solve import fidelity
from modalfe.solve.linalg import single_threaded_blas
from modalfe.solve.rung import Rung


def _family(name: str, window: int = 0, **overrides):
    """The mirror family of the report's window ``window`` of built-in scene ``name``, with ``overrides``."""
    return working_windows(load_scene(name, **overrides))[window].scene


def _mirrored(name: str, symmetric: tuple[str, ...], antisymmetric: tuple[str, ...]):
    """Built-in scene ``name`` solving the family symmetric about ``symmetric``, antisymmetric about
    ``antisymmetric`` (mid-planes): a family the report does not solve."""
    return dataclasses.replace(load_scene(name), symmetry=symmetric, antisymmetry=antisymmetric)


def _free_plate(length: float, width: float, thickness: float, material: str, max_frequency: float):
    return scene_from_dict({
        "name": f"free-{material}-plate", "kind": "plate",
        "parts": [{"name": "plate", "material": material, "origin": [0, 0, 0], "size": [length, width, thickness]}],
        "analysis": {"near": max_frequency / 2, "count": 4},
        "mesh": {"elements_per_wavelength": 6.0, "max_frequency": max_frequency},
    })


def _cantilever(length: float, side: float, max_frequency: float):
    return scene_from_dict({
        "name": "brass-cantilever", "kind": "beam",
        "parts": [{"name": "beam", "material": "brass-seed003", "origin": [0, 0, 0], "size": [length, side, side]}],
        "faces": {"clamp": ["beam.xmin"]}, "clamps": {"clamp": "xyz"},
        "analysis": {"near": max_frequency / 2, "count": 4},
        "mesh": {"elements_per_wavelength": 6.0, "max_frequency": max_frequency},
    })


# (case, scene factory, frequency [Hz] whose nearest mode is checked): none is a window the report solves
CALIBRATION_CASES = {
    "Cu-Be plate, 2.5 mm, near 35 kHz": (lambda: _family("cube_plate", thickness=2.5e-3), 35e3),
    "Cu-Be plate, 70 mm long, near 45 kHz": (lambda: _family("cube_plate", length=70e-3), 45e3),
    "glass plate, 1.5 mm, near 120 kHz": (lambda: _family("glass_plate", thickness=1.5e-3,
                                                            **{"mesh.max_frequency": 130e3}), 120e3),
    "glass plate, near 150 kHz": (lambda: _family("glass_plate", **{"mesh.max_frequency": 160e3}), 150e3),
    "ciliary beam, 80 mm, near 30 kHz": (lambda: _family("ciliary_beam", length=80e-3), 30e3),
    "free Cu-Be plate 40 x 10 x 2 mm, near 40 kHz": (lambda: _free_plate(0.04, 0.01, 0.002, "CuBe", 45e3), 40e3),
    "free Al-5052 plate 50 x 30 x 3 mm, near 30 kHz": (lambda: _free_plate(0.05, 0.03, 0.003, "Al-5052", 35e3),
                                                          30e3),
    "brass cantilever 60 x 4 x 4 mm, near 20 kHz": (lambda: _cantilever(0.06, 0.004, 25e3), 20e3),
    "brass cantilever 100 x 6 x 6 mm, near 12 kHz": (lambda: _cantilever(0.1, 0.006, 15e3), 12e3),
    "honeycomb tile, symmetric x, antisymmetric y, near 1.2 kHz": (lambda: _mirrored("honeycomb_tile", ("x",),
                                                                                      ("y",)), 1.2e3),
    "honeycomb tile, 600 mm, heave family, near 1 kHz": (lambda: _family("honeycomb_tile", length=0.6), 1e3),
}


@dataclasses.dataclass
class Calibration:
    case: str
    dofs: int
    forecast: float
    grid: float  # stated on the scene's own grid
    first_step: float  # stated on the first refinement step
    seconds: float


def calibrate(case: str, factory, near: float, *, count: int = 4) -> Calibration:
    """Forecast and stated errors of one case (see the module's docstring)."""
    start = time.perf_counter()
    scene = factory()
    rung = Rung(scene)
    if not rung.raises_order:
        raise ValueError(f"{case}: not quadratic box hexahedra, the forecast does not apply")
    analysis = Analysis(near=near, count=count, circuit=scene.analysis.circuit)
    with single_threaded_blas():
        levels = fidelity.solid_levels(rung, analysis)
        own = fidelity.solve_estimated(rung, analysis, "solid", levels=levels)
        check = _nearest_check(own, near)
        forecast = fidelity.scene_grid_forecast(rung, levels, check)
        step = fidelity.solve_estimated(rung.step(1), analysis, "solid")
    # the step's mode: the one nearest the grid's (its label may differ: the labeller reads a coarse quartic grid
    # at its vertices)
    return Calibration(case, own.dofs, forecast, fidelity.worst_checked(own, check)[0],
                       fidelity.worst_checked(step, _nearest_check(step, check[0][1]))[0],
                       time.perf_counter() - start)


def _nearest_check(modes, frequency: float) -> tuple[tuple[str, float]]:
    """``check`` naming the mode of ``modes`` nearest ``frequency`` [Hz]."""
    nearest = min(modes, key=lambda m: abs(m.frequency - frequency))
    return ((nearest.label, nearest.frequency),)


def least_ratios(rows: list[Calibration]) -> tuple[float, float]:
    """(least grid / forecast, least first_step / forecast) over the rows with a forecast, rounded down to 0.01."""
    used = [r for r in rows if r.forecast > 0]
    if not used:
        raise ValueError("no case gave a forecast")
    grid = min(r.grid / r.forecast for r in used)
    step = min(r.first_step / r.forecast for r in used)
    return math.floor(grid * 100) / 100, math.floor(step * 100) / 100


def _ratio(stated: float, forecast: float) -> str:
    return f"{stated / forecast:6.3f}" if forecast > 0 else "     -"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tol", type=float, default=0.005)
    parser.add_argument("--case", action="append", help="only these cases (repeatable)")
    args = parser.parse_args(argv)
    names = args.case or list(CALIBRATION_CASES)
    rows = []
    print(f"{'case':60s} {'DOFs':>7s} {'forecast':>9s} {'grid':>8s} {'ratio':>6s} {'step 1':>8s} {'ratio':>6s}  s")
    for name in names:
        factory, near = CALIBRATION_CASES[name]
        r = calibrate(name, factory, near)
        rows.append(r)
        print(f"{name:60s} {r.dofs:7d} {r.forecast:9.3%} {r.grid:8.3%} {_ratio(r.grid, r.forecast)} "
              f"{r.first_step:8.3%} {_ratio(r.first_step, r.forecast)} {r.seconds:4.1f}", flush=True)
    grid, step = least_ratios(rows)
    print(f"least ratios (rounded down): FORECAST_GRID = {grid}, FORECAST_FIRST_STEP = {step}")
    for r in rows:
        decided = 2 if r.forecast * step > args.tol else 1 if r.forecast * grid > args.tol else 0
        needed = 0 if r.grid <= args.tol else 1 if r.first_step <= args.tol else 2
        print(f"  {r.case:60s} starts at step {decided}; the stated errors say {needed} would do"
              + ("" if decided <= needed else "  (WRONG: would skip a grid that meets tol)"))


if __name__ == "__main__":
    main()
