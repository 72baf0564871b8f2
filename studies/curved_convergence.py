"""Mesh convergence of curved parts (curved P2 tetrahedra) and whether their stated errors cover their actual ones.

Cases (issue 20, items 4 and 5):

- ``disc``: free 20 mm x 1 mm PZT-5A disc, planar mode fr (short) and fa (open) against the thin-disc theory of
  IEEE Std 176-1987 (Meitzler et al. 1961);
- ``steel_ring``: free steel ring (R = 20 mm, wall 1 mm, height 2 mm), in-plane flexure n = 2, 3 against Hoppe (1871);
- ``pzt_ring``: radially poled PZT-4 ring (R = 10 mm, wall 0.5 mm, height 1 mm), breathing fr against the thin-ring
  formula fr = sqrt(1 / (rho s11^E)) / (2 pi R) (Berlincourt, Curran & Jaffe 1964);
- ``sensor``: the Cu-Be plate's (0,6) mode with a square or a round 5 mm measurement ceramic, both on tetrahedra.

Each convergence case is solved with one element size for every part, ``LEVELS`` x the part's thickness (ratio 1.25,
``mesh.min_layers = 1``, so the thickness caps no level), extrapolated from the three finest levels with the observed
order (Richardson); then the coarsest mesh that states an error (the fewest ``mesh.min_layers``,
modalfe.solve.rung.Rung.no_estimate_reason: 3 on these thin parts) is solved with ``error_estimate=True`` and its
stated error set against its actual error from the extrapolated value, unless it exceeds ``MAX_DOFS``.

    python studies/curved_convergence.py [disc steel_ring pzt_ring sensor]
"""

from __future__ import annotations

import argparse
import itertools
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path

from modalfe.models.estimate import estimate_size
from modalfe.results.modes import select
from modalfe.scene import load_scene
from modalfe.scene.loading import scene_from_dict
from modalfe.solve.api import OWN_MESH, solve_modes
from modalfe.solve.rung import Rung

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests.oracles
from tests.oracles.discs import (
    axisymmetric,
    compliances,
    in_plane,
    ring_inplane_frequency,
    thin_disc,
    thin_ring_breathing,
)

LEVELS = (1.0, 0.8, 0.64, 0.512)  # element size / thickness: ratio 1.25 a level, ~2x the DOFs a level
RATIO = 1.25
MAX_DOFS = 120_000  # what fits the shared 2-core machine in a few minutes
P2_ORDER = 4.0  # eigenvalue error of P2 ~ h^(2p) = h^4 (Strang & Fix 1973, ch. 6) on smooth modes


def disc_scene(size: float, layers: int = 1):
    return scene_from_dict({
        "units": "mm", "parts": [{"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [0, 0, 0],
                                  "axis": "z", "radius": 10, "height": 1, "poling": 1}],
        "faces": {"electrode_a": ["disc.top"], "electrode_b": ["disc.bottom"]},
        "electrodes": {"electrode_a": "drive", "electrode_b": "ground"},
        "analysis": {"near": 99e3, "count": 8}, "mesh": {"element": "tet", "min_layers": layers, "max_size": size}})


def pzt_ring_scene(size: float, layers: int = 1):
    return scene_from_dict({
        "units": "mm", "parts": [{"name": "ring", "shape": "ring", "material": "PZT-4", "centre": [0, 0, 0],
                                  "axis": "z", "inner": 9.75, "outer": 10.25, "height": 1, "poling": "radial"}],
        "faces": {"electrode_a": ["ring.outer"], "electrode_b": ["ring.inner"]},
        "electrodes": {"electrode_a": "drive", "electrode_b": "ground"},
        "analysis": {"near": 52e3, "count": 8}, "mesh": {"element": "tet", "min_layers": layers, "max_size": size}})


STEEL = {"E": 200e9, "nu": 0.3, "rho": 7850.0}  # generic structural steel, as tests/models/test_curved_parts.py


