"""Face integrals on the curved walls of quadratic tetrahedra (``modalfe.models.facets``): a round hole's wall,
where skfem's Newton inversion of the element map does not converge on this mesh, carries springs, masses,
pressures and mean outputs."""

import math

import numpy as np
import pytest
from skfem import Basis, ElementTetP2, FacetBasis, LinearForm

from modalfe.models.build import build_model
from modalfe.models.facets import facet_basis, facet_reference_points
from modalfe.models.solid import face_area
from modalfe.response.loads import face_traction_load, output_operators, rigid_translation
from modalfe.scene.loading import scene_from_dict
from modalfe.scene.loads import Load
from modalfe.scene.materials import material

R, H = 4e-3, 2e-3  # hole radius, plate thickness [m]
K = (1e6, 2e6, 3e6)  # spring totals on the hole's wall [N/m]
MASS = 1e-3  # mass attached to the hole's wall [kg]


@pytest.fixture(scope="module")
def model():
    """40 x 30 x 2 mm Cu-Be plate with a 4 mm round hole, one layer of 4 mm curved tetrahedra: on this mesh skfem's
    own FacetBasis fails on the hole's wall ("Newton iteration didn't converge up to TOL=1e-12")."""
    scene = scene_from_dict({
        "units": "mm",
        "parts": [{"name": "plate", "shape": "extrusion", "material": "CuBe", "axis": "z", "base": 0, "height": 2,
                   "outline": [[0, 0], [40, 0], [40, 30], [0, 30]], "circles": [[20, 15, 4]]}],
        "faces": {"hole": ["plate.hole_1"], "outside": ["plate.side", "plate.top"],
                  "skin": ["plate.side", "plate.hole_1", "plate.top", "plate.bottom"]},
        "springs": {"hole": list(K)}, "masses": {"hole": MASS},
        "analysis": {"near": 1e4, "count": 4},
        "mesh": {"element": "tet", "order": 2, "min_layers": 1, "max_size": 0.004}})
    return build_model(scene)[0]


def _interpolated(model, field) -> np.ndarray:
    """u DOF vector (n_u,) of the vector ``field`` (3, n) at the DOF locations (3, n) [m]: its P2 interpolant."""
    dofs = model.u_basis.get_dofs(elements=np.arange(model.u_basis.mesh.t.shape[1]))
    x = model.u_basis.doflocs
    u = np.zeros(model.n_u)
    for k in range(3):
        d = dofs.all(f"u^{k + 1}")
        u[d] = field(x[:, d])[k]
    return u


def _area_tolerance(model) -> float:
    """Relative area error bound of the wall's quadratic interpolation: a P2 curve through three points of an arc of
    length h deviates from it by at most |x'''| h^3 / (72 sqrt 3) (Lagrange remainder, max |s (s - h/2) (s - h)| =
    h^3 / (12 sqrt 3), |x'''| = 1 / R^2 on a circle), i.e. by (h / R)^3 / (72 sqrt 3) relative to R; doubled for the
    facets' diagonal edges and the second-order slope term. h: the longest vertex-to-vertex edge on the wall."""
    mesh = model.mesh.mesh
    corners = mesh.p[:, mesh.facets[:, model.mesh.faces["hole"]]]  # (3, 3 corners, nfacets)
    h = max(np.linalg.norm(corners[:, i] - corners[:, (i + 1) % 3], axis=0).max() for i in range(3))
    return 2 * (h / R) ** 3 / (72 * math.sqrt(3))


def test_hole_wall_area_is_2_pi_r_h_to_the_quadratic_geometry_error(model):
    tol = _area_tolerance(model)
    assert tol < 0.01  # the bound means something on this mesh
    assert face_area(model.mesh, "hole") == pytest.approx(2 * math.pi * R * H, rel=tol)


def test_uniform_pressure_on_a_closed_surface_has_no_net_force_or_moment(model):
    """int_S n dS = 0 and int_S x x n dS = 0 on a closed surface (divergence theorem); both hold exactly on the
    piecewise-quadratic surface, whose n dS is the cross product of the facet map's tangents (degree 2; times a P2
    rigid motion, degree 4 = the quadrature's order), so only round-off remains: 1e-12 of p A."""
    p = 1e5
    f = face_traction_load(model, Load("pressure", "skin", (p,)))
    scale = p * face_area(model.mesh, "skin")
    net = np.array([f @ rigid_translation(model, axis) for axis in "xyz"])
    assert np.abs(net).max() < 1e-12 * scale
    rotation = _interpolated(model, lambda x: np.stack([-x[1], x[0], 0 * x[2]]))  # about z: exact in P2
    assert abs(f @ rotation) < 1e-12 * scale * 0.05  # 0.05 m: the plate's largest lever arm
    # the pressure on the hole's wall alone pushes the wall outward: its load does work on the radial field
    g = face_traction_load(model, Load("pressure", "hole", (p,)))
    radial = _interpolated(model, lambda x: np.stack([(x[0] - 0.02) / R, (x[1] - 0.015) / R, 0 * x[2]]))
    # on the wall the radial field is (x - c) / R = the inward normal -n: work p * area (to the geometry's error)
    assert g @ radial == pytest.approx(p * 2 * math.pi * R * H, rel=_area_tolerance(model))


