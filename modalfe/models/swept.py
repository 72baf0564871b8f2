"""Swept hexahedral meshes of assemblies whose parts all stand on one axis.

Discs, rings, extruded outlines and boxes are prisms: a cross-section swept along an axis. When every cylinder,
ring and extrusion of an assembly stands on the same axis (boxes stand on any), the device is the union of
prisms between the parts' ends, and it is meshed as such: the parts' cross-sections, fragmented together by gmsh
(OCC), are meshed with curved quadratic quadrilaterals (9 nodes, mid-side nodes on the circles), and each is swept
through element layers between the parts' end planes into 27-node hexahedra (skfem ``MeshHex2``); a prism cell
inside no part is left out. Elements are thin through the thickness and wide in the plane, like the structured
grid of box devices, where tetrahedra must be equilateral: a thin disc needs a few layers, not a few hundred
thousand tetrahedra, and the Gauss-Lobatto hexahedra of any order (``modalfe.models.hex_elements``) apply. Their
error is estimated from coarser grids, not from orders on one grid: the orders share this mesh's geometry
(``modalfe.solve.rung.Rung.uses_orders``).

Each hexahedron's geometry is the tensor product of its quadrilateral's quadratic map and a linear one along the
axis: exact on the end planes and walls parallel to the axis, a circle met at every node of the section mesh.
Face groups are found geometrically: a facet is on a part's named face when it borders an element of the part and
its centre node lies on that face (``Box.face_bounds``, ``side_of`` of the shapes).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from modalfe.errors import MeshError
from modalfe.geometry.parts import Box
from modalfe.models.section_blocks import Block, arc_elements, blocks, chain_counts, loop_order

# (xi, eta) of the nine nodes of gmsh's quadratic quadrilateral (element type 10): corners counter-clockwise,
# the mid-sides of edges 0-1, 1-2, 2-3, 3-0, the centre (gmsh reference manual, "Node ordering")
_QUAD9 = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0], [1, 0.5], [0.5, 1], [0, 0.5], [0.5, 0.5]])
_REVERSED = np.array([0, 3, 2, 1, 7, 6, 5, 4, 8])  # the same quadrilateral traversed clockwise
# at least this many elements round a full circle (gmsh Mesh.MeshSizeFromCurvature): quadratic arcs of 22.5 degrees,
# measured within 2.2e-6 of a disc's and a ring's exact volumes (tests/models/test_swept_mesh.py)
CIRCLE_ELEMENTS = 16
# a box grid line is cut into the section only this fraction of a curved part's extent clear of it: a line through or
# grazing a circle leaves slivers that fold the quadratic hexahedra (tests/models/test_swept_mesh.py)
LATTICE_CLEARANCE = 0.1
SIZE_RETRIES = (1.0, 0.97, 0.94, 0.91, 0.88, 0.85)  # size scales tried before a section is subdivided


def _quad_node(x: np.ndarray) -> int:
    """The node of gmsh's quadratic quadrilateral at reference (xi, eta) = ``x[:2]`` (0, 1/2 or 1 each)."""
    return int(np.flatnonzero((x[:2] == _QUAD9).all(axis=1))[0])