def steel_ring_scene(size: float, layers: int = 1):
    return scene_from_dict({
        "units": "mm", "materials": {"steel": STEEL},
        "parts": [{"name": "ring", "shape": "ring", "material": "steel", "centre": [0, 0, 0], "axis": "z",
                   "inner": 19.5, "outer": 20.5, "height": 2}],
        "analysis": {"near": 3e3, "count": 12}, "mesh": {"element": "tet", "min_layers": layers, "max_size": size}})


# One quantity of a case: (label, scene kwargs to solve_modes, picker of the mode, theory [Hz]).
Quantity = tuple[str, dict, Callable, float]


def cases() -> dict[str, tuple[Callable, float, list[Quantity]]]:
    """name -> (scene of (element size, min_layers), thickness [m], quantities)."""
    fr, fa = thin_disc("PZT-5A", 0.01)
    ring_fr = thin_ring_breathing("PZT-4", 0.01)
    s, d, eps_t, _ = compliances("PZT-4")
    k31 = math.sqrt(d[2, 0] ** 2 / (s[0, 0] * eps_t[2, 2]))
    # Hoppe's ring, in-plane bending: I / A = wall^2 / 12 (radial wall 1 mm)
    f2, f3 = (ring_inplane_frequency(n, radius=0.02, E=STEEL["E"], rho=STEEL["rho"], area=1.0, inertia=0.001**2 / 12)
              for n in (2, 3))
    disc_pick = lambda m: axisymmetric(m, 0.0098, 0.0005)  # noqa: E731
    ring_pick = lambda m: axisymmetric(m, 0.01, 0.0005)  # noqa: E731
    return {
        "disc": (disc_scene, 1e-3, [
            ("fr", {"near": fr}, disc_pick, fr),
            ("fa", {"near": fa, "circuit": "open"}, disc_pick, fa)]),
        "steel_ring": (steel_ring_scene, 1e-3, [
            ("n=2", {"near": 0.5 * (f2 + f3), "count": 12}, lambda m: in_plane(m, 2, 0.02, 0.001), f2),
            ("n=3", {"near": 0.5 * (f2 + f3), "count": 12}, lambda m: in_plane(m, 3, 0.02, 0.001), f3)]),
        "pzt_ring": (pzt_ring_scene, 0.5e-3, [
            ("fr", {"near": ring_fr}, ring_pick, ring_fr),
            ("fa", {"near": ring_fr / math.sqrt(1 - k31**2), "circuit": "open"}, ring_pick,
             ring_fr / math.sqrt(1 - k31**2))]),
    }


def richardson3(f: list[float], ratio: float = RATIO) -> tuple[float, float]:
    """(observed order, extrapolated value) from three levels f[-3:] (elements ``ratio`` x smaller each):
    p = ln((f1 - f2) / (f2 - f3)) / ln r, f = f3 + (f3 - f2) / (r^p - 1). The order is NaN where the differences
    change sign; where it is NaN or outside [1, 8] (non-nested meshes, differences at round-off, thickness layers
    that do not refine with h) the extrapolation uses P2_ORDER."""
    f1, f2, f3 = f[-3:]
    q = (f1 - f2) / (f2 - f3) if f2 != f3 else -1.0
    order = math.log(q) / math.log(ratio) if q > 0 else math.nan
    p = order if 1.0 <= order <= 8.0 else P2_ORDER
    return order, f3 + (f3 - f2) / (ratio**p - 1)


def convergence(name: str, levels: tuple[float, ...] = LEVELS) -> dict[str, tuple[float, float]]:
    """Print the level table, extrapolation and stated-vs-actual error (``stated_error``) of one case; return
    label -> (observed order, extrapolated value [Hz])."""
    build, thickness, quantities = cases()[name]
    rows = []
    for level in levels:
        start = time.perf_counter()
        values, dofs = [], 0
        for _, kwargs, pick, _ in quantities:
            modes = solve_modes(build(level * thickness), error_estimate=False, **kwargs)
            values.append(pick(modes).frequency)
            dofs = modes.dofs
        rows.append((level, dofs, values, time.perf_counter() - start))
        print(f"{name} h = {level:.3f} t: {dofs:7d} DOFs  " + "  ".join(
            f"{q[0]} {v:10.2f} Hz" for q, v in zip(quantities, values)) + f"  ({rows[-1][3]:.0f} s)", flush=True)
    out = {}
    for i, (label, _, _, theory) in enumerate(quantities):
        f = [r[2][i] for r in rows]
        order, extrapolated = richardson3(f)
        out[label] = (order, extrapolated)
        diffs = " ".join(f"{b - a:+.3g}" for a, b in itertools.pairwise(f))
        print(f"{name} {label}: differences {diffs} Hz, observed order {order:.2f}, extrapolated {extrapolated:.2f} Hz"
              f" vs theory {theory:.2f} Hz ({100 * (extrapolated / theory - 1):+.3f} %); coarsest level"
              f" {100 * abs(f[0] / extrapolated - 1):.4f} % from it", flush=True)
    stated_error(name, quantities, build, {q[0]: out[q[0]][1] for q in quantities})
    return out


