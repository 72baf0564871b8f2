"""Gmsh model of a box assembly, with physical groups named by part and by face role.

Two ways to build it:
- ``add_grid`` (structured hexahedra): the tensor grid of the break coordinates, built directly in
  gmsh's built-in kernel, one six-sided volume per grid cell inside a part. Neighbouring cells
  share their points, lines and faces by construction, so bonded parts share interface nodes with
  no boolean operation (an OCC fragment of the same cells took 0.7-1.4 s per mesh of the Cu-Be and
  tile devices);
- ``add_parts`` (tetrahedra): the parts as OCC solids (boxes, cylinders, rings, extruded outlines),
  fragmented so that touching parts share faces; a fragment claimed by two parts is an overlap.
The caller owns the gmsh session (``gmsh_session``).
"""

from __future__ import annotations

import contextlib
import itertools
import math

import numpy as np

from modalfe.errors import MeshError
from modalfe.geometry.parts import Assembly, Box

TOL = 1e-9


@contextlib.contextmanager
def gmsh_session(name: str = "modalfe"):
    """A fresh gmsh session (any left open is closed first) with a model ``name``, quiet and not installing its own
    Ctrl-C handler (modalfe's stays in charge), finalised on leaving. The user's gmsh option files (~/.gmshrc,
    ~/.gmsh-options) are not read: a mesh depends on its cache key's parameters only, so that every process
    sharing a cache builds the same one."""
    import gmsh

    if gmsh.isInitialized():
        gmsh.finalize()
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(name)
        yield
    finally:
        gmsh.finalize()


def grid_breaks(assembly: Assembly) -> list[np.ndarray]:
    """Sorted distinct box coordinates along x, y and z (part faces and face-window edges)."""
    out = []
    for k in range(3):
        coords = [v for p in assembly.parts for v in (p.lo[k], p.hi[k])]
        for faces in assembly.faces.values():
            for f in faces:
                if f.window is not None:
                    _, _, lo, hi = assembly.part(f.part).face_bounds(f.side, f.window)
                    coords += [lo[k], hi[k]]
        c = np.unique(coords)
        scale = c[-1] - c[0]
        keep = np.concatenate([[True], np.diff(c) > TOL * scale])
        out.append(c[keep])
    return out


def add_grid(assembly: Assembly, breaks: list[np.ndarray]) -> dict[str, list[int]]:
    """Add every grid cell of ``breaks`` that lies in a part as a built-in-kernel volume; physical
    groups as in ``add_physical_groups``. Returns part name -> volume tags."""
    import gmsh

    geo = gmsh.model.geo
    points: dict[tuple[int, int, int], int] = {}
    lines: dict[tuple[tuple[int, int, int], int], int] = {}
    surfaces: dict[tuple[tuple[int, int, int], int], int] = {}

    def step(node: tuple[int, int, int], axis: int) -> tuple[int, int, int]:
        return tuple(n + (k == axis) for k, n in enumerate(node))

    def point(node):
        if node not in points:
            points[node] = geo.addPoint(*(breaks[k][node[k]] for k in range(3)))
        return points[node]

    def line(node, axis: int) -> int:
        """The grid line from ``node`` one step along ``axis``."""
        if (node, axis) not in lines:
            lines[node, axis] = geo.addLine(point(node), point(step(node, axis)))
        return lines[node, axis]

    def surface(node, normal: int) -> int:
        """The grid face with lowest corner ``node`` and normal ``normal``."""
        if (node, normal) not in surfaces:
            u, v = (k for k in range(3) if k != normal)
            loop = geo.addCurveLoop([line(node, u), line(step(node, u), v), -line(step(node, v), u), -line(node, v)])
            surfaces[node, normal] = geo.addPlaneSurface([loop])
        return surfaces[node, normal]

    volumes: dict[str, list[int]] = {}
    for part in assembly.parts:
        ranges = []
        for k in range(3):
            scale = breaks[k][-1] - breaks[k][0]
            first = int(np.searchsorted(breaks[k], part.lo[k] - TOL * scale))
            last = int(np.searchsorted(breaks[k], part.hi[k] - TOL * scale))
            ranges.append(range(first, last))
        for node in itertools.product(*ranges):
            faces = [surface(n, axis) for axis in range(3) for n in (node, step(node, axis))]
            volumes.setdefault(part.name, []).append(geo.addVolume([geo.addSurfaceLoop(faces)]))
    geo.synchronize()
    add_physical_groups(assembly, volumes)
    return volumes