def swept_mesh(assembly, sizes: dict[str, float], layers: np.ndarray, breaks: np.ndarray):
    """(skfem MeshHex2, part name -> element indices, face group -> facet indices) of ``assembly`` swept along
    ``Assembly.sweep_axis``: the section meshed at the parts' sizes [m] (the smallest where parts overlap in
    section), the intervals between ``breaks`` (ascending axial coordinates of the parts' ends) split into
    ``layers`` each."""
    from skfem import MeshHex1, MeshHex2
    from skfem.refdom import RefHex

    axis = assembly.sweep_axis
    if axis is None:
        raise MeshError("mesh: the parts do not all stand on one axis; a swept hexahedral mesh needs them to")
    u, v = (axis + 1) % 3, (axis + 2) % 3
    nodes, quads = section_mesh(assembly, axis, sizes)
    levels = np.concatenate([np.linspace(a, b, n + 1)[:-1] for a, b, n in zip(breaks[:-1], breaks[1:], layers)]
                            + [breaks[-1:]])
    n_slabs = len(levels) - 1
    # the prism cell (quad q, slab s) belongs to the part containing its centre
    centre = np.zeros((quads.shape[1], n_slabs, 3))
    centre[..., u] = nodes[0, quads[8]][:, None]
    centre[..., v] = nodes[1, quads[8]][:, None]
    centre[..., axis] = (0.5 * (levels[:-1] + levels[1:]))[None, :]
    owner = np.full((quads.shape[1], n_slabs), -1)
    for i, part in reversed(list(enumerate(assembly.parts))):
        owner[part.inside(centre.reshape(-1, 3)).reshape(owner.shape)] = i
    q, s = np.nonzero(owner >= 0)
    corners = np.unique(quads[:4])
    corner_id = np.full(nodes.shape[1], -1)
    corner_id[corners] = np.arange(len(corners))
    t = np.stack([(s + int(x[2])) * len(corners) + corner_id[quads[_quad_node(x), q]] for x in RefHex.p.T])
    used, t = np.unique(t, return_inverse=True)
    t = t.reshape(8, -1)
    level_of, node_of = np.divmod(used, len(corners))
    p = np.zeros((3, len(used)))
    p[axis], p[u], p[v] = levels[level_of], nodes[0, corners[node_of]], nodes[1, corners[node_of]]
    straight = MeshHex2.from_mesh(MeshHex1(p, t))
    doflocs = straight.doflocs.copy()
    for j, x in enumerate(MeshHex2.elem.doflocs):  # each of the 27 nodes from its quadrilateral's own node
        k = _quad_node(x)
        at = np.zeros((3, len(q)))
        at[u], at[v] = nodes[0, quads[k, q]], nodes[1, quads[k, q]]
        at[axis] = levels[s] + x[2] * (levels[s + 1] - levels[s])
        doflocs[:, straight.dofs.element_dofs[j]] = at
    mesh = MeshHex2(doflocs, t)
    parts = {part.name: np.flatnonzero(owner[q, s] == i) for i, part in enumerate(assembly.parts)}
    return mesh, parts, _face_groups(mesh, assembly, parts)


def section_mesh(assembly, axis: int, sizes: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """(in-plane coordinates (2, n) [m], quadratic quadrilaterals (9, nq), counter-clockwise) of the parts'
    cross-sections normal to ``axis``, fragmented together and meshed by gmsh with quadrilaterals (Blossom
    recombination; subdivided when a triangle is left), each part's boundary points at its size."""
    import gmsh

    from modalfe.geometry.gmsh_model import gmsh_session, section_point, section_surface

    u, v = (axis + 1) % 3, (axis + 2) % 3
    with gmsh_session("modalfe-section"):
        occ = gmsh.model.occ
        grids = blocks(assembly, u, v, min(sizes.values()))
        seams = {block.part: block.angle for block in grids}  # a circle's seam at a spoke: no fifth side
        tags = [(2, section_surface(occ, p, axis, 0.0, seams.get(p.name, 0.0))) for p in assembly.parts]
        cells = _lattice_cells(occ, assembly, u, v, grids)
        spokes = [(1, occ.addLine(*(occ.addPoint(*section_point(axis, 0.0, *point)) for point in segment)))
                  for block in grids for segment in block.segments()]
        tools = cells + spokes
        children = occ.fragment(tags, tools)[1][:len(tags)] if len(tags) + len(tools) > 1 else [tags]
        occ.synchronize()
        structured = bool(grids) and _structure_blocks(min(sizes.values()))
        if cells and not structured:
            _structure_rectangles(min(sizes.values()))
        point_size: dict[int, float] = {}
        for part, child in zip(assembly.parts, children):
            faces = [(d, t) for d, t in child if d == 2]
            for d, t in gmsh.model.getBoundary(faces, combined=False, oriented=False, recursive=True):
                if d == 0:
                    point_size[t] = min(point_size.get(t, np.inf), sizes[part.name])
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", CIRCLE_ELEMENTS)
        gmsh.option.setNumber("Mesh.Algorithm", 8)  # frontal-Delaunay for quadrilaterals
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        # the grid's fixed counts leave Blossom a triangle in the cells cut by a circle: full-quad Blossom meshes at
        # half the counts (hence even ones) and subdivides, no triangle left
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 3 if cells and not structured else 1)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
        # Blossom leaves a triangle at some sizes (3.2-3.4 mm on a 10 mm disc with a 4 mm hub): the sizes are then
        # lowered step by step, and only failing that is the section meshed at twice the sizes and subdivided (each
        # triangle into three quadrilaterals, each quadrilateral into four). Subdividing at once gave 4x the nodes of
        # the neighbouring sizes (the interior and the 16 elements per circle are not halved by it: 1,777 nodes at
        # 3.4 mm where 3.5 mm gave 419 and 3.1 mm 459, issue 35); lowered by 3 %, 3.4 mm gives 455
        for scale in (*SIZE_RETRIES, 0.0):
            gmsh.model.mesh.clear()
            subdivide = scale == 0.0
            for t, h in point_size.items():
                gmsh.model.mesh.setSize([(0, t)], 2 * h if subdivide else scale * h)
            gmsh.option.setNumber("Mesh.MeshSizeMax", (2.0 if subdivide else scale) * max(sizes.values()))
            gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", int(subdivide))
            try:
                gmsh.model.mesh.generate(2)
            except Exception as exc:  # gmsh raises bare Exception
                raise MeshError(f"gmsh failed to mesh the parts' cross-section: {exc}") from exc
            types = set(gmsh.model.mesh.getElementTypes(2))
            if types == {10}:
                break
        else:
            raise MeshError(f"gmsh left elements of types {sorted(types - {10})} in the quadrilateral section mesh")
        tags_n, coords, _ = gmsh.model.mesh.getNodes()
        _, nodes_of = gmsh.model.mesh.getElementsByType(10)
    index = np.full(int(tags_n.max()) + 1, -1)
    index[tags_n.astype(int)] = np.arange(len(tags_n))
    xyz = coords.reshape(-1, 3).T
    quads = index[np.asarray(nodes_of, dtype=int)].reshape(-1, 9).T
    uv = xyz[[u, v]]
    c = uv[:, quads[:4]]  # (2, 4, nq)
    area = 0.5 * np.sum(c[0] * np.roll(c[1], -1, axis=0) - np.roll(c[0], -1, axis=0) * c[1], axis=0)
    quads[:, area < 0] = quads[_REVERSED][:, area < 0]
    return uv, quads


