"""Curved parts on swept hexahedra (``modalfe.models.swept``): convergence in the element order and in the element
size, stated against actual errors, DOFs and run time against curved tetrahedra.

Cases (the quantities and theories of studies/curved_convergence.py): the free 20 x 1 mm PZT-5A disc (fr, fa against
IEEE Std 176 thin-disc theory), the free steel ring (in-plane n = 2, 3 against Hoppe), the radially poled PZT-4 ring
(fr, fa against the thin-ring formula), and ``round_feet``, the Cu-Be plate's (0,6) mode with round feet.

For each case, on the mesh its scene asks for (``mesh.elements_per_wavelength``):
- p: Lagrange hexahedra of orders 2, 3, 4 with one element layer, the rate q of e_p ~ p^-q observed through them;
- reference: order 3 on elements 1.5x smaller (one layer: the p-sequence shows orders 3 and 4 on one layer within
  ~1e-6 of each other, through the thickness too); its distance from the base mesh's highest order is the
  geometry's share (the orders share one geometry);
- h: order 2 on elements x1, x1/1.25, x1/1.5625 (non-nested section meshes), the observed order;
- stated vs actual: the default (20-node serendipity, three layers, Richardson through three grids) and order 4
  with one layer (also Richardson: on curved hexahedra the orders share one geometry and their steps miss its
  error, ``modalfe.solve.rung.Rung.uses_orders``), each stated error against the actual one from the reference.
``round_feet``: the default's stated error against order 3 on the same mesh (``round_feet``).

    python studies/swept_verification.py [disc steel_ring pzt_ring round_feet]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: studies, tests.oracles
from modalfe.results.modes import select
from modalfe.scene import load_scene
from modalfe.solve.api import OWN_MESH, solve_modes
from modalfe.solve.estimates import p_rate
from studies.curved_convergence import cases, richardson3

H_RATIO = 1.25


def with_mesh(scene, **settings):
    return replace(scene, mesh=replace(scene.mesh, **settings))


def quantities(name: str):
    """(scene on swept hexahedra with the scene's own element sizes, [(label, solve kwargs, picker, theory)])."""
    build, _, qs = cases()[name]
    return with_mesh(build(math.inf, 1), element="hex"), qs


_SOLVED: dict[str, tuple] = {}  # (modes, seconds) by scene and options: the ring's n = 2 and 3 share every solve


def solve(scene, kwargs, pick, **options) -> tuple[float, float, int, float]:
    """(frequency [Hz], stated error, DOFs, seconds of the solve) of the picked mode."""
    key = repr((scene, sorted(kwargs.items()), sorted(options.items())))
    if key not in _SOLVED:
        start = time.perf_counter()
        modes = solve_modes(scene, **{"fidelity": "solid", "tol": OWN_MESH, **kwargs, **options})
        _SOLVED[key] = modes, time.perf_counter() - start
    modes, seconds = _SOLVED[key]
    mode = pick(modes)
    return mode.frequency, mode.error_estimate, modes.dofs, seconds


def round_feet() -> None:
    """The Cu-Be plate's (0,6) with round feet: the default's stated error against order 3 on the same swept mesh
    (three layers; a finer grid at order 3 would be ~600k DOFs). The reference shares the mesh's geometry, whose
    own error was below 2e-7 on the disc and the rings."""
    scene = load_scene("cube_plate", foot_shape="round")
    pick = lambda m: select(m, "(0,6)", 40e3)  # noqa: E731
    f, stated, dofs, seconds = solve(scene, {"near": 40e3, "count": 4}, pick, error_estimate=True)
    ref, _, ref_dofs, ref_s = solve(with_mesh(scene, order=3, family="lagrange"), {"near": 40e3, "count": 4}, pick,
                                    error_estimate=False)
    actual = abs(f / ref - 1)
    print(f"round_feet (0,6): default {f:.3f} Hz, {dofs} DOFs, {seconds:.1f} s with the estimate; order 3 on the same"
          f" mesh {ref:.3f} Hz ({ref_dofs} DOFs, {ref_s:.0f} s); stated {100 * stated:.4f} % vs actual"
          f" {100 * actual:.4f} % -> {'covers' if stated >= actual else 'SHORT'}", flush=True)


def study(name: str) -> None:
    if name == "round_feet":
        return round_feet()
    base, qs = quantities(name)
    for label, kwargs, pick, theory in qs:
        tag = f"{name} {label}"
        orders = {}
        for p in (2, 3, 4):
            scene = with_mesh(base, order=p, family="lagrange", min_layers=1)
            orders[p] = solve(scene, kwargs, pick, error_estimate=False)
            print(f"{tag}: order {p}, 1 layer: {orders[p][0]:.3f} Hz, {orders[p][2]} DOFs, {orders[p][3]:.1f} s",
                  flush=True)
        q = p_rate(4, orders[2][0] - orders[3][0], orders[3][0] - orders[4][0])
        fine = with_mesh(base, order=3, family="lagrange", min_layers=1)
        ref, _, ref_dofs, ref_s = solve(fine, kwargs, pick, error_estimate=False, size_factor=1 / 1.5)
        spread = abs(ref / orders[4][0] - 1)
        theory_note = f", theory {theory:.2f} Hz ({100 * (ref / theory - 1):+.3f} %)" if math.isfinite(theory) else ""
        print(f"{tag}: p-rate through orders 2-3-4 {q if q is None else round(q, 2)}; reference (order 3, elements"
              f" /1.5, {fine.mesh.min_layers} layer(s), {ref_dofs} DOFs, {ref_s:.0f} s) {ref:.3f} Hz, "
              f"{100 * spread:.5f} % from order 4 on the base mesh{theory_note}", flush=True)
        h = [solve(with_mesh(base, order=2, family="lagrange", min_layers=1), kwargs, pick, error_estimate=False,
                   size_factor=H_RATIO**-k) for k in range(3)]
        order, _ = richardson3([r[0] for r in h], H_RATIO)
        print(f"{tag}: order 2 at elements x1, /1.25, /1.5625: " + ", ".join(f"{r[0]:.3f} Hz ({r[2]} DOFs)" for r in h)
              + f"; observed h-order {order:.2f} (quadratic elements on smooth fields: 4)", flush=True)
        checked = (("default (S2, 3 layers, Richardson)", with_mesh(base, order=2, family="auto", min_layers=3)),
                   ("order 4, 1 layer (Richardson)", with_mesh(base, order=4, family="lagrange", min_layers=1)))
        for what, scene in checked:
            f, stated, dofs, seconds = solve(scene, kwargs, pick, error_estimate=True)
            actual = abs(f / ref - 1)
            verdict = "covers" if stated >= actual else "SHORT"
            print(f"{tag}: {what}: {f:.3f} Hz, {dofs} DOFs, {seconds:.1f} s with the estimate; stated "
                  f"{100 * stated:.4f} % vs actual {100 * actual:.4f} % ({actual:.1e}) -> {verdict}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=["disc", "steel_ring", "pzt_ring", "round_feet"])
    for name in parser.parse_args().cases:
        study(name)


if __name__ == "__main__":
    main()
