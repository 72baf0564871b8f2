"""Parts beyond boxes: cylinders (a disc is a short one), rings (tubes) and extruded 2-D outlines.

Each shape stands on an axis (``x``, ``y`` or ``z``) and spans ``height`` along it from its base. In-plane
coordinates (u, v) of the plane normal to the axis are cyclic: (y, z) for x, (z, x) for y, (x, y) for z.
Named faces: ``top`` and ``bottom`` (the planar ends, at base + height and base), ``outer`` (and ``inner``
for a ring) for cylindrical walls, ``side`` and ``hole_K`` (K = 1, 2... in the order of ``holes``) for an
extrusion's outline and hole walls. ``lo``/``hi`` are the bounding box, so the code that places, plots and
sizes parts by their extent reads shapes like boxes.

Poling: 0 (none), an axis ``+x``, ``-x``, ``+y``, ``-y``, ``+z``, ``-z`` (+1 and -1 mean ``+z`` and ``-z``), or
``radial`` / ``-radial`` (outward / inward from the axis), for rings only: on a full cylinder the radial
direction is undefined on its axis and no inner electrode can be laid, so a radially poled cylinder is refused.
Lengths in metres.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from modalfe.errors import SceneError

AXES = ("x", "y", "z")
POLINGS = ("+x", "-x", "+y", "-y", "+z", "-z", "radial", "-radial")


def normalized_poling(name: str, poling, radial_allowed: bool) -> int | str:
    """0 for an unpoled part, else one of ``POLINGS`` (+1 -> ``+z``, -1 -> ``-z``)."""
    if poling in (0, None, "", "0"):
        return 0
    if poling in (1, -1) and not isinstance(poling, bool):
        return "+z" if poling == 1 else "-z"
    if poling not in POLINGS:
        raise SceneError(f"part '{name}': poling must be 0, +1, -1 or one of {POLINGS}, got {poling!r}")
    if poling.endswith("radial") and not radial_allowed:
        raise SceneError(f"part '{name}': radial poling needs a ring (on a solid part the radial direction is "
                         f"undefined on its axis and there is no inner face for an electrode)")
    return poling


def _positive(name: str, field: str, value: float) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise SceneError(f"part '{name}': {field} must be positive and finite, got {value!r}")
    return float(value)


@dataclass(frozen=True)
class _Shape:
    """What cylinders, rings and extrusions share: axis, base point, height, poling and face classification."""

    @property
    def k(self) -> int:
        """Index of the axis."""
        return AXES.index(self.axis)

    @property
    def uv(self) -> tuple[int, int]:
        """Indices of the in-plane coordinates (cyclic after the axis)."""
        return (self.k + 1) % 3, (self.k + 2) % 3

    def _check_common(self) -> None:
        if self.axis not in AXES:
            raise SceneError(f"part '{self.name}': axis must be one of {AXES}, got {self.axis!r}")
        _positive(self.name, "height", self.height)

    @property
    def size(self) -> tuple[float, float, float]:
        return tuple(b - a for a, b in zip(self.lo, self.hi))

    @property
    def lo(self) -> tuple[float, float, float]:
        """Lowest corner of the bounding box [m]."""
        return self._bounds()[0]

    @property
    def hi(self) -> tuple[float, float, float]:
        """Highest corner of the bounding box [m]."""
        return self._bounds()[1]

    def _round_bounds(self, r: float):
        """Bounding box of a round part of outer radius ``r``."""
        (u, v), c = self.uv, self.centre
        return self._box(c[self.k], c[u] - r, c[u] + r, c[v] - r, c[v] + r)

    def _box(self, base: float, umin: float, umax: float, vmin: float, vmax: float):
        lo, hi = [0.0] * 3, [0.0] * 3
        (u, v), k = self.uv, self.k
        lo[k], hi[k] = base, base + self.height
        lo[u], hi[u], lo[v], hi[v] = umin, umax, vmin, vmax
        return tuple(lo), tuple(hi)

    def face(self, side: str):
        from modalfe.geometry.parts import Face

        if side not in self.sides:
            raise SceneError(f"part '{self.name}': face side must be one of {self.sides}, got '{side}'")
        return Face(self.name, side)

    def planar_face(self, side: str):
        """(normal axis, coordinate, lo, hi) of the bounding rectangle of a planar end (top, bottom); None for
        the walls (curved or many-sided)."""
        if side not in ("top", "bottom"):
            return None
        lo, hi = self.lo, self.hi
        return self.k, hi[self.k] if side == "top" else lo[self.k], lo, hi

    def face_bounds(self, side: str, window=None):
        """The bounding rectangle of a planar end; SceneError for a wall or a window (windows are box-only)."""
        if window is not None:
            raise SceneError(f"face window on '{self.name}.{side}': windows are for box parts only")
        rect = self.planar_face(side)
        if rect is None:
            raise SceneError(f"face '{self.name}.{side}' is not planar")
        return rect

    @property
    def poling_faces(self) -> tuple[str, str] | None:
        """The two faces an electric field across the poling runs between (None: no such pair)."""
        if not self.poling:
            return None
        if self.poling.endswith("radial"):
            return ("inner", "outer")
        return ("bottom", "top") if self.poling[1] == self.axis else None

    @property
    def poling_vector(self) -> np.ndarray | None:
        """Unit poling direction (3,), None for radial poling (it varies) or an unpoled part."""
        if not self.poling or self.poling.endswith("radial"):
            return None
        d = np.zeros(3)
        d[AXES.index(self.poling[1])] = 1.0 if self.poling[0] == "+" else -1.0
        return d

    def poling_directions(self, x: np.ndarray) -> np.ndarray:
        """Unit poling directions (..., 3) at points ``x`` (3, ...) [m]."""
        d = self.poling_vector
        if d is not None:
            return np.broadcast_to(d, (*x.shape[1:], 3)).copy()
        r = np.moveaxis(np.asarray(x, dtype=float), 0, -1) - np.asarray(self.centre)
        r[..., self.k] = 0.0
        sign = -1.0 if self.poling.startswith("-") else 1.0
        return sign * r / np.linalg.norm(r, axis=-1, keepdims=True)

    def _axial(self, points: np.ndarray) -> np.ndarray:
        return points[..., self.k] - self.lo[self.k]

    def side_of(self, point, tol: float) -> str | None:
        """The named face a point of the part's boundary lies on (within ``tol`` [m]), or None."""
        p = np.asarray(point, dtype=float)
        s = float(self._axial(p))
        if abs(s) <= tol:
            return "bottom"
        if abs(s - self.height) <= tol:
            return "top"
        return self._wall_of(p, tol)