def add_parts(assembly: Assembly) -> dict[str, list[int]]:
    """Add the parts as OCC solids fragmented together (tetrahedral meshing); physical groups as in
    ``add_physical_groups``. Returns part name -> volume tags; MeshError when two parts share a volume
    (they interpenetrate)."""
    import gmsh

    occ = gmsh.model.occ
    tags = [(3, _occ_solid(occ, p)) for p in assembly.parts]
    if len(tags) > 1:
        _, children = occ.fragment(tags, [])
    else:
        children = [tags]  # nothing to glue: fragment would return no map
    occ.synchronize()
    volumes = {p.name: [t for d, t in child if d == 3] for p, child in zip(assembly.parts, children)}
    owner: dict[int, str] = {}
    for name, vols in volumes.items():
        for t in vols:
            if t in owner:
                raise MeshError(f"parts: '{owner[t]}' and '{name}' overlap (a volume of the mesh lies in both)")
            owner[t] = name
    add_physical_groups(assembly, volumes)
    return volumes


def _occ_solid(occ, part) -> int:
    """The OCC volume tag of one part: a box, a cylinder, a ring (cylinder minus its bore) or an extruded outline
    with holes (``modalfe.geometry.shapes``)."""
    from modalfe.geometry.shapes import Cylinder, Extrusion, Ring

    if isinstance(part, Box):
        return occ.addBox(*part.lo, *(h - l for l, h in zip(part.lo, part.hi)))
    along = [0.0, 0.0, 0.0]
    along[part.k] = part.height
    if isinstance(part, (Cylinder, Ring)):
        inner, outer = part.radii
        solid = occ.addCylinder(*part.centre, *along, outer)
        if inner > 0:
            solid = occ.cut([(3, solid)], [(3, occ.addCylinder(*part.centre, *along, inner))])[0][0][1]
        if not part.cuts:
            return solid
        box = occ.addBox(*part.lo, *(h - l for l, h in zip(part.lo, part.hi)))
        return occ.intersect([(3, solid)], [(3, box)])[0][0][1]  # the half (quarter) its cuts keep
    if isinstance(part, Extrusion):
        out = occ.extrude([(2, section_surface(occ, part, part.k, part.base))], *along)
        return next(t for d, t in out if d == 3)
    raise MeshError(f"part '{part.name}': unknown part type {type(part).__name__}")


def section_point(axis: int, level: float, a: float, b: float) -> list[float]:
    """(x, y, z) of the point (a, b) on the in-plane axes after ``axis`` (cyclically) at coordinate ``level``
    along it."""
    xyz = [0.0, 0.0, 0.0]
    xyz[axis], xyz[(axis + 1) % 3], xyz[(axis + 2) % 3] = level, a, b
    return xyz


