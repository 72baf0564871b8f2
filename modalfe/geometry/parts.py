"""Box parts and named face groups: the pure-Python description every device builder returns.

A device is a set of axis-aligned boxes (plates, patches, bars, beams, feet, mounts), and possibly
cylinders, rings and extruded outlines (``modalfe.geometry.shapes``). Parts that touch are bonded.
Faces are named by role (``electrode_top``, ``clamp``, ``foot_1``...) so that the
same names reach the gmsh physical groups, the mesh, the model's DOF sets and the reports.
Lengths in metres.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from modalfe.errors import SceneError

SIDES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")


@dataclass(frozen=True)
class Box:
    """An axis-aligned box part.

    name : unique part name (``plate``, ``ceramic_3``, ``foot_1``)
    region : material role shared by several parts (``plate``, ``piezo``, ``foot``...)
    material : material name (see ``modalfe.scene.materials``)
    lo, hi : opposite corners [m]
    poling : +1 poled along +z, -1 along -z, 0 for a non-piezoelectric part
    """

    name: str
    region: str
    material: str
    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    poling: int = 0

    def __post_init__(self) -> None:
        for axis, (a, b) in enumerate(zip(self.lo, self.hi)):
            if not b - a > 0:
                raise SceneError(
                    f"part '{self.name}': size along {'xyz'[axis]} must be positive, got {b - a:g} m"
                )
        if self.poling not in (-1, 0, 1):
            raise SceneError(f"part '{self.name}': poling must be +1, -1 or 0")

    @property
    def size(self) -> tuple[float, float, float]:
        return tuple(b - a for a, b in zip(self.lo, self.hi))

    @property
    def volume(self) -> float:
        sx, sy, sz = self.size
        return sx * sy * sz

    def contains(self, point, tol: float = 0.0) -> bool:
        return all(a - tol <= p <= b + tol for p, a, b in zip(point, self.lo, self.hi))

    def inside(self, points: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Whether points (n, 3) [m] lie in the box widened by ``tol`` [m] (narrowed when negative)."""
        p = np.asarray(points, dtype=float)
        return np.all((p >= np.array(self.lo) - tol) & (p <= np.array(self.hi) + tol), axis=-1)

    sides = SIDES

    @property
    def thickness(self) -> float:
        """Smallest extent [m]."""
        return min(self.size)

    @property
    def poling_faces(self) -> tuple[str, str] | None:
        """The two faces the poling field runs between (None: unpoled)."""
        return ("zmin", "zmax") if self.poling else None

    @property
    def poling_vector(self) -> np.ndarray | None:
        """Unit poling direction (3,), None when unpoled."""
        return np.array([0.0, 0.0, float(self.poling)]) if self.poling else None

    def planar_face(self, side: str):
        """(normal axis, coordinate, lo, hi) of a face: every box face is a rectangle."""
        return self.face_bounds(side)

    def area(self, side: str, window=None) -> float:
        """Area [m^2] of one face (or of a window in it)."""
        axis, _, lo, hi = self.face_bounds(side, window)
        return float(np.prod([hi[k] - lo[k] for k in range(3) if k != axis]))

    def face(self, side: str) -> Face:
        if side not in SIDES:
            raise SceneError(f"part '{self.name}': face side must be one of {SIDES}, got '{side}'")
        return Face(self.name, side)

    def face_bounds(self, side: str, window=None) -> tuple[int, float, tuple, tuple]:
        """(normal axis, coordinate, lo, hi) of one face of the box, or of a window in it."""
        axis = "xyz".index(side[0])
        coordinate = self.lo[axis] if side.endswith("min") else self.hi[axis]
        if window is None:
            return axis, coordinate, self.lo, self.hi
        inplane = [k for k in range(3) if k != axis]
        lo, hi = list(self.lo), list(self.hi)
        for (k, a, b) in zip(inplane, window[0], window[1]):
            if not (self.lo[k] - 1e-12 <= a < b <= self.hi[k] + 1e-12):
                raise SceneError(f"face window on '{self.name}.{side}' lies outside the face along {'xyz'[k]}")
            lo[k], hi[k] = a, b
        return axis, coordinate, tuple(lo), tuple(hi)