def _lattice_cells(occ, assembly, u: int, v: int, grids: list[Block]) -> list[tuple[int, int]]:
    """OCC rectangles of the box parts' grid (their faces' coordinates along ``u`` and ``v``, but those within
    ``LATTICE_CLEARANCE`` of a curved part) and of the O-grid blocks' cells (``grids``) over the boxes' extent:
    cut into the section, they split it into rectangles wherever no curved part lies, as the structured grid of box
    devices does (a 0.4 mm gap between ceramics becomes a strip of slivers, not of 0.4 mm squares)."""
    boxes = [p for p in assembly.parts if isinstance(p, Box)]
    if not boxes or (u, v) != (0, 1):
        return []  # OCC draws rectangles in z planes only: sections normal to x or y keep the unstructured mesh
    blocked = {block.part for block in grids}  # a block takes the lines near its circle (``section_blocks.blocks``)
    curved = [p for p in assembly.parts if not isinstance(p, Box) and p.name not in blocked]

    def clear(c: float, k: int) -> bool:  # a grid line that crosses or grazes no curved part (no sliver beside it)
        return all(not p.lo[k] - LATTICE_CLEARANCE * (p.hi[k] - p.lo[k]) < c
                   < p.hi[k] + LATTICE_CLEARANCE * (p.hi[k] - p.lo[k]) for p in curved)

    bounds = [(min(p.lo[k] for p in boxes), max(p.hi[k] for p in boxes)) for k in (u, v)]
    breaks = [np.unique([c for p in boxes for c in (p.lo[k], p.hi[k]) if clear(c, k) or c in bounds[i]]
                        + [c for block in grids for c in block.lines[i]])
              for i, k in enumerate((u, v))]
    if len(breaks[0]) + len(breaks[1]) == 4:
        return []  # no grid line inside the boxes: nothing to structure
    cells = []
    for a0, a1 in itertools.pairwise(breaks[0]):
        for b0, b1 in itertools.pairwise(breaks[1]):
            cells.append((2, occ.addRectangle(a0, b0, 0.0, a1 - a0, b1 - b0)))
    return cells