@dataclass(frozen=True)
class _Round(_Shape):
    """What cylinders and rings share: walls round the axis at their ``radii`` (inner, outer) [m] (inner 0 for a
    cylinder), and ``cuts``: ((axis index, coordinate [m]), ...) of mirror planes through the axis that keep the part
    below them (``cut_below``: the half or quarter a symmetric model solves, ``Assembly.halved``). A cut part has a
    planar face ``cut_x`` (``cut_y``, ``cut_z``) on each plane."""

    walls = ("top", "bottom", "outer")

    @property
    def sides(self) -> tuple[str, ...]:
        return (*self.walls, *(f"cut_{AXES[a]}" for a, _ in self.cuts))

    def _bounds(self):
        lo, hi = self._round_bounds(self.radii[1])
        hi = list(hi)
        for a, plane in self.cuts:
            hi[a] = plane
        return lo, tuple(hi)

    @property
    def _kept(self) -> float:
        """Share of the whole round part the cuts keep: a half per plane through the axis."""
        return 0.5 ** len(self.cuts)

    @property
    def volume(self) -> float:
        inner, outer = self.radii
        return math.pi * (outer**2 - inner**2) * self.height * self._kept

    def area(self, side: str, window=None) -> float:
        self.face_bounds(side, window) if window is not None else self.face(side)
        inner, outer = self.radii
        if side in ("top", "bottom"):
            return math.pi * (outer**2 - inner**2) * self._kept
        if side.startswith("cut_"):  # a strip across the axis, on one side of it when the other plane cuts too
            return (outer - inner) * self.height * 2 ** (2 - len(self.cuts))
        return 2 * math.pi * (outer if side == "outer" else inner) * self.height * self._kept

    def planar_face(self, side: str):
        """(normal axis, coordinate, lo, hi) of the bounding rectangle of a planar end (top, bottom) or of a cut
        face; None for the round walls."""
        for a, plane in self.cuts:
            if side == f"cut_{AXES[a]}":
                return a, plane, self.lo, self.hi
        return super().planar_face(side)

    def inside(self, points: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Whether points (n, 3) [m] lie in the part, its surface widened by ``tol`` [m] (negative: narrowed)."""
        points = np.asarray(points, dtype=float)
        inner, outer = self.radii
        s, rho = self._axial(points), axis_distance(self, points)
        ok = (s >= -tol) & (s <= self.height + tol) & (rho <= outer + tol)
        if inner > 0:
            ok &= rho >= inner - tol
        for a, plane in self.cuts:
            ok &= points[..., a] <= plane + tol
        return ok

    def _wall_of(self, p, tol):
        for a, plane in self.cuts:
            if abs(float(p[a]) - plane) <= tol:
                return f"cut_{AXES[a]}"
        inner, outer = self.radii
        rho = float(axis_distance(self, p))
        if abs(rho - outer) <= tol:
            return "outer"
        return "inner" if inner > 0 and abs(rho - inner) <= tol else None

    def cut_below(self, axis: int, plane: float, tol: float) -> tuple[_Round, str]:
        """(the part below the plane x[axis] = ``plane`` [m], the side of its face on that plane), for a plane that
        crosses the part: normal to its axis (a shorter part, the face ``top``) or through its axis (a half, the face
        ``cut_<axis>``); SceneError for a plane along the axis off it (the cut part is then no mirror half) or one
        cut twice. ``tol`` [m]: how far off the axis a plane still passes through it."""
        if axis == self.k:
            return replace(self, height=plane - self.lo[axis]), "top"
        if abs(plane - self.centre[axis]) > tol:
            raise SceneError(f"symmetry: part '{self.name}' crosses the {AXES[axis]} mid-plane off its axis "
                             f"(centre {AXES[axis]} = {self.centre[axis]:g} m, plane at {plane:g} m): a round part "
                             f"is cut there only through its axis (drop the symmetry)")
        if any(a == axis for a, _ in self.cuts):
            raise SceneError(f"symmetry: part '{self.name}' is cut at the {AXES[axis]} mid-plane twice")
        return replace(self, cuts=(*self.cuts, (axis, float(plane)))), f"cut_{AXES[axis]}"


@dataclass(frozen=True)
class Cylinder(_Round):
    """A solid circular cylinder (a disc when short): ``centre`` (x, y, z) of its base [m], ``axis``,
    ``radius`` and ``height`` [m]; ``cuts`` see ``_Round``. Faces: top, bottom, outer (and cut_x... once cut)."""

    name: str
    region: str
    material: str
    centre: tuple[float, float, float]
    axis: str
    radius: float
    height: float
    poling: int | str = 0
    cuts: tuple[tuple[int, float], ...] = ()

    def __post_init__(self) -> None:
        self._check_common()
        _positive(self.name, "radius", self.radius)
        object.__setattr__(self, "poling", normalized_poling(self.name, self.poling, radial_allowed=False))

    @property
    def radii(self) -> tuple[float, float]:
        return 0.0, self.radius

    @property
    def thickness(self) -> float:
        return min(2 * self.radius, self.height)


@dataclass(frozen=True)
class Ring(_Round):
    """A ring or tube: ``centre`` of its base, ``axis``, ``inner`` and ``outer`` radii and ``height`` [m]; ``cuts``
    see ``_Round``. Faces: top, bottom, outer, inner (and cut_x... once cut). Poling may be ``radial`` or
    ``-radial``."""

    name: str
    region: str
    material: str
    centre: tuple[float, float, float]
    axis: str
    inner: float
    outer: float
    height: float
    poling: int | str = 0
    cuts: tuple[tuple[int, float], ...] = ()

    walls = ("top", "bottom", "outer", "inner")

    def __post_init__(self) -> None:
        self._check_common()
        _positive(self.name, "inner radius", self.inner)
        _positive(self.name, "outer radius", self.outer)
        if not self.inner < self.outer:
            raise SceneError(f"part '{self.name}': inner radius {self.inner:g} m must be below the outer "
                             f"radius {self.outer:g} m")
        object.__setattr__(self, "poling", normalized_poling(self.name, self.poling, radial_allowed=True))

    @property
    def radii(self) -> tuple[float, float]:
        return self.inner, self.outer

    @property
    def thickness(self) -> float:
        return min(self.outer - self.inner, self.height)


@dataclass(frozen=True)
class Extrusion(_Shape):
    """A 2-D polygon ``outline`` ((u, v) vertices [m] in the plane normal to ``axis``, see the module docstring),
    with optional polygon ``holes`` and round holes ``circles`` ((u, v, radius) [m] each), extruded from coordinate
    ``base`` along ``axis`` by ``height`` [m]. Faces: top, bottom, side (the outline's wall), hole_1, hole_2... (the
    holes' walls: the polygons first, then the circles)."""

    name: str
    region: str
    material: str
    outline: tuple[tuple[float, float], ...]
    axis: str
    base: float
    height: float
    holes: tuple[tuple[tuple[float, float], ...], ...] = ()
    poling: int | str = 0
    circles: tuple[tuple[float, float, float], ...] = ()

    def __post_init__(self) -> None:
        self._check_common()
        object.__setattr__(self, "outline", _polygon(self.name, "outline", self.outline))
        holes = tuple(_polygon(self.name, f"holes[{i}]", h) for i, h in enumerate(self.holes))
        object.__setattr__(self, "holes", holes)
        outer = np.array(self.outline)
        for i, hole in enumerate(holes):
            h = np.array(hole)
            if not _points_in_polygon(h, outer).all() or _edges_cross(h, outer):
                raise SceneError(f"part '{self.name}': holes[{i}] is not inside the outline")
            for j, other in enumerate(holes[:i]):
                o = np.array(other)
                if _edges_cross(h, o) or _points_in_polygon(h, o).any() or _points_in_polygon(o, h).any():
                    raise SceneError(f"part '{self.name}': holes[{i}] overlaps holes[{j}]")
        self._check_circles(outer, holes)
        if not math.isfinite(self.base):
            raise SceneError(f"part '{self.name}': base must be finite, got {self.base!r}")
        object.__setattr__(self, "poling", normalized_poling(self.name, self.poling, radial_allowed=False))

    def _check_circles(self, outer: np.ndarray, holes) -> None:
        """Round holes: positive radius, inside the outline, clear of the polygon holes and of each other."""
        circles = []
        for i, c in enumerate(self.circles):
            try:
                u, v, r = (float(x) for x in c)
            except (TypeError, ValueError):
                raise SceneError(f"part '{self.name}': circles[{i}] must be [u, v, radius]") from None
            _positive(self.name, f"circles[{i}] radius", r)
            centre = np.array([[u, v]])
            if not _points_in_polygon(centre, outer)[0] or _distance_to_loop(centre, outer)[0] <= r:
                raise SceneError(f"part '{self.name}': circles[{i}] is not inside the outline")
            for j, h in enumerate(holes):
                h = np.array(h)
                if _points_in_polygon(centre, h)[0] or _distance_to_loop(centre, h)[0] <= r:
                    raise SceneError(f"part '{self.name}': circles[{i}] overlaps holes[{j}]")
            for j, (u2, v2, r2) in enumerate(circles):
                if math.hypot(u - u2, v - v2) <= r + r2:
                    raise SceneError(f"part '{self.name}': circles[{i}] overlaps circles[{j}]")
            circles.append((u, v, r))
        object.__setattr__(self, "circles", tuple(circles))

    @property
    def sides(self) -> tuple[str, ...]:
        n = len(self.holes) + len(self.circles)
        return ("top", "bottom", "side", *tuple(f"hole_{i + 1}" for i in range(n)))

    def _bounds(self):
        o = np.array(self.outline)
        return self._box(self.base, o[:, 0].min(), o[:, 0].max(), o[:, 1].min(), o[:, 1].max())

    @property
    def section_area(self) -> float:
        return (_area(self.outline) - sum(_area(h) for h in self.holes)
                - sum(math.pi * r**2 for _, _, r in self.circles))

    @property
    def volume(self) -> float:
        return self.section_area * self.height

    @property
    def thickness(self) -> float:
        return min(self.height, min(self.size[i] for i in self.uv))

    def area(self, side: str, window=None) -> float:
        self.face_bounds(side, window) if window is not None else self.face(side)
        if side in ("top", "bottom"):
            return self.section_area
        if side == "side":
            return _perimeter(self.outline) * self.height
        k = int(side[5:]) - 1
        if k >= len(self.holes):
            return 2 * math.pi * self.circles[k - len(self.holes)][2] * self.height
        return _perimeter(self.holes[k]) * self.height

    def _uv(self, points: np.ndarray) -> np.ndarray:
        u, v = self.uv
        return np.stack([points[..., u], points[..., v]], axis=-1)

    def inside(self, points: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Whether points (n, 3) [m] lie in the part, its surface widened by ``tol`` [m] (negative: narrowed)."""
        points = np.asarray(points, dtype=float)
        s, q = self._axial(points), self._uv(points)
        ok = (s >= -tol) & (s <= self.height + tol) & _in_loop(q, np.array(self.outline), tol)
        for h in self.holes:
            ok &= ~_in_loop(q, np.array(h), -tol)
        for u, v, r in self.circles:
            ok &= np.hypot(q[..., 0] - u, q[..., 1] - v) >= r - tol
        return ok

    def _wall_of(self, p, tol):
        q = self._uv(p)[None]
        if _distance_to_loop(q, np.array(self.outline))[0] <= tol:
            return "side"
        for i, h in enumerate(self.holes):
            if _distance_to_loop(q, np.array(h))[0] <= tol:
                return f"hole_{i + 1}"
        for i, (u, v, r) in enumerate(self.circles):
            if abs(math.hypot(q[0, 0] - u, q[0, 1] - v) - r) <= tol:
                return f"hole_{len(self.holes) + i + 1}"
        return None


def axis_distance(shape, points) -> np.ndarray:
    """Distance [m] of points (..., 3) from the shape's axis."""
    u, v = shape.uv
    p = np.asarray(points, dtype=float)
    return np.hypot(p[..., u] - shape.centre[u], p[..., v] - shape.centre[v])


def _polygon(name: str, field: str, loop) -> tuple[tuple[float, float], ...]:
    """A simple polygon of at least 3 finite (u, v) vertices, no repeated closing vertex, positive area, listed
    counter-clockwise from its lowest (u, v) vertex."""
    try:
        pts = np.array([[float(a), float(b)] for a, b in loop])
    except (TypeError, ValueError):
        raise SceneError(f"part '{name}': {field} must be a list of [u, v] pairs") from None
    if len(pts) >= 2 and np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]
    if len(pts) < 3 or not np.all(np.isfinite(pts)):
        raise SceneError(f"part '{name}': {field} needs at least 3 finite vertices")
    scale = float(np.ptp(pts, axis=0).max())
    n = len(pts)
    seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    if seg.min() <= 1e-9 * scale:
        raise SceneError(f"part '{name}': {field} repeats a vertex")
    for i in range(n):
        for j in range(i + 1, n):
            if j in (i + 1, (i - 1) % n) or (i == 0 and j == n - 1):
                continue
            if _segments_cross(pts[i], pts[(i + 1) % n], pts[j], pts[(j + 1) % n]):
                raise SceneError(f"part '{name}': {field} intersects itself (edges {i} and {j})")
    if abs(_area(pts)) <= 1e-12 * scale**2:
        raise SceneError(f"part '{name}': {field} encloses no area")
    # one listing per polygon (counter-clockwise from its lowest-u, then lowest-v vertex): the same outline listed the
    # other way round or from another vertex is the same part, with the same mesh and cache key
    if np.dot(pts[:, 0], np.roll(pts[:, 1], -1)) < np.dot(pts[:, 1], np.roll(pts[:, 0], -1)):
        pts = pts[::-1]
    pts = np.roll(pts, -int(np.lexsort((pts[:, 1], pts[:, 0]))[0]), axis=0)
    return tuple((float(a), float(b)) for a, b in pts)


def _area(loop) -> float:
    """Absolute area of a polygon (shoelace formula)."""
    p = np.asarray(loop, dtype=float)
    x, y = p[:, 0], p[:, 1]
    return float(abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 2)


def _perimeter(loop) -> float:
    p = np.asarray(loop, dtype=float)
    return float(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1).sum())


def _segments_cross(a, b, c, d) -> bool:
    """Closed segments ab and cd have a point in common."""
    def orient(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    def on(p, q, r):
        return min(p[0], q[0]) <= r[0] <= max(p[0], q[0]) and min(p[1], q[1]) <= r[1] <= max(p[1], q[1])

    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return ((o1 == 0 and on(a, b, c)) or (o2 == 0 and on(a, b, d)) or (o3 == 0 and on(c, d, a))
            or (o4 == 0 and on(c, d, b)))


def _edges_cross(p: np.ndarray, q: np.ndarray) -> bool:
    """Some edge of polygon ``p`` meets some edge of polygon ``q``."""
    return any(_segments_cross(p[i], p[(i + 1) % len(p)], q[j], q[(j + 1) % len(q)])
               for i in range(len(p)) for j in range(len(q)))


def _points_in_polygon(points: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """Even-odd ray test of points (n, 2) against a polygon (m, 2)."""
    x, y = points[..., 0], points[..., 1]
    inside = np.zeros(x.shape, dtype=bool)
    for (x0, y0), (x1, y1) in zip(loop, np.roll(loop, -1, axis=0)):
        crosses = (y0 > y) != (y1 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
        inside ^= crosses & (x < xc)
    return inside


def _in_loop(points: np.ndarray, loop: np.ndarray, tol: float) -> np.ndarray:
    """Points (n, 2) inside a polygon widened by ``tol`` [m] (narrowed when negative)."""
    inside, d = _points_in_polygon(points, loop), _distance_to_loop(points, loop)
    return inside | (d <= tol) if tol >= 0 else inside & (d >= -tol)


def _distance_to_loop(points: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """Distance [m] of points (n, 2) to the nearest edge of a closed polygon (m, 2)."""
    a, b = loop, np.roll(loop, -1, axis=0)
    ab = b - a
    t = np.einsum("nmk,mk->nm", points[:, None, :] - a[None], ab) / np.einsum("mk,mk->m", ab, ab)
    foot = a[None] + np.clip(t, 0.0, 1.0)[..., None] * ab[None]
    return np.linalg.norm(points[:, None, :] - foot, axis=2).min(axis=1)


def shaped(*, parts: Sequence[Mapping], faces: Mapping[str, Sequence[str]] | None = None):
    """Assembly from part tables with shapes (``modalfe.scene.part_tables``: lengths already in metres) and face
    groups (group name -> ["part.side", ...], sides as the part's ``sides``)."""
    from modalfe.geometry.boxes import boxes
    from modalfe.geometry.parts import Assembly, face_ref

    built = []
    for spec in parts:
        spec = dict(spec)
        shape = spec.pop("shape", "box")
        spec.setdefault("region", spec["name"])
        if shape == "box":
            built.extend(boxes(parts=[spec]).parts)
            continue
        if "holes" in spec:
            spec["holes"] = tuple(tuple(tuple(p) for p in h) for h in spec["holes"])
        if "circles" in spec:
            spec["circles"] = tuple(tuple(c) for c in spec["circles"])
        if "outline" in spec:
            spec["outline"] = tuple(tuple(p) for p in spec["outline"])
        if "centre" in spec:
            spec["centre"] = tuple(spec["centre"])
        built.append({"cylinder": Cylinder, "ring": Ring, "extrusion": Extrusion}[shape](**spec))
    groups = {group: tuple(face_ref(group, ref) for ref in refs) for group, refs in (faces or {}).items()}
    return Assembly(tuple(built), groups)
