"""The feet of a device whose builder places them (the Cu-Be plate): where they are, how they print, and where the
antinodes of a mode of the device without them would put them (``modalfe.design.tuning``'s ``replace_feet``)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from modalfe.errors import SolverError
from modalfe.results.modes import select
from modalfe.solve.api import solve_modes

# feet are placed on the antinodes of ``placement.antinodes`` (0.5 mm grid, each peak refined by a parabola): a foot
# that would move by less than half a grid step is left where it is
FOOT_TOL = 0.25e-3


def feet_text(feet: Sequence[tuple[float, float]]) -> str:
    """``(x, y)`` of each foot in mm."""
    return " ".join(f"({1e3 * x:.2f}, {1e3 * y:.2f})" for x, y in feet) + " mm"


def has_feet(scene) -> bool:
    """Whether the scene's builder places feet (``replace_feet`` can be used)."""
    return "feet" in builder_parameters_of(scene)


def builder_parameters_of(scene) -> dict:
    from modalfe.geometry import builder_parameters

    return builder_parameters(scene.device) if scene.device != "boxes" else {}


def scene_feet(scene) -> tuple[tuple[float, float], ...]:
    """The scene's foot centres (x, y) [m] (its builder's default when not set)."""
    feet = scene.params.get("feet", builder_parameters_of(scene)["feet"].default)
    return tuple((float(x), float(y)) for x, y in feet)


def feet_on_mode_antinodes(scene, label: str, near: float) -> tuple[tuple[float, float], ...] | None:
    """The feet moved to the antinodes of the mode ``label`` of the device without feet (solved near ``near``
    [Hz]; ``placement.feet_on_antinodes``, without ``place_feet``'s re-solves with the feet: the antinodes of the
    mode with feet are pulled off each foot by the foot itself); None when no foot would move by more than
    ``FOOT_TOL``."""
    from modalfe.response.placement import feet_on_antinodes

    feet = scene_feet(scene)
    size = float(scene.params.get("foot_size", builder_parameters_of(scene)["foot_size"].default))
    bare = solve_modes(scene.with_overrides(feet=()), near=near, count=8, fidelity="solid", error_estimate=False)
    try:
        mode = select(bare, label, near)
    except SolverError as exc:
        raise SolverError(f"tune: the mode {label} of the device without feet is not found near {near:.6g} Hz "
                          f"({exc})") from None
    placed = feet_on_antinodes(mode, feet, part="plate", foot_size=size)
    moved = max(math.hypot(a - x, b - y) for (a, b), (x, y) in zip(placed, feet))
    return placed if moved > FOOT_TOL else None
