"""Does the error estimate tell the truth? Richardson estimates against refinement sequences.

For each device's working mode: solve on meshes refined uniformly (element sizes x 1.5^-k, layers
through the thickness scaled alike), extrapolate from the three finest with the observed order, and
compare the default mesh's reported error estimate with its error against the extrapolated value.

    python studies/convergence.py [--quick]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from modalfe.results.modes import select
from modalfe.scene import load_scene
from modalfe.solve.api import OWN_MESH, solve_modes

CASES = {
    "cube_plate": ("(0,6)", 40.7e3),
    "ciliary_beam": ("bending-z 6", 22e3),
    "glass_plate": ("(0,n)", 66e3),
}


def sequence(name: str, selector: str, near: float, levels: int) -> list[tuple[float, int, float]]:
    """(size factor, DOFs, frequency) from coarse to fine; layers 2, 3, 4.5 -> rounded."""
    out = []
    for k in range(levels):
        factor = 1.5 ** (1 - k)
        layers = max(2, round(2 * 1.5**k))
        scene = load_scene(name, **{"mesh.min_layers": layers})
        modes = solve_modes(scene, near=near, count=8, size_factor=factor, error_estimate=False)
        out.append((factor, modes.dofs, select(modes, selector, near).frequency))
    return out


def _plot(name: str, seq, extrapolated: float, order: float, path: Path) -> None:
    from modalfe.plot.figures import plot_convergence

    path.parent.mkdir(parents=True, exist_ok=True)
    fig = plot_convergence([d for _, d, _ in seq], [abs(f / extrapolated - 1) for _, _, f in seq],
                           label=f"{name}: error vs extrapolated", order=order)
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="beam only, three levels")
    parser.add_argument("--plots", default="studies/out", help="folder for the error vs DOFs plots")
    args = parser.parse_args()
    cases = {"ciliary_beam": CASES["ciliary_beam"]} if args.quick else CASES
    levels = 3 if args.quick else 4
    for name, (selector, near) in cases.items():
        seq = sequence(name, selector, near, levels)
        (_, _, f1), (_, _, f2), (_, _, f3) = seq[-3:]
        ratio = 1.5
        order = math.log(abs((f1 - f2) / (f2 - f3))) / math.log(ratio) if f2 != f3 else float("nan")
        extrapolated = f3 + (f3 - f2) / (ratio**order - 1)
        default = solve_modes(load_scene(name), near=near, count=8, fidelity="solid", tol=OWN_MESH)
        mode = select(default, selector, near)
        true_error = abs(mode.frequency / extrapolated - 1)
        print(f"{name} {mode.label}: levels " + ", ".join(f"{d} DOFs {f:.1f} Hz" for _, d, f in seq))
        _plot(name, seq, extrapolated, order, Path(args.plots) / f"convergence_{name}.png")
        print(f"  observed order {order:.2f}, extrapolated {extrapolated:.1f} Hz; "
              f"default mesh {mode.frequency:.1f} Hz: estimate {100 * mode.error_estimate:.3f}% "
              f"vs error {100 * true_error:.3f}%")


if __name__ == "__main__":
    main()