@dataclass(frozen=True)
class Face:
    """One face of a part, by part name and side (``zmax`` is the top).

    ``window`` ((u0, v0), (u1, v1)) optionally restricts it to a rectangle, in the face's two
    in-plane coordinates in xyz order (x, y for a z face); the mesh puts grid lines on its edges.
    """

    part: str
    side: str
    window: tuple[tuple[float, float], tuple[float, float]] | None = None


def _window_below(face: Face, axis: int, mid: float, tol: float) -> Face | None:
    """``face`` with its window clipped to the half below ``mid`` along ``axis`` (an in-plane axis of the face),
    None where nothing of it is left."""
    j = [k for k in range(3) if k != "xyz".index(face.side[0])].index(axis)
    lo, hi = list(face.window[0]), list(face.window[1])
    if lo[j] >= mid - tol:
        return None
    hi[j] = min(hi[j], mid)
    return Face(face.part, face.side, (tuple(lo), tuple(hi)))


def face_ref(group: str, ref) -> Face:
    """A scene file's face reference: 'part.side', or {face = 'part.side', window = [[u0, v0], [u1, v1]]} [m]."""
    window = None
    if isinstance(ref, Mapping):
        window = tuple(tuple(float(c) for c in corner) for corner in ref["window"])
        ref = ref["face"]
    part, _, side = str(ref).rpartition(".")
    if not part:
        raise SceneError(f"faces.{group}: '{ref}' is not 'part.side'")
    return Face(part, side, window)


