"""The Cu-Be plate with round feet (seeds 000/001 plate, ``foot_shape = "round"``) on swept hexahedra: its section is
cut by the box parts' grid (``modalfe.models.swept``), so the 0.4 mm gaps between the ceramics are strips of slivers
(as on the box grid), not of 0.4 mm squares that spread over the plate, and each foot's circle is an O-grid block
(``modalfe.models.section_blocks``); the coarser grids coarsen it; the answer's stated error (orders 2-3-4 on one
grid plus the walls' geometry bound) covers a finer solve."""

from __future__ import annotations

from dataclasses import replace

import pytest
from skfem.quadrature import get_quadrature

from modalfe.models.mesh import build_mesh, element_sizes
from modalfe.models.swept import section_mesh
from modalfe.scene import load_scene
from modalfe.solve.api import solve_modes
from modalfe.solve.estimates import MIN_RATIO
from modalfe.solve.rung import CHECK_FACTORS

SCENE = load_scene("cube_plate", foot_shape="round")


def _quads(factor: float) -> int:
    assembly = SCENE.assembly()
    sizes = {k: h * factor for k, h in element_sizes(SCENE).items()}
    return section_mesh(assembly, assembly.sweep_axis, sizes)[1].shape[1]


def test_round_feet_section_stays_structured_and_coarsens():
    # measured 264 quadrilaterals at the scene's sizes (the half plate, y symmetry), 402 with the feet's cells meshed
    # unstructured, 668 before the grid cut (the gaps' 0.4 mm squares spreading over the plate): 300 separates them
    fine, coarsest = _quads(1.0), _quads(CHECK_FACTORS[1])
    assert fine <= 300
    # the x2.25 grid must coarsen the section in both in-plane directions by MIN_RATIO at least, else an h-estimate
    # has no level (measured 264 / 132 = 2.0 >= 1.2^2 = 1.44; 402 / 254 with unstructured cells, 668 / 452 before)
    assert fine / coarsest >= MIN_RATIO**2


def test_round_feet_swept_hexahedra_are_not_folded():
    assembly = SCENE.assembly()
    dm = build_mesh(assembly, size=element_sizes(SCENE), element="hex", min_layers=SCENE.mesh.min_layers,
                    use_cache=False)
    X, _ = get_quadrature(dm.mesh.elem.refdom, 4)
    det = dm.mesh.mapping().detDF(X)
    # every element positively oriented at every Gauss point, the worst ratio in one element bounded away from 0 (the
    # same bound as tests/models/test_swept_mesh.py; a folded element reaches 0 or below)
    assert det.min() > 0
    assert (det.min(axis=1) / det.max(axis=1)).min() > 0.05


# finer references: both answers are quartic on the grid x3 with 1 layer (orders 2-3-4 on it; the round feet's plus
# the walls' geometry bound); the round feet's reference is cubic on x0.667 with 5 layers (187 092 DOFs), the square
# feet's quartic on x1.5 with 2 layers (elements halved in the plane and through the plate). Measured: round
# 39 692.03 Hz stated 0.375 % against 39 648.16 (0.111 % off; quartic on x1.5 with 2 layers gives 39 655.02; before
# the cells reached the box edges, ``Block.reaching``: 39 681.69 Hz stated 0.276 % on 42 049 DOFs), square
# 39 610.80 Hz stated 0.283 % against 39 583.65 (0.069 % off)
REFERENCES = {"round": {"order": 3, "elements_per_wavelength": 9.0, "min_layers": 5},
              "square": {"order": 4, "elements_per_wavelength": 4.0, "min_layers": 2}}


@pytest.mark.slow  # the round reference 187 092 DOFs, 28 s; the square one 70 365 DOFs, 13 s
@pytest.mark.parametrize("shape", ["round", "square"])
def test_working_mode_stated_error_covers_a_finer_solve(shape):
    """The (0,6) at tol 0.5 % (``modalfe modes cube_plate --near 40e3 --count 4 --fidelity solid``) against a finer
    solve of the same scene (``REFERENCES``): their difference must lie within the stated error (the promise of a
    stated error)."""
    scene = load_scene("cube_plate", foot_shape=shape)
    frequency, stated = _working_mode(scene, tol=5e-3)
    finer = replace(scene, mesh=replace(scene.mesh, **REFERENCES[shape]))
    reference, _ = _working_mode(finer, tol=None)
    assert abs(frequency - reference) / reference <= stated


def _working_mode(scene, *, tol: float | None) -> tuple[float, float]:
    """(frequency [Hz], stated relative error) of the (0,6) at ``tol`` (None: the scene's mesh once, no estimate); the
    modes and their model are dropped on return, so the reference solve does not hold the answer's matrices too."""
    modes = solve_modes(scene, near=40e3, count=4, fidelity="solid", error_estimate=tol is not None,
                        **({} if tol is None else {"tol": tol}))
    mode = modes.labelled("(0,6)")
    return mode.frequency, mode.error_estimate