def _structure_rectangles(size: float) -> None:
    """Transfinite (structured) quadrilaterals on every section surface bounded by four straight lines; every curve
    split into an even number of elements (full-quad Blossom meshes at half the counts and subdivides): ceil(length /
    ``size``) rounded up, arcs at least ``CIRCLE_ELEMENTS`` a full circle. A side shared by two rectangles is split
    alike on both, a narrow rectangle gets slivers."""
    import gmsh

    for _, c in gmsh.model.getEntities(1):
        length, curvature = _curve_extent(c)
        n = length / size
        if curvature > 0.0:
            n = max(n, CIRCLE_ELEMENTS * length * curvature / (2 * np.pi))
        gmsh.model.mesh.setTransfiniteCurve(c, 2 * max(1, math.ceil(n / 2 - 1e-9)) + 1)
    for _, surface in gmsh.model.getEntities(2):
        curves = [abs(c) for _, c in gmsh.model.getBoundary([(2, surface)], oriented=False)]
        if len(curves) == 4 and all(gmsh.model.getType(1, c) == "Line" for c in curves):
            gmsh.model.mesh.setTransfiniteSurface(surface)


def _structure_blocks(size: float) -> bool:
    """Transfinite quadrilaterals on every section surface when each has four sides (the lattice's rectangles and
    the O-grid blocks' faces): each curve split into ceil(length / ``size``) elements, arcs at least
    ``ARC_ELEMENTS`` a full circle, one count for each chain of opposite sides (``chain_counts``). False, and
    nothing set, if a surface has other than four sides."""
    import gmsh

    wanted = {}
    for _, c in gmsh.model.getEntities(1):
        length, curvature = _curve_extent(c)
        n = length / size if curvature == 0.0 else max(length / size, arc_elements(length, curvature))
        wanted[c] = max(1, math.ceil(n - 1e-9))
    ends = {c: tuple(gmsh.model.getAdjacencies(1, c)[1]) for c in wanted}
    faces = {s: [abs(c) for _, c in gmsh.model.getBoundary([(2, s)], oriented=False)]
             for _, s in gmsh.model.getEntities(2)}
    counts = chain_counts({s: loop_order(curves, ends) for s, curves in faces.items()}, wanted)
    if counts is None:
        return False
    for c, n in counts.items():
        gmsh.model.mesh.setTransfiniteCurve(c, n + 1)
    for s in faces:
        gmsh.model.mesh.setTransfiniteSurface(s)
        gmsh.model.mesh.setRecombine(2, s)  # quadrilaterals made as such, not recombined from triangles
    return True


def _curve_extent(c: int) -> tuple[float, float]:
    """(length [m], largest curvature [1/m], 0 for a line) of the section curve ``c``, from 65 points on it."""
    import gmsh

    lo, hi = gmsh.model.getParametrizationBounds(1, c)
    t = np.linspace(lo[0], hi[0], 65)
    x = np.reshape(gmsh.model.getValue(1, c, t), (-1, 3))
    length = float(np.linalg.norm(np.diff(x, axis=0), axis=1).sum())
    if gmsh.model.getType(1, c) == "Line":
        return length, 0.0
    return length, float(np.max(gmsh.model.getCurvature(1, c, t)))


def _face_groups(mesh, assembly, parts: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Face group -> facets: those bordering an element of the face's part whose centre node lies on the face."""
    lo, hi = assembly.bounds
    tol = 1e-6 * max(b - a for a, b in zip(lo, hi))
    centres = mesh.doflocs[:, mesh.dofs.facet_dofs[0]]  # (3, nfacets): on the true (curved) face
    f2t = mesh.f2t
    out = {}
    for group, faces in assembly.faces.items():
        found = []
        for face in faces:
            part = assembly.part(face.part)
            mine = np.zeros(mesh.t.shape[1], dtype=bool)
            mine[parts[face.part]] = True
            borders = mine[f2t[0]] | ((f2t[1] >= 0) & mine[np.maximum(f2t[1], 0)])
            candidates = np.flatnonzero(borders)
            x = centres[:, candidates]
            if isinstance(part, Box):
                k, c, flo, fhi = part.face_bounds(face.side, face.window)
                on = np.abs(x[k] - c) <= tol
                for j in range(3):
                    if j != k:
                        on &= (x[j] >= flo[j] - tol) & (x[j] <= fhi[j] + tol)
            else:
                on = np.array([part.side_of(point, tol) == face.side for point in x.T], dtype=bool)
            found.append(candidates[on])
        out[group] = np.unique(np.concatenate(found)) if found else np.zeros(0, dtype=int)
    return out
