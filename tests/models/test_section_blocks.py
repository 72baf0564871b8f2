"""O-grid blocks for circles on a box grid's swept section (``modalfe.models.section_blocks``) and the bound on their
walls' geometry (``modalfe.models.wall_geometry``): over generated plates with a round foot, crossed or not by a
ceramic's edge, the section is quadrilaterals only, unfolded, area-exact to the quadratic arcs, with the circle's
nodes on it; the seed plate's round feet get blocks; the geometry bound covers what finer arcs change."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from modalfe.geometry.parts import Assembly, Box, Face
from modalfe.geometry.shapes import Cylinder
from modalfe.models import section_blocks, swept
from modalfe.models.section_blocks import BLOCK_CELL, blocks, chain_counts, loop_order
from modalfe.models.swept import section_mesh
from modalfe.scene import load_scene

# gmsh's 9-node quadrilateral: corners, mid-sides, centre at these reference points (modalfe.models.swept._QUAD9)
_QUAD9 = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0], [1, 0.5], [0.5, 1], [0, 0.5], [0.5, 0.5]])
_GAUSS = (np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)]) + 1) / 2  # 3-point Gauss-Legendre on [0, 1]
_WEIGHTS = np.array([5, 8, 5]) / 18


def _lagrange_1d(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and derivatives (3, n) of the quadratic Lagrange polynomials on the nodes 0, 1/2, 1 at ``t``."""
    values = np.array([(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)])
    slopes = np.array([4 * t - 3, 4 - 8 * t, 4 * t - 1])
    return values, slopes


