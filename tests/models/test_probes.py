"""Point probes on hexahedra with a sliver element (modalfe/models/probing.py ``probing``): skfem's inverse map
stalls at round-off there; the probes must still locate every point and read a linear field exactly."""

import numpy as np
import pytest
from skfem import Basis, ElementHex1, MeshHex1

from modalfe.models.probing import probing as _probing


def test_probes_in_a_sliver_element_read_a_linear_field_exactly():
    """An 11.7 um wide last column of elements at x = 61.6 mm, as a tuned Cu-Be plate's mesh had (a part's edge
    11.7 um from the plate's end): skfem's probes raise ("Newton iteration didn't converge up to TOL=1e-12": the
    reference coordinates stall at eps x / h ~ 1e-12); ours give a trilinear element's exact values of a linear
    field, to round-off (1e-12 of the field's range)."""
    x = np.r_[np.linspace(0, 0.0616117, 40), 0.06162348]
    mesh = MeshHex1.init_tensor(x, np.linspace(0, 0.019, 8), np.array([0, 1e-3, 1.6944e-3]))
    basis = Basis(mesh, ElementHex1(), intorder=1)
    rng = np.random.default_rng(1)
    points = np.vstack([rng.uniform(0.06161174, 0.06162348, 600), rng.uniform(0, 0.019, 600),
                        rng.uniform(0, 1.69e-3, 600)])
    with pytest.raises(Exception, match="Newton iteration didn't converge"):
        basis.probes(points)  # skfem's own tolerance (if this passes, skfem changed and _probing may go)
    field = 1.0 + 20 * mesh.p[0] - 30 * mesh.p[1] + 400 * mesh.p[2]
    read = _probing(basis).probes(points) @ field
    assert read == pytest.approx(1.0 + 20 * points[0] - 30 * points[1] + 400 * points[2], abs=1e-12)


def test_the_grid_search_gives_skfems_matrix_on_a_seed_mesh_and_refuses_points_outside():
    """The box grid's element search (``_box_grid``) against skfem's own search: the same probe matrix at element
    centroids and at mesh vertices (on grid planes, where either neighbour's values agree), on the Cu-Be plate's
    quarter (ceramics over the plate, feet below: cells of the grid's bounding box that hold no element); a point
    in an empty cell (between two feet) is refused as skfem refuses it."""
    from modalfe.models.build import build_model
    from modalfe.report.report import working_windows
    from modalfe.scene import load_scene

    scene = working_windows(load_scene("cube_plate"))[0].scene
    model, _ = build_model(scene, "solid")
    probing = model._displacement_probing
    assert probing._find is not None
    mesh = model.mesh.mesh
    points = model._inside(np.hstack([mesh.p[:, mesh.t].mean(axis=1)[:, ::5], mesh.p[:, ::17]]))
    ours, skfems = probing.probes(points).tocsr(), probing.basis.probes(points).tocsr()
    assert abs(ours - skfems).max() <= 1e-12
    between_feet = np.array([[0.030], [0.010], [-0.002]])  # below the plate, beside every foot
    with pytest.raises(ValueError, match="lie in no element"):
        probing.probes(between_feet)


def test_the_grid_search_stands_aside_on_tetrahedra():
    from skfem import ElementTetP1, MeshTet1

    assert _probing(Basis(MeshTet1.init_tensor(*[np.linspace(0, 1, 3)] * 3), ElementTetP1(), intorder=1))._find \
        is None


@pytest.mark.parametrize("order", [3, 4])
def test_the_grid_probes_of_oriented_lagrange_hexahedra_are_skfems(order):
    """Quartic and cubic Lagrange hexahedra (``ElementHexGLL``, oriented per element): the grid's affine reference
    coordinates and the scalar values copied to the vector components give skfem's own probe matrix (Newton's
    inverse map, every vector function evaluated), at random points of the Cu-Be plate's quarter and at its
    vertices."""
    import dataclasses

    from modalfe.models.build import build_model
    from modalfe.report.report import working_windows
    from modalfe.scene import load_scene

    scene = working_windows(load_scene("cube_plate"))[0].scene
    mesh_settings = dataclasses.replace(scene.mesh, order=order, family="lagrange", min_layers=1)
    model, _ = build_model(dataclasses.replace(scene, mesh=mesh_settings), "solid", size_factor=3.0)
    probing = model._displacement_probing
    assert probing._find is not None and probing.basis is model.u_basis
    mesh = model.mesh.mesh
    rng = np.random.default_rng(order)
    corners = mesh.p[:, mesh.t]  # (3, 8, elements): a random point in each of (up to) 300 elements
    picked = rng.choice(mesh.t.shape[1], min(300, mesh.t.shape[1]), replace=False)
    lo, hi = corners.min(axis=1)[:, picked], corners.max(axis=1)[:, picked]
    points = model._inside(np.hstack([lo + rng.uniform(0, 1, lo.shape) * (hi - lo), mesh.p[:, ::23]]))
    ours, skfems = probing.probes(points).tocsr(), probing.basis.probes(points).tocsr()
    assert ours.shape == skfems.shape
    assert abs(ours - skfems).max() <= 1e-12


