"""O-grid blocks: a circle on a box grid's swept section (a round foot or sensor under or on a plate) meshed by
structured quadrilaterals, as the grid around it is.

A circle standing alone in a square cell of the section's lattice (half-side ``BLOCK_CELL`` x its radius, or out to
the box edges near it where the elements are large: ``Block.reaching``) is cut
into nine four-sided faces: an inner rectangle, four faces between it and the circle, four between the circle and
the cell, split by spokes from the rectangle's corners through the circle to the cell's corners (the O-grid of
structured CFD and FE meshing, e.g. Thompson, Soni & Weatherill, Handbook of Grid Generation, 1999, ch. 4). A box
edge crossing the circle (a ceramic's edge over a foot) splits faces into four-sided ones as long as it crosses the
inner rectangle and the circle between the spokes: the spokes' angle and the rectangle are moved to make it so.
Every face then has four sides and is meshed transfinite, with one element count for each chain of opposite sides
(``chain_counts``): no unstructured patch, so no full-quad subdivision either, which doubled the counts of the whole
section (docs/studies.md, "Round feet").
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from modalfe.geometry.parts import Box
from modalfe.geometry.shapes import Cylinder

BLOCK_CELL = 1.5  # a circle's cell: half-side this x its radius (faces between circle and cell 0.5 r deep)
BLOCK_CELL_LEAST = 1.2  # ... or less where a box edge or the boxes' extent is nearer (a sensor by the plate's edge)
BLOCK_INNER = 0.5  # the inner rectangle's half-sides: this x the radius (spokes at 45 degrees) unless moved
BLOCK_CLEAR = 0.15  # x radius: the least distance from a crossing edge to a spoke's end or the rectangle's corner
# elements on a full circle's O-grid arcs: quadratic arcs of 45 degrees, radial error 7.2e-4 x radius (16: 4.6e-5)
ARC_ELEMENTS = 4


@dataclass(frozen=True)
class Block:
    """The O-grid of the circle of ``part``: ``centre`` (2,) [m] in the section plane, ``radius`` [m], the ``cell``
    ((u, v) of its low corner, of its high corner) [m], the spokes' ``angle`` [rad] above the u axis, the inner
    rectangle's half-sides ``inner`` (u, v) [m] and the box edges ``crossing`` the cell (u coordinates of lines
    u = c, v coordinates) [m]."""

    part: str
    centre: tuple[float, float]
    radius: float
    cell: tuple[tuple[float, float], tuple[float, float]]
    angle: float
    inner: tuple[float, float]
    crossing: tuple[tuple[float, ...], tuple[float, ...]] = ((), ())

    @property
    def lines(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The lattice lines the block needs (u coordinates, v coordinates) [m]: its cell's sides and the box edges
        crossing it, which run on through the whole lattice (an edge ending at the cell would leave its neighbours
        five-sided)."""
        (u0, v0), (u1, v1) = self.cell
        return (u0, u1, *self.crossing[0]), (v0, v1, *self.crossing[1])

    def segments(self) -> list[tuple[tuple[float, float], tuple[float, float]]]:
        """The block's own straight curves ((u, v) start, end) [m]: the inner rectangle's four sides, four spokes
        from its corners to the circle, four from the circle to the cell's corners."""
        inner, rim, cell = self._corners()
        sides = [(inner[i], inner[(i + 1) % 4]) for i in range(4)]
        return sides + list(zip(inner, rim)) + list(zip(rim, cell))

    def _corners(self) -> tuple[list, list, list]:
        """The (u, v) [m] of the inner rectangle's corners, the spokes' ends on the circle and the cell's corners,
        counter-clockwise from the first quadrant."""
        (a, b), r = self.centre, self.radius
        signs = ((1, 1), (-1, 1), (-1, -1), (1, -1))
        inner = [(a + su * self.inner[0], b + sv * self.inner[1]) for su, sv in signs]
        rim = [(a + su * r * math.cos(self.angle), b + sv * r * math.sin(self.angle)) for su, sv in signs]
        (u0, v0), (u1, v1) = self.cell
        return inner, rim, [(u1 if su > 0 else u0, v1 if sv > 0 else v0) for su, sv in signs]

    def reaching(self, lines: tuple[list, list], size: float, taken: list) -> Block:
        """This block with each side of its cell moved out to the nearest box edge beyond it (``lines``: u, v
        coordinates) where the cell's sides and the spokes from the circle to its corners stay within ``size`` [m]
        (one element each, as the circle's quarter arcs have) and the cell overlaps none of ``taken`` (u0, v0, u1,
        v1): a side of its own there would cut a line through the whole lattice beside that edge, a strip of
        elements across the section."""
        block = self
        for i, high in sorted(((i, high) for i in (0, 1) for high in (False, True)),
                              key=lambda side: self._beyond(lines, *side)[1]):
            edge, _ = block._beyond(lines, i, high)
            if edge is None:
                continue
            bounds = [list(block.cell[0]), list(block.cell[1])]
            bounds[int(high)][i] = edge
            moved = replace(block, cell=(tuple(bounds[0]), tuple(bounds[1])))
            _, rim, corners = moved._corners()
            spans = (bounds[1][0] - bounds[0][0], bounds[1][1] - bounds[0][1],
                     *(math.dist(p, q) for p, q in zip(rim, corners)))
            if max(spans) <= size and not _overlaps((*bounds[0], *bounds[1]), taken):
                block = moved
        return block

    def _beyond(self, lines: tuple[list, list], i: int, high: bool) -> tuple[float | None, float]:
        """(the nearest box edge beyond the cell's side ``high`` (else low) along axis ``i``, None if none; its
        distance from that side [m], inf if none)."""
        side = self.cell[int(high)][i]
        beyond = [c for c in lines[i] if (c > side if high else c < side)]
        if not beyond:
            return None, math.inf
        edge = min(beyond) if high else max(beyond)
        return edge, abs(edge - side)