def _jacobians(uv: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """det of the quadratic map of each quadrilateral at the 3 x 3 Gauss points (nq, 9) [m^2]."""
    node = np.rint(2 * _QUAD9).astype(int)  # each node's (i, j) on the 3 x 3 grid of 1-D nodes
    v, d = _lagrange_1d(_GAUSS)
    x, y = uv[0, quads], uv[1, quads]  # (9, nq)
    dets = []
    for a in range(3):
        for b in range(3):
            ds = d[node[:, 0], a] * v[node[:, 1], b]  # d/ds of each node's shape function
            dt = v[node[:, 0], a] * d[node[:, 1], b]
            dets.append((ds @ x) * (dt @ y) - (dt @ x) * (ds @ y))
    return np.array(dets).T


def _plate(foot: tuple[float, float], radius: float, edge: float | None) -> Assembly:
    """A 30 x 20 x 2 mm plate, a round foot of ``radius`` [m] under it at ``foot`` (x, y) [m], and on top a ceramic
    whose lower edge lies at y = ``edge`` [m] (None: no ceramic)."""
    plate = Box("plate", "plate", "steel", (0.0, 0.0, 0.0), (0.03, 0.02, 0.002))
    parts = [plate, Cylinder("foot", "foot", "steel", (*foot, -0.003), "z", radius, 0.003)]
    if edge is not None:
        parts.append(Box("ceramic", "piezo", "PZT-4", (0.002, edge, 0.002), (0.028, 0.018, 0.0025), poling=1))
    return Assembly(tuple(parts), {"tip": (Face("foot", "bottom"),)})


@settings(max_examples=12, deadline=None)
@given(x=st.floats(0.009, 0.021), y=st.floats(0.007, 0.013), radius=st.floats(0.001, 0.002),
       crossing=st.one_of(st.none(), st.floats(-0.4, 0.4)), size=st.sampled_from([0.002, 0.004, 0.012]))
def test_a_round_foot_on_a_plate_is_an_unfolded_area_exact_block(x, y, radius, crossing, size):
    """A ceramic edge crossing the foot's circle at up to 0.4 r from its centre is passed by the block's spokes
    (``BLOCK_CLEAR``): every generated case gets its block. Every quadrilateral's Jacobian is positive at its Gauss
    points; the section's area is the plate's to round-off (the foot's circle lies inside it; arcs shift area
    between the foot and the plate, not out of the section); the foot's own quadrilaterals hold its disc within the
    quadratic arcs' area error (1.2 % at four arcs a circle, ``ARC_ELEMENTS``; 2 % allowed); the circle's nodes lie
    on it to round-off."""
    assembly = _plate((x, y), radius, None if crossing is None else y + crossing * radius)
    found = blocks(assembly, 0, 1)
    half = BLOCK_CELL * radius
    assert len(found) == 1 and np.ravel(found[0].cell) == pytest.approx([x - half, y - half, x + half, y + half])
    uv, quads = section_mesh(assembly, 2, {"plate": size, "foot": size, "ceramic": size})
    det = _jacobians(uv, quads)
    assert det.min() > 0
    area = det @ np.kron(_WEIGHTS, _WEIGHTS)
    assert area.sum() == pytest.approx(0.03 * 0.02, rel=1e-9)
    centre = uv[:, quads[8]]
    inside = np.hypot(centre[0] - x, centre[1] - y) < radius
    assert area[inside].sum() == pytest.approx(math.pi * radius**2, rel=0.02)
    rim = np.abs(np.hypot(uv[0] - x, uv[1] - y) / radius - 1)
    assert np.sum(rim < 1e-9) >= 4  # the spokes' ends at least, all on the circle
    assert rim[rim < 1e-3].max() < 1e-9  # no node near the circle but off it


def test_the_seed_plates_round_feet_are_blocks_passing_the_ceramics_edge():
    """The Cu-Be plate's round feet (r 1.5 mm at y = 6 mm, the ceramics' edge at y = 6.5 mm: 0.33 r off the centre)
    each get a block whose inner rectangle is crossed by that edge; the section at the quartic answer's grid (x3) is
    measured 88 quadrilaterals (half plate: the cells reach out to the ceramics' edge at x = 25.6 mm, 38.4 mm and to
    the plate's edge at y = 0, ``Block.reaching``), against 114 with lines of their own there and 252 for the
    unstructured cells before the blocks."""
    scene = load_scene("cube_plate", foot_shape="round")
    assembly = scene.assembly()
    found = blocks(assembly, 0, 1)
    assert len(found) == 2
    for block in found:
        assert block.crossing[1] == pytest.approx((6.5e-3,))
        assert block.inner[1] > abs(6.5e-3 - block.centre[1])
    from modalfe.models.mesh import element_sizes

    sizes = {k: 3 * h for k, h in element_sizes(scene).items()}
    assert section_mesh(assembly, 2, sizes)[1].shape[1] <= 95  # 88 measured; 114 without reaching, 252 unstructured


def test_a_cell_reaches_out_to_a_box_edge_within_one_element(monkeypatch):
    """A box edge 3 r beside a foot's circle: without an element size the cell keeps its 1.5 r sides; with one, the
    side moves out onto the edge where the cell's sides and its outer spokes stay within that size (one element
    each, as the quarter arcs), so no line of the block's own runs through the whole lattice beside the edge. The
    section then has fewer quadrilaterals (measured 57 against 64 at 6 mm), unfolded and area-exact; at 4 mm the
    4.5 mm wide cell would need two elements a side: the side stays."""
    plate = Box("plate", "plate", "steel", (0.0, 0.0, 0.0), (0.03, 0.02, 0.002))
    foot = Cylinder("foot", "foot", "steel", (0.015, 0.01, -0.003), "z", 0.001, 0.003)
    pad = Box("pad", "pad", "steel", (0.018, 0.002, 0.002), (0.028, 0.018, 0.0025))
    assembly = Assembly((plate, foot, pad), {})
    (fixed,) = blocks(assembly, 0, 1)
    assert np.ravel(fixed.cell) == pytest.approx([0.0135, 0.0085, 0.0165, 0.0115])
    (reached,) = blocks(assembly, 0, 1, 0.006)
    assert np.ravel(reached.cell) == pytest.approx([0.0135, 0.0085, 0.018, 0.0115])
    assert blocks(assembly, 0, 1, 0.004) == [fixed]
    sizes = dict.fromkeys(("plate", "foot", "pad"), 0.006)
    uv, quads = section_mesh(assembly, 2, sizes)
    assert _jacobians(uv, quads).min() > 0
    assert (_jacobians(uv, quads) @ np.kron(_WEIGHTS, _WEIGHTS)).sum() == pytest.approx(0.03 * 0.02, rel=1e-9)
    monkeypatch.setattr(swept, "blocks", lambda assembly, u, v, size=None: section_blocks.blocks(assembly, u, v))
    assert quads.shape[1] < section_mesh(assembly, 2, sizes)[1].shape[1]


def test_edges_near_a_circle_move_its_cell_in_or_refuse_the_block():
    """Every box edge runs through the whole lattice: within the circle it is a crossing (the inner rectangle clears
    it), between the circle and the cell's side it moves the side in (not below ``BLOCK_CELL_LEAST`` r), and a circle
    crowded by another round part or with an edge too near its rim gets no block."""
    plate = Box("plate", "plate", "steel", (0.0, 0.0, 0.0), (0.03, 0.02, 0.002))
    foot = Cylinder("foot", "foot", "steel", (0.015, 0.01, -0.003), "z", 0.002, 0.003)
    pad = Box("pad", "pad", "steel", (0.0145, 0.01, 0.002), (0.03, 0.02, 0.0025))  # edges through the centre region
    (block,) = blocks(Assembly((plate, foot, pad), {}), 0, 1)
    assert block.crossing == ((0.0145,), (0.01,)) and block.inner[0] > 0.0005 and block.inner[1] > 0.0
    near = Box("near", "pad", "steel", (0.0, 0.0127, 0.002), (0.03, 0.02, 0.0025))  # 1.35 r above the centre
    (block,) = blocks(Assembly((plate, foot, near), {}), 0, 1)
    assert np.ravel(block.cell) == pytest.approx([0.0123, 0.0073, 0.0177, 0.0127]) and block.crossing == ((), ())
    for edge in (0.0122, 0.0115):  # 1.1 r: between the circle and the least cell; 0.75 r: too near the rim
        skin = Box("skin", "skin", "steel", (0.0, edge, 0.002), (0.03, 0.02, 0.0025))
        assert blocks(Assembly((plate, foot, skin), {}), 0, 1) == []
    other = Cylinder("other", "foot", "steel", (0.0185, 0.01, -0.003), "z", 0.001, 0.003)  # inside the cell
    assert blocks(Assembly((plate, foot, other), {}), 0, 1) == []


def test_chain_counts_share_one_count_along_opposite_sides():
    # two faces side by side: 1 (curves 1, 2, 3, 4) and 2 (curves 3, 5, 6, 7), sharing curve 3; opposite pairs
    # (1, 3), (2, 4) and (3, 6), (5, 7): the chain 1-3-6 takes its largest count, 4
    faces = {1: [1, 2, 3, 4], 2: [3, 5, 6, 7]}
    wanted = {1: 1, 2: 2, 3: 1, 4: 1, 5: 3, 6: 4, 7: 1}
    counts = chain_counts(faces, wanted)
    assert counts[1] == counts[3] == counts[6] == 4
    assert counts[2] == counts[4] == 2 and counts[5] == counts[7] == 3
    assert chain_counts({1: [1, 2, 3, 4, 5]}, {c: 1 for c in range(1, 6)}) is None


def test_loop_order_chains_the_curves_round_their_face():
    ends = {10: (1, 2), 11: (3, 4), 12: (2, 3), 13: (4, 1)}
    assert loop_order([10, 11, 12, 13], ends) == [10, 12, 11, 13]
    assert loop_order([10, 11], {10: (1,), 11: (1, 2)}) == [10, 11]  # a closed circle: left as given


def test_arc_elements_follow_the_arcs_angle():
    assert section_blocks.arc_elements(math.pi / 2 * 0.002, 1 / 0.002) == pytest.approx(
        section_blocks.ARC_ELEMENTS / 4)