def stated_error(name: str, quantities: list[Quantity], build: Callable, extrapolated: dict[str, float]) -> None:
    """Stated (``Mode.error_estimate``) against actual error from ``extrapolated`` on the fewest layers whose mesh
    states one (``Rung.no_estimate_reason``); skipped, with the DOFs it would take, above ``MAX_DOFS``."""
    for layers in (1, 2, 3):
        scene = build(math.inf, layers)
        reason = Rung(scene).no_estimate_reason
        if reason is None:
            break
        print(f"{name}: min_layers {layers} states no error ({reason[:60]}...)", flush=True)
    else:
        return
    dofs = estimate_size(scene).dofs
    if dofs > MAX_DOFS:
        print(f"{name}: min_layers {layers} would state one at ~{dofs:.0f} DOFs (estimate_size): skipped", flush=True)
        return
    for label, kwargs, pick, _ in quantities:
        stated = solve_modes(scene, fidelity="solid", tol=OWN_MESH, **kwargs)
        mode = pick(stated)
        actual = abs(mode.frequency / extrapolated[label] - 1)
        print(f"{name} {label}: min_layers {layers} ({stated.dofs} DOFs) {mode.frequency:.2f} Hz, stated"
              f" {100 * mode.error_estimate:.4f} % vs actual {100 * actual:.4f} %"
              f" -> {'covers' if mode.error_estimate >= actual else 'SHORT'}", flush=True)


SENSOR_AT = (32e-3, 34.5e-3)  # between the upper ceramic row (y 19.5-31.5 mm) and the edge (38 mm), mid-length


def sensor(layers: tuple[int, ...] = (1, 2)) -> dict[tuple[str, int], tuple[float, int]]:
    """(0,6) of the Cu-Be plate with no, a square and a round 5 mm ceramic at ``SENSOR_AT``, all on tetrahedra with
    the same mesh settings, for each ``mesh.min_layers`` in ``layers``: (label, layers) -> (Hz, DOFs). The whole
    plate (the sensor breaks the y mirror): its tetrahedra are the plate's thickness / layers, ~290k DOFs at the 3
    layers that state an error (``Rung.no_estimate_reason``), over ``MAX_DOFS``; the shift's change from one mesh to
    the next is its mesh error instead."""
    out = {}
    for n in layers:
        for label, extra in (("none", {}), ("square", {"sensor": SENSOR_AT}),
                             ("round", {"sensor": SENSOR_AT, "sensor_shape": "round"})):
            start = time.perf_counter()
            scene = load_scene("cube_plate", symmetry=[], **{"mesh.element": "tet", "mesh.min_layers": n}, **extra)
            modes = solve_modes(scene, near=40e3, count=6, error_estimate=False)
            mode = select(modes, "(0,6)", 40e3)
            out[label, n] = (mode.frequency, modes.dofs)
            print(f"sensor {label:6s} min_layers {n}: {modes.dofs} DOFs, (0,6) {mode.frequency:.2f} Hz "
                  f"({time.perf_counter() - start:.0f} s)", flush=True)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=["disc", "steel_ring", "pzt_ring", "sensor"])
    args = parser.parse_args()
    for name in args.cases:
        if name == "sensor":
            sensor()
        else:
            convergence(name)


if __name__ == "__main__":
    main()