@dataclass(frozen=True)
class Assembly:
    """What a device builder returns: parts plus named face groups.

    faces : name -> faces, e.g. ``{"electrode_top": (Face("ceramic_1", "zmax"), ...)}``
    """

    parts: tuple  # Box, Cylinder, Ring or Extrusion
    faces: dict[str, tuple[Face, ...]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        names = [p.name for p in self.parts]
        if len(set(names)) != len(names):
            raise SceneError(f"parts: duplicate part names {sorted({n for n in names if names.count(n) > 1})}")
        if not self.parts:
            raise SceneError("parts: a device needs at least one part")
        by_name = {p.name: p for p in self.parts}
        for group, faces in self.faces.items():
            for f in faces:
                if f.part not in by_name:
                    raise SceneError(f"faces.{group}: unknown part '{f.part}'")
                try:
                    by_name[f.part].face(f.side)
                    if f.window is not None:
                        by_name[f.part].face_bounds(f.side, f.window)
                except SceneError as exc:
                    raise SceneError(f"faces.{group}: {exc}") from None
        _check_overlaps(self.parts)

    @property
    def shaped(self) -> tuple[str, ...]:
        """Names of the parts that are not boxes (cylinders, rings, extrusions): swept hexahedra (``sweep_axis``) or
        tetrahedra mesh them."""
        return tuple(p.name for p in self.parts if not isinstance(p, Box))

    @property
    def sweep_axis(self) -> int | None:
        """Index of the axis every cylinder, ring and extrusion stands on (boxes stand on any): the assembly is then
        a union of prisms along it (``modalfe.models.swept``); None when they stand on different axes or when every
        part is a box."""
        axes = {p.k for p in self.parts if not isinstance(p, Box)}
        return axes.pop() if len(axes) == 1 else None

    @property
    def thickness_axis(self) -> int:
        """Index of the axis through the device's thickness: the one its main part stands on (a disc, ring or
        extrusion), else the one its cylinders, rings and extrusions share, else z (box devices are laid out with
        their thickness along z: the plate and beam labels read w = u_z)."""
        main = self.main_part
        if not isinstance(main, Box) and getattr(main, "axis", None) in ("x", "y", "z"):
            return main.k
        return 2 if self.sweep_axis is None else self.sweep_axis

    def part(self, name: str) -> Box:
        for p in self.parts:
            if p.name == name:
                return p
        raise SceneError(f"no part named '{name}'")

    @property
    def main_part(self) -> Box:
        """The largest part by volume (the plate, the beam, the tile's core): the reference for element
        counts, label grids and the device's thickness."""
        return max(self.parts, key=lambda p: p.volume)

    @property
    def regions(self) -> dict[str, tuple[str, ...]]:
        """Region -> names of its parts."""
        out: dict[str, list[str]] = {}
        for p in self.parts:
            out.setdefault(p.region, []).append(p.name)
        return {k: tuple(v) for k, v in out.items()}

    def face_rect(self, face: Face) -> tuple | None:
        """(normal axis, coordinate, lo, hi) of a face's rectangle (a window's, or the bounding rectangle of a shape's
        planar end), None for a curved or many-sided wall."""
        part = self.part(face.part)
        return part.face_bounds(face.side, face.window) if face.window is not None else part.planar_face(face.side)

    def meeting_length(self, group_a: str, group_b: str) -> float | None:
        """Total length [m] of the lines where face groups ``group_a`` and ``group_b`` meet (an edge support's line),
        from the faces' rectangles: two faces meet on a line where their rectangles' intersection has length along one
        axis only (faces at an angle, or two windows side by side in one plane). None when a face has no rectangle (a
        curved wall: the mesh decides)."""
        bounds = self.bounds
        tol = 1e-9 * max(b - a for a, b in zip(*bounds))
        total = 0.0
        for fa in self.faces[group_a]:
            for fb in self.faces[group_b]:
                ra, rb = self.face_rect(fa), self.face_rect(fb)
                if ra is None or rb is None:
                    return None
                extent = [min(r[1] if k == r[0] else r[3][k] for r in (ra, rb))
                          - max(r[1] if k == r[0] else r[2][k] for r in (ra, rb)) for k in range(3)]
                if min(extent) >= -tol and sum(e > tol for e in extent) == 1:
                    total += max(extent)
        return total

    def face_area(self, group: str) -> float:
        """Area [m^2] of a face group, from the parts' exact shapes (windows included)."""
        return sum(self.part(f.part).area(f.side, f.window) for f in self.faces[group])

    def halved(self, axis: int) -> Assembly:
        """The half below the mid-plane normal to ``axis``, with the cut faces in group
        ``symmetry_<x|y|z>``: a box cut there keeps its ``xmax`` (``ymax``, ``zmax``) face on the plane, a cylinder or
        ring its ``top`` (the plane normal to its axis) or ``cut_x`` (``cut_y``, ``cut_z``: the plane through its axis,
        ``Cylinder.cut_below``); raises SceneError unless the assembly is mirror-symmetric, or where an extrusion
        crosses the plane."""
        lo, hi = self.bounds
        mid = 0.5 * (lo[axis] + hi[axis])
        scale = hi[axis] - lo[axis]
        tol = 1e-9 * scale

        def mirrored(p: Box) -> tuple:
            a, b = list(p.lo), list(p.hi)
            a[axis], b[axis] = 2 * mid - p.hi[axis], 2 * mid - p.lo[axis]
            return tuple(a), tuple(b)

        for p in self.parts:
            a, b = mirrored(p)
            if not any(q.material == p.material and q.poling == p.poling and np.allclose(q.lo, a, atol=tol)
                       and np.allclose(q.hi, b, atol=tol) and _profile(q) == _profile(p) for q in self.parts):
                raise SceneError(f"symmetry: part '{p.name}' has no mirror image about the {'xyz'[axis]} mid-plane")
        kept, cut = [], []
        for p in self.parts:
            if p.lo[axis] >= mid - tol:
                continue
            if p.hi[axis] > mid + tol:
                if isinstance(p, Box):
                    h = list(p.hi)
                    h[axis] = mid
                    p, side = Box(p.name, p.region, p.material, p.lo, tuple(h), p.poling), "xyz"[axis] + "max"
                elif hasattr(p, "cut_below"):  # a cylinder or ring (modalfe.geometry.shapes, which imports this)
                    p, side = p.cut_below(axis, mid, tol)
                else:
                    raise SceneError(f"symmetry: part '{p.name}' crosses the {'xyz'[axis]} mid-plane; only boxes, "
                                     f"cylinders and rings can be cut there (drop the symmetry)")
                cut.append(Face(p.name, side))
            kept.append(p)
        names = {p.name for p in kept}
        cut_side = {f.part: f.side for f in cut}
        faces = {}
        for group, entries in self.faces.items():
            inside = []
            for f in entries:
                if f.part not in names or cut_side.get(f.part) == f.side:
                    continue  # removed with the mirror half (a clipped part's far face is the cut)
                if f.window is not None and "xyz".index(f.side[0]) != axis:
                    f = _window_below(f, axis, mid, tol)
                    if f is None:
                        continue  # a window wholly in the mirror half
                inside.append(f)
            if inside:
                faces[group] = tuple(inside)
        if not cut:
            raise SceneError(f"symmetry: no part crosses the {'xyz'[axis]} mid-plane")
        faces[f"symmetry_{'xyz'[axis]}"] = tuple(cut)
        return Assembly(tuple(kept), faces)

    @property
    def bounds(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        lo = tuple(min(p.lo[i] for p in self.parts) for i in range(3))
        hi = tuple(max(p.hi[i] for p in self.parts) for i in range(3))
        return lo, hi

    @property
    def tolerance(self) -> float:
        """Length below which two coordinates are the same [m]: 1e-9 of the device's largest extent."""
        lo, hi = self.bounds
        return 1e-9 * max(b - a for a, b in zip(lo, hi))

    def holding(self, points: np.ndarray) -> np.ndarray:
        """(n, parts) whether each part holds each of ``points`` (3, n) [m], to ``tolerance`` (exact shapes: a ring's
        hole holds nothing)."""
        return np.stack([part.inside(points.T, self.tolerance) for part in self.parts], axis=1)

    def holders(self, points: np.ndarray) -> np.ndarray:
        """``holding``, and SceneError naming the first point no part holds (a probe or output off the device)."""
        inside = self.holding(points)
        if not inside.any(axis=1).all():
            x, y, z = points[:, np.argmin(inside.any(axis=1))]
            raise SceneError(f"points: ({x:g}, {y:g}, {z:g}) m lies outside the device's parts")
        return inside

    def components(self) -> list[tuple[str, ...]]:
        """The bonded groups of parts, largest first: parts sharing a face patch of positive area
        (``contact_area`` > 0) are bonded, through any chain of such patches. An edge or a corner
        bonds nothing (the mesh would join the parts along a line, a hinge of zero stiffness)."""
        tol = self.tolerance
        names = [p.name for p in self.parts]
        parent = list(range(len(names)))

        def root(i: int) -> int:
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for i, a in enumerate(self.parts):
            for j in range(i + 1, len(self.parts)):
                if _bonded(a, self.parts[j], tol):
                    parent[root(j)] = root(i)
        groups: dict[int, list[str]] = {}
        for i, n in enumerate(names):
            groups.setdefault(root(i), []).append(n)
        return sorted((tuple(g) for g in groups.values()), key=len, reverse=True)

    def check_connected(self) -> None:
        """Raise SceneError naming the parts not bonded to the device's main group (see ``components``)."""
        groups = self.components()
        if len(groups) == 1:
            return
        main = next(g for g in groups if self.main_part.name in g)
        loose = [n for g in groups if g is not main for n in g]
        tol = self.tolerance
        first = self.part(loose[0])
        near = [p.name for p in self.parts if p.name in main and _touching(first, p, tol)]
        how = (f"'{first.name}' touches '{near[0]}' only along an edge or at a corner" if near
               else f"'{first.name}' touches no part of it")
        shown = ", ".join(f"'{n}'" for n in loose[:6]) + (f" and {len(loose) - 6} more" if len(loose) > 6 else "")
        raise SceneError(f"parts: {shown} not bonded to '{self.main_part.name}' and the parts joined to it "
                         f"({how}); bonded parts must share a face patch of positive area")


def contact_area(a: Box, b: Box, tol: float = 0.0) -> float:
    """Area [m^2] of the face patch two boxes share: one of them ends where the other begins along one
    axis (within ``tol``) and they overlap by more than ``tol`` along the other two; 0 otherwise."""
    for axis in range(3):
        if abs(a.hi[axis] - b.lo[axis]) <= tol or abs(b.hi[axis] - a.lo[axis]) <= tol:
            others = [k for k in range(3) if k != axis]
            overlap = [min(a.hi[k], b.hi[k]) - max(a.lo[k], b.lo[k]) for k in others]
            if all(o > tol for o in overlap):
                return float(overlap[0] * overlap[1])
    return 0.0


def _profile(part) -> tuple:
    """What a part's bounding box does not say of its shape: its type and, for a shape, its axis and radii or
    section area (an extrusion's mirror image is matched by its box, section and height only)."""
    if isinstance(part, Box):
        return ("box",)
    dims = [getattr(part, k, None) for k in ("radius", "inner", "outer", "section_area")]
    return (type(part).__name__, part.axis, *(None if d is None else round(d, 12) for d in dims),
            tuple(a for a, _ in getattr(part, "cuts", ())))


def _bonded(a, b, tol: float) -> bool:
    """Two parts share a face patch of positive area. Boxes: ``contact_area``. With a shape: their bounding boxes
    meet on a plane (``contact_area`` > 0) and a 24 x 24 grid of points over that patch has a point in both parts
    (just off the plane on either side). A shape bonded only through a curved wall (a shaft in a ring's bore)
    is not recognised."""
    if isinstance(a, Box) and isinstance(b, Box):
        return contact_area(a, b, tol) > 0
    if contact_area(_bbox(a), _bbox(b), tol) <= 0:
        return False
    for axis in range(3):
        for below, above in ((a, b), (b, a)):
            if abs(below.hi[axis] - above.lo[axis]) > tol:
                continue
            others = [k for k in range(3) if k != axis]
            grids = [np.linspace(max(a.lo[k], b.lo[k]), min(a.hi[k], b.hi[k]), 26)[1:-1] for k in others]
            u, v = np.meshgrid(*grids, indexing="ij")
            points = np.zeros((u.size, 3))
            points[:, others[0]], points[:, others[1]] = u.ravel(), v.ravel()
            step = max(10 * tol, 1e-6 * max(max(a.size), max(b.size)))
            points[:, axis] = below.hi[axis] - step
            in_below = below.inside(points)
            points[:, axis] = above.lo[axis] + step
            if np.any(in_below & above.inside(points)):
                return True
    return False


def _bbox(part) -> Box:
    return part if isinstance(part, Box) else Box(part.name, part.region, part.material, part.lo, part.hi)


def _touching(a: Box, b: Box, tol: float) -> bool:
    """The closed boxes meet (a face, an edge or a corner in common)."""
    return all(min(a.hi[k], b.hi[k]) - max(a.lo[k], b.lo[k]) >= -tol for k in range(3))


def _check_overlaps(parts: tuple) -> None:
    """Bonded parts may touch but not interpenetrate. Two boxes overlap when their extents do; with a shape, when
    a point of a 16 x 16 x 16 grid over their common extent lies inside both, 1e-6 of their size inside their
    surfaces (an overlap thinner than the grid's step can pass here: the mesher finds it exactly, see
    ``modalfe.geometry.gmsh_model.add_parts``)."""
    for i, a in enumerate(parts):
        for b in parts[i + 1 :]:
            overlap = [min(a.hi[k], b.hi[k]) - max(a.lo[k], b.lo[k]) for k in range(3)]
            scale = max(max(a.size), max(b.size))
            if not all(o > 1e-9 * scale for o in overlap):
                continue
            if not (isinstance(a, Box) and isinstance(b, Box)):
                grids = [np.linspace(max(a.lo[k], b.lo[k]), min(a.hi[k], b.hi[k]), 18)[1:-1] for k in range(3)]
                points = np.stack(np.meshgrid(*grids, indexing="ij"), axis=-1).reshape(-1, 3)
                margin = -1e-6 * scale
                if not np.any(a.inside(points, margin) & b.inside(points, margin)):
                    continue
            raise SceneError(f"parts: '{a.name}' and '{b.name}' overlap")


def face_on_face(outer: Box, side: str, inner: Box, inner_side: str, name: str) -> None:
    """Raise unless face ``inner_side`` of ``inner`` lies within face ``side`` of ``outer``."""
    axis, c_out, _, _ = outer.face_bounds(side)
    _, c_in, _, _ = inner.face_bounds(inner_side)
    scale = max(outer.size)
    if abs(c_out - c_in) > 1e-9 * scale:
        raise SceneError(f"{name}: not on the {side} face of '{outer.name}'")
    for k in range(3):
        if k != axis and (inner.lo[k] < outer.lo[k] - 1e-9 * scale or inner.hi[k] > outer.hi[k] + 1e-9 * scale):
            raise SceneError(f"{name}: lies outside the {side} face of '{outer.name}' along {'xyz'[k]}")