def test_spring_and_mass_on_the_hole_wall_are_the_scene_totals(model):
    """A rigid translation u = e_i stores r^T K r = k_i (the free plate stores none) and carries r^T M r = the plate's
    mass + the attached mass. The totals are spread over the wall's exact area 2 pi r h and integrated over the mesh's
    (the assembly's quadrature, order 4), so r^T K r = k_i A_mesh / (2 pi r h) to round-off (1e-9: the elastic K's
    rigid-motion energy cancels to ~1e-11 k here), and A_mesh = 2 pi r h to the geometry's error."""
    n = model.n_u
    Kuu, Muu = model.K[:n, :n], model.M[:n, :n]
    mesh = model.mesh.mesh
    share = facet_basis(mesh, ElementTetP2(), model.mesh.faces["hole"], intorder=4).dx.sum() / (2 * math.pi * R * H)
    assert share == pytest.approx(1.0, rel=_area_tolerance(model))
    # r^T M r of the plate is int rho det DF (the basis sums to one): degree 3, exact at order 4 like this volume
    plate_mass = material("CuBe").rho * Basis(mesh, ElementTetP2(), intorder=4).dx.sum()
    for i, axis in enumerate("xyz"):
        r = rigid_translation(model, axis)
        assert r @ Kuu @ r == pytest.approx(K[i] * share, rel=1e-9)
        assert r @ Muu @ r - plate_mass == pytest.approx(MASS * share, rel=1e-9)
        other = rigid_translation(model, "xyz"[(i + 1) % 3])
        assert abs(r @ Kuu @ other) < 1e-9 * K[i]  # springs along the axes: no coupling beyond round-off


def test_mean_of_a_linear_field_over_the_wall_is_its_value_at_the_walls_centroid(model):
    # u = (x - 20 mm, (y - 15 mm)^2, z): P2 holds each exactly; the wall (a cylinder about (20, 15) mm, z in
    # [0, H]) has its centroid on the axis at z = H / 2 and mean (y - 15 mm)^2 = R^2 / 2, to the curved geometry's
    # accuracy (``_area_tolerance``, as the wall's area; the DOF locations of the edges are the chords' midpoints):
    # a facet mapped to the wrong place in its element moves these means by a facet's size
    P = output_operators(model, ["mean:hole"])["mean:hole"]
    x, y, z = model.u_basis.doflocs[:, ::3]
    u = np.zeros(P.shape[1])
    u[0:model.n_u:3], u[1:model.n_u:3], u[2:model.n_u:3] = x - 20e-3, (y - 15e-3) ** 2, z
    mean = P @ u
    tol = _area_tolerance(model)
    assert abs(mean[0]) < tol * R
    assert mean[1] == pytest.approx(R**2 / 2, rel=tol)
    assert mean[2] == pytest.approx(H / 2, rel=tol)


def test_facet_quadrature_matches_skfem_where_its_newton_converges(model):
    """On the planar faces skfem's inversion converges (to 1e-12): both bases give the same load to round-off."""
    mesh, facets = model.mesh.mesh, model.mesh.faces["outside"]

    @LinearForm
    def normal_load(v, w):
        return w.n[0] * v[0] * w.x[1] + w.n[1] * v[1] + w.n[2] * v[2] * w.x[0]

    ours = normal_load.assemble(facet_basis(mesh, model.u_basis.elem, facets, intorder=4))
    skfem = normal_load.assemble(FacetBasis(mesh, model.u_basis.elem, facets=facets, intorder=4))
    assert np.abs(ours - skfem).max() < 1e-10 * np.abs(skfem).max()


def test_skfem_own_facet_basis_fails_on_this_wall(model):
    """Why ``facet_basis`` exists: when a scikit-fem release inverts these elements, this fails and it can go."""
    with pytest.raises(Exception, match="Newton iteration didn't converge"):
        FacetBasis(model.mesh.mesh, ElementTetP2(), facets=model.mesh.faces["hole"])


def test_facet_points_lie_on_their_facets_and_other_points_still_invert(model):
    """The element map at the reference points built from the facets' vertices returns the facet map's points
    (no inversion error beyond round-off, eps |x|); points that are not facet points go to skfem's Newton."""
    mesh, facets = model.mesh.mesh, model.mesh.faces["hole"]
    fb = facet_basis(mesh, ElementTetP2(), facets)
    x = fb.mapping.G(fb.X, find=fb.find)
    Y = facet_reference_points(mesh, facets, fb.tind, fb.X)
    assert np.abs(fb.mapping.F(Y, tind=fb.tind) - x).max() < 1e-15
    inside = np.full_like(Y, 0.2)  # an interior point of every element (barycentrics 0.2, 0.2, 0.2, 0.4)
    assert fb.mapping.invF(fb.mapping.F(inside, tind=fb.tind), tind=fb.tind) == pytest.approx(inside, abs=1e-10)