def test_curved_hexahedra_locate_each_point_in_an_element_that_maps_back_to_it():
    """Swept 27-node hexahedra with curved sides (``_HexLocator``): points made from known (element, reference
    coordinates) are found in an element whose map sends the found coordinates back to the point, to round-off (1e-12
    of the mesh's size; Newton stops at steps below 1e-8 of an element and converges quadratically), inside the
    reference cube; a linear field (which the isoparametric element holds exactly) reads exactly; a point outside
    raises."""
    from skfem import ElementHex2

    from tests.models.test_mapped_assembly import swept_mesh

    mesh = swept_mesh(3, 2, np.array([0.0, 0.1, 0.35, 0.5]), bend=0.35, twist=-0.25)
    basis = Basis(mesh, ElementHex2(), intorder=1)
    rng = np.random.default_rng(3)
    cells, X = rng.integers(0, mesh.nelements, 500), rng.random((3, 500))
    points = basis.mapping.F(X[:, :, None], tind=cells)[:, :, 0]
    probes = _probing(basis)
    found, local = probes._locate(points)
    back = basis.mapping.F(local[:, :, None], tind=found)[:, :, 0]
    assert np.abs(back - points).max() < 1e-12
    assert local.min() >= 0.0 and local.max() <= 1.0
    x, y, z = basis.doflocs
    assert probes.probes(points) @ (1 + 2 * x - 3 * y + 4 * z) == pytest.approx(
        1 + 2 * points[0] - 3 * points[1] + 4 * points[2], abs=1e-12)
    with pytest.raises(ValueError, match="lie in no element"):
        probes.probes(np.array([[0.5], [0.5], [0.6]]))


@pytest.mark.parametrize("element", ["ElementHex1", "ElementHex2"])
def test_the_locators_tensor_basis_is_the_geometry_elements_own(element):
    """The curved-hexahedron locator's all-at-once basis (``LagrangeHex``) against skfem's ``lbasis`` one function
    at a time, values and gradients at random reference points (round-off: 1e-13)."""
    import skfem

    from modalfe.models.probing import LagrangeHex

    geometry = getattr(skfem, element)()
    X = np.random.default_rng(7).random((3, 11))
    values, grads = LagrangeHex(geometry.doflocs)(X)
    own = [geometry.lbasis(X, a) for a in range(geometry.doflocs.shape[0])]
    assert np.allclose(values, np.array([v for v, _ in own]), atol=1e-13)
    assert np.allclose(grads, np.array([g for _, g in own]), atol=1e-13)


def test_the_orders_on_one_curved_mesh_share_one_point_search(monkeypatch):
    """Bases of different orders on one curved hexahedral mesh (the p-estimate's orders 2-3-4 on one grid) share its
    locator (``_locator``): the second basis's probes reuse the first's search (the points given again are not
    searched again) and equal those of a fresh search."""
    from skfem import ElementHex2, MeshHex2

    from modalfe.models.hex_elements import ElementHexGLL
    from modalfe.models.probing import _HexLocator, _Probing

    straight = MeshHex1.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 1, 3), np.linspace(0, 0.5, 3))
    curved = MeshHex2.from_mesh(straight)
    doflocs = curved.doflocs.copy()
    doflocs[2] += 0.05 * np.sin(np.pi * doflocs[0]) * doflocs[1]  # bend the mid-side nodes: a curved map
    mesh = MeshHex2(doflocs, curved.t)
    quadratic, quartic = Basis(mesh, ElementHex2(), intorder=2), Basis(mesh, ElementHexGLL(4), intorder=2)
    first, second = _probing(quadratic), _probing(quartic)
    assert first._locate is second._locate
    points = np.random.default_rng(3).uniform([[0.05], [0.05], [0.1]], [[0.95], [0.95], [0.4]], (3, 50))
    first.probes(points)
    fresh = _Probing(quartic, locate=_HexLocator(mesh)).probes(points).tocsr()
    monkeypatch.setattr(_HexLocator, "_located", lambda self, x: pytest.fail("the same points searched again"))
    shared = second.probes(points).tocsr()
    assert abs(shared - fresh).max() == 0.0