def blocks(assembly, u: int, v: int, size: float | None = None) -> list[Block]:
    """The O-grid blocks of the assembly's section normal to the third axis: one for each whole circle (a cylinder
    standing on that axis, not cut) whose cell lies inside the boxes' extent, clear of every other round part and
    cell. Every box edge is a lattice line through the whole extent (``modalfe.models.swept``): one crossing the
    circle is passed by the spokes (else no block: too near the rim), one between the circle and the cell's side
    moves the side in to it, down to ``BLOCK_CELL_LEAST`` x the radius (else no block); the side also stops at the
    boxes' extent. With the element ``size`` [m], each cell then reaches out to the box edges near it
    (``Block.reaching``)."""
    boxes = [p for p in assembly.parts if isinstance(p, Box)]
    if not boxes:
        return []
    lo = [min(p.lo[k] for p in boxes) for k in (u, v)]
    hi = [max(p.hi[k] for p in boxes) for k in (u, v)]
    lines = [sorted({c for p in boxes for c in (p.lo[k], p.hi[k])}) for k in (u, v)]
    curved = [p for p in assembly.parts if not isinstance(p, Box)]
    found: list[Block] = []
    for part in curved:
        if not isinstance(part, Cylinder) or part.cuts or part.k in (u, v):
            continue
        centre, r = (part.centre[u], part.centre[v]), part.radius
        half = min(BLOCK_CELL * r, *(centre[i] - lo[i] for i in (0, 1)), *(hi[i] - centre[i] for i in (0, 1)))
        crossing: tuple[list, list] = ([], [])
        for i in (0, 1):
            for c in lines[i]:
                off = abs(c - centre[i])
                if off < r:
                    crossing[i].append(c)
                elif off < half:
                    half = off
        if half < BLOCK_CELL_LEAST * r * (1 - 1e-9):
            continue
        cell_lo = (centre[0] - half, centre[1] - half)
        cell_hi = (centre[0] + half, centre[1] + half)
        others = [(q.lo[u], q.lo[v], q.hi[u], q.hi[v]) for q in curved if q is not part]
        if _overlaps((*cell_lo, *cell_hi), others + [(*b.cell[0], *b.cell[1]) for b in found]):
            continue
        block = _fitted(part.name, centre, r, (cell_lo, cell_hi), crossing)
        if block is not None:
            found.append(block)
    if size is None:
        return found
    reached: list[Block] = []
    for k, block in enumerate(found):
        taken = [(q.lo[u], q.lo[v], q.hi[u], q.hi[v]) for q in curved if q.name != block.part]
        taken += [(*b.cell[0], *b.cell[1]) for b in (*reached, *found[k + 1:])]
        reached.append(block.reaching((lines[0], lines[1]), size, taken))
    return reached


