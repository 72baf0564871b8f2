"""Antinodes of a mode on a face, and feet placed on them (seeds 000, 001: feet at antinodes).

``place_feet`` moves each foot of the Cu-Be plate to the nearest antinode of the working mode that
is in phase with the others, keeps it inside the plate, re-solves with the feet, and reports the
frequency shift caused by the feet and by their contact stiffness against the substrate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalfe.errors import SolverError
from modalfe.results.modes import Mode


@dataclass(frozen=True)
class Antinode:
    """A local maximum of |w| on a face: position (x, y) [m] and signed normal displacement."""

    x: float
    y: float
    w: float


def face_field(mode: Mode, *, part: str, side: str = "zmin", spacing: float = 0.5e-3):
    """Normal displacement of ``mode`` on one face of a part (whole device, symmetry unfolded) on a
    grid of ``spacing`` [m]: returns (xs, ys, W)."""

    model = mode.model
    box = model.scene.full_assembly().part(part)
    axis, c, lo, hi = box.face_bounds(side)
    if axis != 2:
        raise SolverError("antinodes: only z faces (zmin, zmax) are supported")
    xs = np.linspace(lo[0], hi[0], max(8, round((hi[0] - lo[0]) / spacing) + 1))
    ys = np.linspace(lo[1], hi[1], max(8, round((hi[1] - lo[1]) / spacing) + 1))
    X, Y = np.meshgrid(xs, ys)
    points = np.vstack([X.ravel(), Y.ravel(), np.full(X.size, c)])
    w = (model.displacement_probes(points.T) @ mode.shape)[2 * X.size:]
    return xs, ys, w.reshape(X.shape)


def antinodes(mode: Mode, *, part: str, side: str = "zmin", threshold: float = 0.5,
              spacing: float = 0.5e-3) -> list[Antinode]:
    """Local maxima of |w| above ``threshold`` x the face's peak, strongest first.

    For a mode with nodal lines in one direction only, ``(0,n)`` or ``(m,0)``, the antinodes are
    ridges across the face: maxima are sought along x (or y) only, so every point of a ridge counts.
    """
    from scipy.ndimage import maximum_filter

    xs, ys, W = face_field(mode, part=part, side=side, spacing=spacing)
    A = np.abs(W)
    window = (5, 5)
    if mode.label.startswith("(0,") and not mode.label.startswith("(0,0"):
        window = (1, 5)  # nodal lines across x only: maxima along x
    elif mode.label.endswith(",0)") and not mode.label.startswith("(0,"):
        window = (5, 1)
    peaks = (maximum_filter(A, size=window, mode="nearest") == A) & (threshold * A.max() <= A)
    found = [Antinode(float(xs[j]), float(ys[i]), float(W[i, j])) for i, j in zip(*np.nonzero(peaks))]
    return sorted(found, key=lambda a: -abs(a.w))


@dataclass(frozen=True)
class FootPlacement:
    """Feet moved to antinodes and what they do to the working mode's frequency [Hz]."""

    feet: tuple[tuple[float, float], ...]
    moved_by: tuple[float, ...]
    frequency_without_feet: float
    frequency_with_feet: float
    frequency_in_contact: float
    contact_stiffness: float

    @property
    def shift_from_feet(self) -> float:
        return self.frequency_with_feet - self.frequency_without_feet

    @property
    def shift_from_contact(self) -> float:
        return self.frequency_in_contact - self.frequency_with_feet


def place_feet(scene, *, selector: str, near: float, contact_stiffness: float,
               part: str = "plate") -> FootPlacement:
    """Put the scene's feet on in-phase antinodes of the working mode (nearest to where they are),
    then re-solve with the feet free and with ``contact_stiffness`` [N/m] under each foot."""
    from modalfe.results.modes import select
    from modalfe.solve.api import solve_modes

    feet = tuple(scene.params.get("feet", _default_feet(scene)))
    if not feet:
        raise SolverError("place_feet: the scene has no feet")
    size = scene.params.get("foot_size", 3e-3)
    bare = scene.with_overrides(feet=())
    modes = solve_modes(bare, near=near, count=8, error_estimate=False)
    mode = select(modes, selector, near)
    candidates = antinodes(mode, part=part)
    box = scene.full_assembly().part(part)
    sign = np.sign(min(candidates, key=lambda a: np.hypot(a.x - feet[0][0], a.y - feet[0][1])).w)
    in_phase = [a for a in candidates if np.sign(a.w) == sign]
    placed, moved = [], []
    for x, y in feet:
        best = min(in_phase, key=lambda a: np.hypot(a.x - x, a.y - y))
        px = float(np.clip(best.x, box.lo[0] + size / 2, box.hi[0] - size / 2))
        py = float(np.clip(best.y, box.lo[1] + size / 2, box.hi[1] - size / 2))
        placed.append((px, py))
        moved.append(float(np.hypot(px - x, py - y)))
    with_feet = scene.with_overrides(feet=tuple(placed))
    f_feet = select(solve_modes(with_feet, near=near, count=8, error_estimate=False), selector, near).frequency
    springs = {f"springs.foot_{i}": [0.0, 0.0, contact_stiffness] for i in range(1, len(placed) + 1)}
    contact = with_feet.with_overrides(**springs)
    f_contact = select(solve_modes(contact, near=near, count=8, error_estimate=False), selector, near).frequency
    return FootPlacement(tuple(placed), tuple(moved), mode.frequency, f_feet, f_contact, contact_stiffness)


def _default_feet(scene):
    import inspect

    from modalfe.geometry import BUILDERS

    feet = inspect.signature(BUILDERS[scene.device]).parameters.get("feet")
    if feet is None:
        raise SolverError(f"place_feet: the scene's device '{scene.device}' has no feet parameter")
    return feet.default
