"""Verification of the 32-node cubic serendipity hexahedron (``ElementHexS3``, modalfe/models/hex_elements.py):
its space, node matching between elements of any local orientation, the linear-elasticity patch test, the
observed order of the eigenvalue error against the exact 3-D plate mode, the DOFs it needs for 0.1 % on a thin
plate mode against the Lagrange elements, and the scene setting that selects it (``mesh.family``).

Round-off bounds as in tests/models/test_hex_elements.py: sums of O(1) terms, after a sparse solve a few hundred
ulps, so 1e-10 separates round-off from the smallest genuine error here (> 1e-8).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from skfem import Basis

from modalfe.errors import SceneError
from modalfe.models.hex_elements import ElementHexGLL, ElementHexS3, dof_locations
from modalfe.solve.api import OWN_MESH
from tests.models.test_hex_elements import (
    THICK,
    THIN,
    box,
    elasticity,
    locations,
    messy_box,
    plate_eigenvalue,
    reoriented,
)


def _monomials_of_s3() -> list[tuple[int, int, int]]:
    """The 32 monomials of S_3 written out by hand (Arnold & Awanou 2011: superlinear degree <= 3)."""
    cubic = [e for e in itertools.product(range(4), repeat=3) if sum(e) <= 3]  # 20
    quartic = [(3, 1, 0), (3, 0, 1), (1, 3, 0), (0, 3, 1), (1, 0, 3), (0, 1, 3), (2, 1, 1), (1, 2, 1), (1, 1, 2)]
    quintic = [(3, 1, 1), (1, 3, 1), (1, 1, 3)]
    return cubic + quartic + quintic


def test_space_is_the_cubic_serendipity_space():
    elem = ElementHexS3()
    assert sorted(map(tuple, elem.exponents.tolist())) == sorted(_monomials_of_s3())
    assert len(elem.doflocs) == 32 and elem.facet_dofs == 0 and elem.interior_dofs == 0
    X = elem.doflocs.T
    values = np.array([elem.lbasis(X, i)[0] for i in range(32)])
    assert np.abs(values - np.eye(32)).max() < 1e-12  # Lagrange basis on its nodes: round-off of a 32 x 32 inverse


def test_partition_of_unity_on_a_distorted_reoriented_mesh():
    b = Basis(messy_box(seed=41), ElementHexS3(), intorder=6)
    assert np.abs(sum(np.asarray(f[0]) for f in b.basis) - 1).max() < 1e-12
    assert np.abs(sum(f[0].grad for f in b.basis)).max() < 1e-10


def test_s3_polynomials_are_interpolated_exactly_across_reoriented_boxes():
    """On box elements (affine maps) every monomial of S_3 in x is in the element's space: the nodal interpolant
    is exact at random points of every element, with the elements' local orientations (reflections included)
    scrambled, so a mismatched edge node shows at once (it would break continuity and exactness)."""
    mesh = reoriented(box((3, 2, 2), (1.0, 0.8, 0.6)), seed=5)
    rng = np.random.default_rng(3)
    powers = _monomials_of_s3()
    coef = rng.normal(size=len(powers))

    def f(x):
        return sum(c * x[0] ** i * x[1] ** j * x[2] ** k for c, (i, j, k) in zip(coef, powers))

    elem = ElementHexS3()
    b = Basis(mesh, elem, intorder=6)
    u = f(dof_locations(b))
    X = rng.uniform(0, 1, size=(3, mesh.nelements, 7))
    tind = np.arange(mesh.nelements)
    x = b.mapping.F(X, tind=tind)
    value = sum(u[b.element_dofs[i]][:, None] * np.asarray(elem.gbasis(b.mapping, X, i, tind=tind)[0])
                for i in range(b.Nbfun))
    assert np.abs(value - f(x)).max() < 1e-11 * np.abs(u).max()
    # and a monomial outside S_3 is not reproduced (the check can fail)
    u2 = (dof_locations(b)[0] * dof_locations(b)[1]) ** 2
    value2 = sum(u2[b.element_dofs[i]][:, None] * np.asarray(elem.gbasis(b.mapping, X, i, tind=tind)[0])
                 for i in range(b.Nbfun))
    assert np.abs(value2 - (x[0] * x[1]) ** 2).max() > 1e-4


def test_patch_test_linear_elasticity():
    """A linear displacement prescribed on the boundary of a distorted, reoriented mesh is reproduced inside:
    S_3 holds Q_1, so x (Q_1 in the reference coordinates of a trilinear element) is in the space."""
    mesh = messy_box(seed=33, n=(2, 2, 2))
    elem = ElementHexS3()
    K, _ = elasticity(mesh, elem, E=2.0, nu=0.3, rho=1.0, intorder=6)
    x = locations(mesh, elem)
    A = np.array([[0.3, -0.2, 0.5], [0.1, 0.4, -0.3], [-0.6, 0.2, 0.1]])
    exact = (A @ x + np.array([[0.1], [-0.2], [0.3]])).T.ravel()
    fixed_nodes = np.flatnonzero(np.any((x < 1e-12) | (x > 1 - 1e-12), axis=0))
    fixed = (3 * fixed_nodes[:, None] + np.arange(3)).ravel()
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    u = exact.copy()
    u[free] = sla.spsolve(K[free][:, free].tocsc(), -K[free][:, fixed] @ exact[fixed])
    assert len(free) > 0
    assert np.abs(u - exact).max() < 1e-10


def test_eigenvalue_error_order():
    """Eigenvalue error ~ h^6 for a smooth mode, the order of Q_3 (S_3 holds the complete cubics; Babuska &
    Osborn 1991, thm. 10.1). Thick plate (1,1) mode (a/h = 5), elements halved then thirded (r = 1, 2, 3):

        errors 3.55e-4, 4.93e-6, 4.24e-7: observed orders 6.17, 6.05

    Band 6 +- 0.4: an element one order off (4 or 8) or with a lost order falls outside."""
    errors = [abs(plate_eigenvalue(ElementHexS3(), (2 * r, 2 * r, r), **THICK)[1]) for r in (1, 2)]
    order = math.log(errors[0] / errors[1]) / math.log(2)
    print(f"S3: errors {errors}, observed order {order:.2f}")
    assert abs(order - 6) < 0.4


def test_fewer_dofs_than_lagrange_cubic_to_a_tenth_of_a_percent():
    """Thin plate (3,3) mode (a/h = 50), eighth model, the coarsest (nx, round(0.75 nx), 1) mesh at 0.1 %:
    S3 (8, 6, 1) 1248 free DOFs (error 6.8e-4), where Q3 needs (5, 4, 1) 1800 (test_hex_elements.py); one
    element coarser, (7, 5, 1), S3 is above 0.1 %. Two layers through the thickness, (8, 6, 2), also reach it
    but with 2256 DOFs."""
    count, error = plate_eigenvalue(ElementHexS3(), (8, 6, 1), **THIN)
    _, coarser = plate_eigenvalue(ElementHexS3(), (7, 5, 1), **THIN)
    lagrange, lagrange_error = plate_eigenvalue(ElementHexGLL(3), (5, 4, 1), **THIN)
    print(f"S3 {count} DOFs {error:.2e} (one coarser {coarser:.2e}); Q3 {lagrange} DOFs {lagrange_error:.2e}")
    assert abs(error) < 1e-3 < abs(coarser)
    assert abs(lagrange_error) < 1e-3
    assert count < 0.75 * lagrange


def test_the_scene_selects_the_family():
    from modalfe.models.solid import element_for
    from modalfe.scene import load_scene

    def element(**settings):
        return element_for(load_scene("cube_plate", **{f"mesh.{k}": v for k, v in settings.items()}).mesh)

    assert type(element(order=2)).__name__ == "ElementHexS2"  # auto: serendipity at order 2
    assert type(element(order=3)) is ElementHexGLL  # auto: Lagrange above
    assert type(element(order=3, family="serendipity")) is ElementHexS3
    assert type(element(order=2, family="lagrange")) is ElementHexGLL
    with pytest.raises(SceneError, match=r"mesh\.family: serendipity elements are hexahedra of order 1 to 3"):
        load_scene("cube_plate", **{"mesh.order": 4, "mesh.family": "serendipity"})
    with pytest.raises(SceneError, match=r"mesh\.family"):
        load_scene("cube_plate", **{"mesh.family": "hermite"})


def test_size_estimate_counts_the_nodes_of_each_family():
    """The pre-meshing size estimate (modalfe/models/estimate.py) against the assembled model's DOFs."""
    from modalfe.models.build import build_model
    from modalfe.models.estimate import estimate_size
    from modalfe.scene import scene_from_dict

    for order, family in ((2, "auto"), (3, "serendipity"), (3, "lagrange"), (4, "lagrange")):
        scene = scene_from_dict({
            "name": "bar", "kind": "plate",
            "parts": [{"name": "bar", "material": "CuBe", "origin": [0, 0, 0], "size": [20e-3, 6e-3, 2e-3]}],
            "analysis": {"near": 3e4, "count": 2},
            "mesh": {"order": order, "family": family, "min_layers": 1},
        })
        model, _ = build_model(scene)
        estimate = estimate_size(scene)
        assert estimate.dofs == pytest.approx(model.n_u, rel=0.05), (order, family)


def test_states_no_error_estimate():
    """Its h-estimate was short on coarse clamped grids (modalfe/solve/rung.py ``UNVERIFIED``): a solve gives
    the frequencies with no stated error (infinite, said), and solves no estimate level for it."""
    import math

    from modalfe.solve import rung
    from modalfe.solve.api import solve_modes
    from tests.oracles.cases import k31_bar_scene

    scene = k31_bar_scene(3e-3)
    serendipity = scene.with_overrides(**{"mesh.order": 3, "mesh.family": "serendipity"})
    modes = solve_modes(serendipity, fidelity="solid", tol=OWN_MESH)
    assert modes.estimate_method == rung.UNVERIFIED
    assert all(math.isinf(m.error_estimate) for m in modes)
    lagrange = solve_modes(scene.with_overrides(**{"mesh.order": 3}), fidelity="solid", tol=OWN_MESH)
    assert lagrange.estimate_method.startswith("h-refinement")
    assert any(math.isfinite(m.error_estimate) for m in lagrange)  # (a mode without a partner level stays inf)
