"""The box fast path of the solid assembly (modalfe/models/box_assembly.py) against the general path (on hexahedra
modalfe/models/mapped_assembly.py, itself checked against scikit-fem's forms in test_mapped_assembly.py).

On axis-aligned boxes the fast path uses the general path's quadrature and basis functions, only summed
in another order, so K and M agree to round-off: the difference of two sums of O(1e3) products of O(1)
terms, a few ulps of the norm, so 1e-12 (relative, Frobenius norm) catches any wrong orientation, scale or
material constant (each an O(1) error) with a large margin.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from modalfe.models import box_assembly
from modalfe.models.build import build_model
from modalfe.scene import load_scene
from modalfe.solve.api import solve_modes
from tests.oracles.cases import k31_bar_scene

# a generic rotation (Euler z-y-x 37, -23, 61 degrees): no box survives it
_z, _y, _x = np.radians([37.0, -23.0, 61.0])
ROTATION = (
    np.array([[np.cos(_z), -np.sin(_z), 0], [np.sin(_z), np.cos(_z), 0], [0, 0, 1]])
    @ np.array([[np.cos(_y), 0, np.sin(_y)], [0, 1, 0], [-np.sin(_y), 0, np.cos(_y)]])
    @ np.array([[1, 0, 0], [0, np.cos(_x), -np.sin(_x)], [0, np.sin(_x), np.cos(_x)]])
)


def _general_only(monkeypatch):
    """Route every element through the general path."""
    real = box_assembly.find_boxes

    def none(mesh, scalar, element_dofs, elements):
        boxes, _ = real(mesh, scalar, element_dofs, elements[:0])
        return boxes, elements

    monkeypatch.setattr(box_assembly, "find_boxes", none)


def _counting(monkeypatch) -> list[tuple[int, int]]:
    """Record (boxes, others) of every part that ``find_boxes`` splits."""
    real, seen = box_assembly.find_boxes, []

    def counted(mesh, scalar, element_dofs, elements):
        boxes, rest = real(mesh, scalar, element_dofs, elements)
        seen.append((boxes.dofs.shape[1], len(rest)))
        return boxes, rest

    monkeypatch.setattr(box_assembly, "find_boxes", counted)
    return seen


def _relative(A, B) -> float:
    return float(sla.norm(A - B) / sla.norm(B))


# cube_plate: a multi-part device (Cu-Be plate, PZT ceramics of both polings, feet); ciliary_beam with
# graded layers toward its clamp (mesh.clamp_grading): piezoelectric sheets on a brass beam
CASES = [("cube_plate", 4.0, {}), ("ciliary_beam", 3.0, {"mesh.clamp_grading": 3})]


# the quartic case (17 s on the Cu-Be plate) runs with -m slow: the cubic cases take the same fast path
@pytest.mark.parametrize(("order", "family"), [(1, "auto"), (2, "auto"), (2, "lagrange"), (3, "auto"),
                                               (3, "serendipity"), pytest.param(4, "auto", marks=pytest.mark.slow)])
@pytest.mark.parametrize(("name", "size_factor", "extra"), CASES)
def test_fast_path_matches_the_general_path(monkeypatch, name, size_factor, extra, order, family):
    from modalfe.models.build import forget_models

    scene = load_scene(name, **{"mesh.order": order, "mesh.family": family, **extra})
    forget_models()
    with monkeypatch.context() as m:
        seen = _counting(m)
        fast, _ = build_model(scene, size_factor=size_factor)
    assert all(rest == 0 for _, rest in seen) and sum(b for b, _ in seen) == fast.mesh.nelements
    forget_models()
    with monkeypatch.context() as m:
        _general_only(m)
        general, _ = build_model(scene, size_factor=size_factor)
    forget_models()
    assert fast.n_phi > 0 and np.array_equal(fast.phi_dofs, general.phi_dofs)
    assert _relative(fast.K, general.K) < 1e-12
    assert _relative(fast.M, general.M) < 1e-12
    n_u = fast.n_u  # the piezo blocks alone, so that the stiff elastic block does not hide them
    assert _relative(fast.K[:n_u, n_u:], general.K[:n_u, n_u:]) < 1e-12
    assert _relative(fast.K[n_u:, n_u:], general.K[n_u:, n_u:]) < 1e-12


@pytest.mark.parametrize("family", ["lagrange", "serendipity"])  # Gauss-Lobatto Q_3, the 32-node S_3
def test_a_rotated_frame_takes_the_general_path_with_the_same_frequencies(monkeypatch, family):
    scene = k31_bar_scene(2.0e-3)
    scene = dataclasses.replace(scene, mesh=dataclasses.replace(scene.mesh, order=3, family=family))
    seen = _counting(monkeypatch)
    rotated = solve_modes(scene, frame=ROTATION, error_estimate=False)
    assert seen and all(boxes == 0 for boxes, _ in seen)
    seen.clear()
    aligned = solve_modes(scene, error_estimate=False)
    assert seen and all(rest == 0 for _, rest in seen)
    f_rot = np.array([m.frequency for m in rotated])
    f_ali = np.array([m.frequency for m in aligned])
    assert f_rot == pytest.approx(f_ali, rel=1e-8)


def test_a_distorted_element_takes_the_general_path_beside_the_boxes(monkeypatch):
    from modalfe.models.solid import assemble

    scene = load_scene("ciliary_beam", **{"mesh.order": 3})
    model, _ = build_model(scene, size_factor=3.0)
    dm = model.mesh
    p = dm.mesh.p.copy()
    inner = np.flatnonzero(np.all((p > p.min(axis=1, keepdims=True)) & (p < p.max(axis=1, keepdims=True)), axis=0))
    vertex = inner[0]
    p[:, vertex] += 1e-3 * np.ptp(p, axis=1) / np.sqrt(dm.nelements)  # a small shift of one interior vertex
    distorted = dataclasses.replace(dm, mesh=type(dm.mesh)(p, dm.mesh.t))
    touching = int(np.any(dm.mesh.t == vertex, axis=0).sum())
    with monkeypatch.context() as m:
        seen = _counting(m)
        mixed = assemble(scene, distorted)
    assert sum(rest for _, rest in seen) == touching > 0
    with monkeypatch.context() as m:
        _general_only(m)
        general = assemble(scene, distorted)
    assert _relative(mixed.K, general.K) < 1e-12
    assert _relative(mixed.M, general.M) < 1e-12


@pytest.mark.parametrize("overrides", [{}, {"mesh.element": "tet"}])
def test_face_springs_and_masses_from_the_scalar_face_mass_equal_the_vector_form(overrides):
    """``solid._face_operator`` assembles int_face u v ds once and spreads it over the three components
    (kron with diag(d)); the vector form sum_c d_c u_c v_c assembled directly must equal it to round-off, on box
    hexahedra and on tetrahedra, with three different weights (a swapped component would show)."""
    from skfem import BilinearForm, ElementVector

    from modalfe.models import solid
    from modalfe.models.facets import facet_basis

    scene = load_scene("tile_eq5", **overrides)
    model, _ = build_model(scene, "solid")
    scalar = solid.element_for(scene.mesh)
    d = np.array([1.0, 2.0, 5.0])

    @BilinearForm
    def weighted(u, v, _):
        return d[0] * u[0] * v[0] + d[1] * u[1] * v[1] + d[2] * u[2] * v[2]

    for group in ("side_x", "side_y"):
        direct = weighted.assemble(facet_basis(model.mesh.mesh, ElementVector(scalar), model.mesh.faces[group],
                                               intorder=4))
        spread = solid._face_operator(model.mesh, group, scalar, 4, d)
        assert spread.shape == direct.shape
        assert abs(spread - direct).max() <= 1e-12 * abs(direct).max()