def section_surface(occ, part, axis: int, level: float, seam: float = 0.0) -> int:
    """The OCC plane surface of a part's cross-section normal to ``axis`` (a shape's own axis; any axis for a box),
    placed at coordinate ``level`` along it: a rectangle, a disc, an annulus or an outline with its holes. A round
    part's circles start (their seam point) at the angle ``seam`` [rad] from the in-plane axis after ``axis``."""
    from modalfe.geometry.shapes import Cylinder, Extrusion, Ring

    u, v = (axis + 1) % 3, (axis + 2) % 3
    normal = [float(k == axis) for k in range(3)]

    def at(a: float, b: float) -> list[float]:
        return section_point(axis, level, a, b)

    def loop(points) -> int:
        corners = [occ.addPoint(*at(a, b)) for a, b in points]
        return occ.addCurveLoop([occ.addLine(p, q) for p, q in zip(corners, corners[1:] + corners[:1])])

    start = section_point(axis, 0.0, math.cos(seam), math.sin(seam)) if seam else []  # else OCC's own seam

    def circle(a: float, b: float, r: float) -> int:
        return occ.addCurveLoop([occ.addCircle(*at(a, b), r, zAxis=normal, xAxis=start)])

    (u0, v0), (u1, v1) = (part.lo[u], part.lo[v]), (part.hi[u], part.hi[v])
    rectangle = [(u0, v0), (u1, v0), (u1, v1), (u0, v1)]  # the bounding box's
    if isinstance(part, Box):
        loops = [loop(rectangle)]
    elif isinstance(part, (Cylinder, Ring)):
        loops = [circle(part.centre[u], part.centre[v], r) for r in reversed(part.radii) if r > 0]
    elif isinstance(part, Extrusion):
        loops = [loop(part.outline)] + [loop(h) for h in part.holes] + [circle(*c) for c in part.circles]
    else:
        raise MeshError(f"part '{part.name}': unknown part type {type(part).__name__}")
    surface = occ.addPlaneSurface(loops)
    if not getattr(part, "cuts", ()):
        return surface
    return occ.intersect([(2, surface)], [(2, occ.addPlaneSurface([loop(rectangle)]))])[0][0][1]  # a half (quarter)


def add_physical_groups(assembly: Assembly, volumes: dict[str, list[int]]) -> None:
    """One physical volume group per part (named after the part) and one physical surface group per
    named face group, found by the face's bounding box (box parts) or by classifying the part's boundary
    surfaces (other shapes, see ``shape_faces``)."""
    import gmsh

    for name, vols in volumes.items():
        gmsh.model.addPhysicalGroup(3, sorted(set(vols)), name=name)
    lo, hi = assembly.bounds
    scale = max(h - l for l, h in zip(lo, hi))
    classified = {name: shape_faces(assembly.part(name), volumes[name], 1e-5 * scale) for name in assembly.shaped}
    for group, faces in assembly.faces.items():
        surfaces: set[int] = set()
        for face in faces:
            if face.part in classified:
                surfaces.update(classified[face.part].get(face.side, ()))
                continue
            axis, c, flo, fhi = assembly.part(face.part).face_bounds(face.side, face.window)
            bmin = [flo[k] if k != axis else c for k in range(3)]
            bmax = [fhi[k] if k != axis else c for k in range(3)]
            eps = 1e-5 * scale  # OCC bounding boxes carry ~1e-7 m of tolerance
            found = gmsh.model.getEntitiesInBoundingBox(
                *(b - eps for b in bmin), *(b + eps for b in bmax), dim=2
            )
            surfaces.update(t for _, t in found)
        if not surfaces:
            raise MeshError(f"faces.{group}: no surface found on the named faces")
        gmsh.model.addPhysicalGroup(2, sorted(surfaces), name=group)


def shape_faces(part, vols: list[int], tol: float) -> dict[str, list[int]]:
    """Side name -> boundary surface tags of a non-box part's volumes: each surface is named by the point at the
    middle of its parametric range (on the surface, also for a closed cylindrical wall whose centre of mass is on
    the axis), ``part.side_of`` within ``tol`` [m]."""
    import gmsh

    out: dict[str, list[int]] = {}
    boundary = gmsh.model.getBoundary([(3, t) for t in vols], combined=False, oriented=False)
    for _, tag in dict.fromkeys(boundary):
        pmin, pmax = gmsh.model.getParametrizationBounds(2, tag)
        point = gmsh.model.getValue(2, tag, [(a + b) / 2 for a, b in zip(pmin, pmax)])
        side = part.side_of(point, tol)
        if side is not None:
            out.setdefault(side, []).append(tag)
    return out
