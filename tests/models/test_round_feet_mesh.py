"""The Cu-Be plate with round feet (seeds 000/001 plate, ``foot_shape = "round"``) on swept hexahedra: its section is
cut by the box parts' grid (``modalfe.models.swept``), so the 0.4 mm gaps between the ceramics are strips of slivers
(as on the box grid), not of 0.4 mm squares that spread over the plate; and the coarser estimate levels coarsen it."""

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
    # measured 402 quadrilaterals at the scene's sizes (the half plate, y symmetry); the unstructured section before
    # the grid cut had 668 (the gaps' 0.4 mm squares spreading over the plate): 450 separates the two
    fine, coarsest = _quads(1.0), _quads(CHECK_FACTORS[1])
    assert fine <= 450
    # the x2.25 estimate level must coarsen the section in both in-plane directions by MIN_RATIO at least, else the
    # h-estimate has no level (measured 402 / 254 = 1.58 >= 1.2^2 = 1.44; before: 668 / 452 at x2.25 and 686 at x1.5)
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


# finer references: the round feet's answer is quadratic swept hexahedra on the scene's grid x0.444 with 7 layers, its
# reference cubic on x0.667 with 5 layers (node spacing alike, one order higher); the square feet's answer is quartic on
# the grid x3 with 1 layer, its reference quartic on x1.5 with 2 layers (elements halved in the plane and through the
# plate). Measured: round 39 694.65 Hz stated 0.201 % against 39 643.71 (0.128 % off), square 39 610.80 Hz stated
# 0.283 % against 39 583.65 (0.069 % off)
REFERENCES = {"round": {"order": 3, "elements_per_wavelength": 9.0, "min_layers": 5},
              "square": {"order": 4, "elements_per_wavelength": 4.0, "min_layers": 2}}


@pytest.mark.slow  # both 323 s on 2 shared cores; the round reference alone 350 055 DOFs, 133 s
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
