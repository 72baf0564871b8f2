"""Pictures of every device's working mode for the README (docs/img/<scene>.png), with render times: two panels
(from above and from below) so that every foot and electrode is marked, and the list of markers drawn.

    python studies/render_working_modes.py [--quick] [--out docs/img]

Render time is measured after the modes are computed (median of three renders).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from modalfe.plot.render import render_mode
from modalfe.results.modes import select
from modalfe.scene import load_scene
from modalfe.scene.builtin import BUILTIN
from modalfe.solve.api import solve_modes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse meshes")
    parser.add_argument("--out", type=Path, default=Path("docs/img"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for name in BUILTIN:
        overrides = {"mesh.elements_per_wavelength": 4.0} if args.quick else {}
        scene = load_scene(name, **overrides)
        for k, wm in enumerate(scene.working_modes):
            if wm.selector == "heave":
                continue  # a rigid suspension mode: nothing to see in a picture
            modes = solve_modes(scene, near=wm.near, count=12, error_estimate=False)
            mode = select(modes, wm.selector, wm.near)
            path = args.out / (f"{name}.png" if k == 0 or len(scene.working_modes) == 1 else f"{name}_{k}.png")
            samples = []
            for _ in range(3):
                start = time.perf_counter()
                plotter = render_mode(mode, out=str(path), window_size=(1400, 520), view="iso+bottom")
                samples.append(time.perf_counter() - start)
                markers = sorted({m.group for m in plotter._modalfe["markers"]})
                plotter.close()
            print(f"{name:<16} {mode.label:<12} {mode.frequency:>10.1f} Hz  render {statistics.median(samples):.2f} s"
                  f"  -> {path}  marked: {', '.join(markers) or 'none'}")


if __name__ == "__main__":
    main()