def _overlaps(cell: tuple[float, float, float, float], others: list) -> bool:
    """Whether the rectangle ``cell`` (u0, v0, u1, v1) overlaps any of ``others`` (alike) by more than a side."""
    x0, y0, x1, y1 = cell
    return any(a0 < x1 and a1 > x0 and b0 < y1 and b1 > y0 for a0, b0, a1, b1 in others)


def all_blocked(assembly) -> bool:
    """Whether the assembly has boxes and each of its round parts is a block of its swept section: the whole section
    is then structured (every face four-sided, ``modalfe.models.swept``)."""
    axis = assembly.sweep_axis
    if axis is None or len(assembly.shaped) == len(assembly.parts):
        return False
    return len(blocks(assembly, (axis + 1) % 3, (axis + 2) % 3)) == len(assembly.shaped)


def _fitted(part: str, centre, r: float, cell, crossing) -> Block | None:
    """The block whose spokes and inner rectangle clear the ``crossing`` edges by ``BLOCK_CLEAR`` x r; None if none
    does (an edge off the circle, or too near its rim)."""
    across_u, across_v = (max((abs(c - centre[i]) for c in crossing[i]), default=0.0) for i in (0, 1))
    clear = BLOCK_CLEAR * r
    angle = math.pi / 4
    if r * math.sin(angle) < across_v + clear:
        angle = math.asin(min(1.0, (across_v + clear) / r))
    if r * math.cos(angle) < across_u + clear:
        angle = math.acos(min(1.0, (across_u + clear) / r))
    extent = (r * math.cos(angle), r * math.sin(angle))  # where the spokes meet the circle
    if extent[0] < across_u + clear or extent[1] < across_v + clear:
        return None
    inner = []
    for reach, across in zip(extent, (across_u, across_v)):
        side = min(max(BLOCK_INNER * math.sqrt(2) * reach, across + clear), reach - clear)
        if side < across + clear - 1e-12 * r:
            return None
        inner.append(side)
    return Block(part, tuple(centre), r, cell, angle, tuple(inner), tuple(tuple(c) for c in crossing))


def chain_counts(faces: dict[int, list[int]], wanted: dict[int, int]) -> dict[int, int] | None:
    """Element count of each curve for transfinite four-sided ``faces`` (face -> its four curves in order round
    it): opposite sides of a face carry one count, so each chain of opposite sides takes the largest count any
    curve of it ``wanted``. None if a face has not four curves."""
    parent = {c: c for c in wanted}

    def root(c: int) -> int:
        while parent[c] != c:
            parent[c] = parent[parent[c]]
            c = parent[c]
        return c

    for curves in faces.values():
        if len(curves) != 4:
            return None
        for a, b in ((curves[0], curves[2]), (curves[1], curves[3])):
            parent[root(a)] = root(b)
    largest: dict[int, int] = {}
    for c, n in wanted.items():
        largest[root(c)] = max(largest.get(root(c), 1), n)
    return {c: largest[root(c)] for c in wanted}


def loop_order(curves: list[int], ends: dict[int, tuple[int, ...]]) -> list[int]:
    """``curves`` of one closed loop in order round it, each curve's end points given by ``ends``; as given when
    they do not form a single chain (a face with a hole, a closed circle)."""
    if any(len(ends[c]) != 2 for c in curves):
        return curves
    ordered, rest = [curves[0]], set(curves[1:])
    point = ends[curves[0]][1]
    while rest:
        following = next((c for c in rest if point in ends[c]), None)
        if following is None:
            return curves
        ordered.append(following)
        rest.discard(following)
        a, b = ends[following]
        point = b if a == point else a
    return ordered


def arc_elements(length: float, curvature: float) -> float:
    """The elements an arc of ``length`` [m] and ``curvature`` [1/m] needs at ``ARC_ELEMENTS`` a full circle."""
    return ARC_ELEMENTS * length * curvature / (2 * np.pi)
