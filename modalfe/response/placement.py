"""Antinodes of a mode on a face, and feet placed on them (seeds 000, 001: feet at antinodes).

``feet_on_antinodes`` moves each foot to the nearest antinode of a mode that is in phase with the others and
keeps it inside the plate (the one rule ``place_feet`` and ``modalfe.design.tuning`` use); ``place_feet`` does
it for the working mode of the Cu-Be plate, re-solves with the feet, and reports the frequency shift caused by
the feet and by their contact stiffness against the substrate.
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


def face_field(mode: Mode, *, part: str, side: str = "zmin", spacing: float = 0.5e-3,
               window: tuple[tuple[float, float], tuple[float, float]] | None = None):
    """Normal displacement of ``mode`` on one face of a part (whole device, symmetry unfolded) on a
    grid of ``spacing`` [m] (over ``window``, ((x0, y0), (x1, y1)) [m], clipped to the face, where given): returns
    (xs, ys, W)."""

    model = mode.model
    box = model.scene.full_assembly().part(part)
    axis, c, lo, hi = box.face_bounds(side)
    if axis != 2:
        raise SolverError("antinodes: only z faces (zmin, zmax) are supported")
    if window is not None:
        lo, hi = np.maximum(lo[:2], window[0]), np.minimum(hi[:2], window[1])
    xs = np.linspace(lo[0], hi[0], max(8, round((hi[0] - lo[0]) / spacing) + 1))
    ys = np.linspace(lo[1], hi[1], max(8, round((hi[1] - lo[1]) / spacing) + 1))
    X, Y = np.meshgrid(xs, ys)
    points = np.vstack([X.ravel(), Y.ravel(), np.full(X.size, c)])
    w = (model.displacement_probes(points.T) @ mode.shape)[2 * X.size:]
    return xs, ys, w.reshape(X.shape)


def ridge_axis(label: str) -> int | None:
    """For a mode with nodal lines in one direction only, the axis its antinode ridges are sought along: 0 (x)
    for ``(0,n)``, whose ridges run across the plate along y; 1 (y) for ``(m,0)``; None for other modes."""
    if label.startswith("(0,") and not label.startswith("(0,0"):
        return 0
    if label.endswith(",0)") and not label.startswith("(0,"):
        return 1
    return None


def peaks(xs: np.ndarray, ys: np.ndarray, W: np.ndarray, *, along: int | None = None,
          threshold: float = 0.5) -> list[Antinode]:
    """Local maxima of |W| (rows: ``ys``, columns: ``xs``), strongest first, each refined between grid points by
    the parabola through it and its two neighbours along each searched axis.

    ``along`` None: 2-D maxima (5 x 5 window) above ``threshold`` x the face's peak. ``along`` 0 (1): maxima
    along x (y) only, each row (column) of the grid against ``threshold`` x its own peak: a ridge's strength
    varies along it (measured on the whole Cu-Be plate, 36.8 mm wide: the (0,6) ridge near x = 20 mm falls to
    0.44 of the face's peak, which sits at the free ends, on the row y = 32 mm, yet stays at >= 0.58 of each
    row's peak), so a single threshold over the face cut the ridge where a foot sits."""
    from scipy.ndimage import maximum_filter

    A = np.abs(W)
    window = {None: (5, 5), 0: (1, 5), 1: (5, 1)}[along]
    top = A.max() if along is None else A.max(axis=1 - along, keepdims=True)  # the face's, or each line's, peak
    found = (maximum_filter(A, size=window, mode="nearest") == A) & (threshold * top <= A) & (A > 0)
    out = []
    for i, j in zip(*np.nonzero(found)):
        x = _vertex(xs, A[i, :], j) if along in (None, 0) else float(xs[j])
        y = _vertex(ys, A[:, j], i) if along in (None, 1) else float(ys[i])
        out.append(Antinode(x, y, float(W[i, j])))
    return sorted(out, key=lambda a: -abs(a.w))


def _vertex(grid: np.ndarray, values: np.ndarray, k: int) -> float:
    """The abscissa of the maximum of the parabola through ``values`` at k - 1, k, k + 1 (uniform ``grid``),
    kept within half a grid step of grid[k]; grid[k] itself at the grid's ends."""
    if k == 0 or k == len(grid) - 1:
        return float(grid[k])
    a, b, c = values[k - 1], values[k], values[k + 1]
    curvature = a - 2 * b + c
    shift = 0.0 if curvature >= 0 else float(np.clip(0.5 * (a - c) / curvature, -0.5, 0.5))
    return float(grid[k] + shift * (grid[1] - grid[0]))


def antinodes(mode: Mode, *, part: str, side: str = "zmin", threshold: float = 0.5,
              spacing: float = 0.5e-3) -> list[Antinode]:
    """Antinodes of ``mode`` on a face (``peaks`` of its ``face_field``), strongest first: for a mode with nodal
    lines in one direction only, ``(0,n)`` or ``(m,0)``, ridges across the face (``ridge_axis``), a point on each
    row (column) of the grid."""
    xs, ys, W = face_field(mode, part=part, side=side, spacing=spacing)
    return peaks(xs, ys, W, along=ridge_axis(mode.label), threshold=threshold)


def feet_on_antinodes(mode: Mode, feet, *, part: str, foot_size: float) -> tuple[tuple[float, float], ...]:
    """Each foot (x, y) [m] moved to the nearest antinode of ``mode`` on ``part``'s underside in phase with the
    one nearest the first foot, its footprint (``foot_size`` [m] square) kept inside the part. On a ridge mode
    (``ridge_axis``) every point of a ridge is an antinode: a foot moves across the ridges only, to the nearest
    ridge point of its own grid row (column), keeping its y (x)."""
    along = ridge_axis(mode.label)
    found = antinodes(mode, part=part)
    if not found:
        raise SolverError(f"antinodes: mode {mode.label} has none on '{part}'")

    def nearest(candidates, foot: tuple[float, float]) -> tuple[float, float, float]:
        """(x, y, w) of the antinode the foot goes to."""
        if along is None:
            a = min(candidates, key=lambda a: np.hypot(a.x - foot[0], a.y - foot[1]))
            return a.x, a.y, a.w
        keep = 1 - along  # the coordinate along the ridges, kept
        line = min({(a.x, a.y)[keep] for a in candidates}, key=lambda c: abs(c - foot[keep]))
        a = min((a for a in candidates if (a.x, a.y)[keep] == line),
                key=lambda a: abs((a.x, a.y)[along] - foot[along]))
        to = [a.x, a.y]
        to[keep] = foot[keep]
        return to[0], to[1], a.w

    feet = [(float(x), float(y)) for x, y in feet]
    sign = np.sign(nearest(found, feet[0])[2])
    in_phase = [a for a in found if np.sign(a.w) == sign]
    box = mode.model.scene.full_assembly().part(part)
    placed = []
    for foot in feet:
        px, py, _ = nearest(in_phase, foot)
        placed.append((float(np.clip(px, box.lo[0] + foot_size / 2, box.hi[0] - foot_size / 2)),
                       float(np.clip(py, box.lo[1] + foot_size / 2, box.hi[1] - foot_size / 2))))
    return tuple(placed)


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
               part: str = "plate", **resolution) -> FootPlacement:
    """Put the scene's feet on in-phase antinodes of the working mode (nearest to where they are),
    then re-solve with the feet free and with ``contact_stiffness`` [N/m] under each foot; each solve the 3-D solid
    that ``modes`` answers that scene with at ``resolution`` (``solve_modes``' tol, fidelity, error_estimate)."""
    from modalfe.results.modes import select
    from modalfe.solve.api import solid_modes, working_question

    def working(device):  # the mode as ``modes`` answers the device's question about it
        modes = solid_modes(device, needs="foot placement", **working_question(device, selector, near), **resolution)
        return select(modes, selector, near)

    feet = tuple(scene.params.get("feet", _default_feet(scene)))
    if not feet:
        raise SolverError("place_feet: the scene has no feet")
    size = scene.params.get("foot_size", 3e-3)
    bare = scene.with_overrides(feet=())
    mode = working(bare)
    placed = feet_on_antinodes(mode, feet, part=part, foot_size=size)
    moved = [float(np.hypot(px - x, py - y)) for (px, py), (x, y) in zip(placed, feet)]
    with_feet = scene.with_overrides(feet=tuple(placed))
    f_feet = working(with_feet).frequency
    springs = {f"springs.foot_{i}": [0.0, 0.0, contact_stiffness] for i in range(1, len(placed) + 1)}
    contact = with_feet.with_overrides(**springs)
    f_contact = working(contact).frequency
    return FootPlacement(tuple(placed), tuple(moved), mode.frequency, f_feet, f_contact, contact_stiffness)


def _default_feet(scene):
    import inspect

    from modalfe.geometry import BUILDERS

    feet = inspect.signature(BUILDERS[scene.device]).parameters.get("feet")
    if feet is None:
        raise SolverError(f"place_feet: the scene's device '{scene.device}' has no feet parameter")
    return feet.default
