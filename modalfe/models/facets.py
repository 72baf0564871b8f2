"""Facet quadrature that also works on curved (isoparametric) tetrahedra.

skfem's ``FacetBasis`` places its quadrature points on a facet through the facet's own map, then finds their
reference coordinates in the adjacent element by Newton's method on the element's isoparametric map
(``MappingIsoparametric.invF``: start at (1/2, 1/2, 1/2), clipped to [0, 1]^3, tolerance 1e-12). On quadratic
tetrahedra along a concave wall (a round hole's wall) that iteration does not converge. No inversion is needed: a
face of the reference tetrahedron is the affine image of the reference triangle, and the quadratic element's map
restricted to that face is the quadratic triangle map through the same six nodes (on a face the four basis functions
of the off-face nodes vanish and the other six are the triangle's P2 functions, the property that makes P2
conforming). So a point with barycentrics (l0, l1, l2) on the facet's vertices (v0, v1, v2) sits at Y = l0 V(v0) +
l1 V(v1) + l2 V(v2) in the element, V(v) the reference vertex of the element's local vertex v.
"""

from __future__ import annotations

import numpy as np
from skfem import FacetBasis
from skfem.mapping import MappingIsoparametric
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTet

from modalfe.errors import MeshError

# vertices of skfem's reference tetrahedron (RefTet), in its local vertex order
_REFERENCE_TET = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


def facet_basis(mesh, elem, facets: np.ndarray, *, intorder: int | None = None) -> FacetBasis:
    """skfem ``FacetBasis`` of ``elem`` over the mesh ``facets`` (indices); on curved tetrahedra (skfem MeshTet2)
    its quadrature points' element coordinates come from each facet's local vertices (module docstring), not from
    skfem's Newton inversion. ``intorder`` as skfem's (default 2 x the element's degree)."""
    facets = np.asarray(facets, dtype=np.int64)
    if not (isinstance(mesh.mapping(), MappingIsoparametric) and mesh.elem.refdom is RefTet):
        return FacetBasis(mesh, elem, facets=facets, intorder=intorder)
    quadrature = get_quadrature(mesh.brefdom, intorder if intorder is not None else 2 * elem.maxdeg)
    mapping = _TetFacetMapping(mesh, facets, quadrature[0])
    return FacetBasis(mesh, elem, mapping=mapping, quadrature=quadrature, facets=facets)


def facet_reference_points(mesh, facets: np.ndarray, elements: np.ndarray, X: np.ndarray) -> np.ndarray:
    """(3, nfacets, npoints) reference coordinates in tetrahedron ``elements[i]`` of the points ``X`` (2, npoints)
    of the reference triangle mapped onto facet ``facets[i]`` (one of that element's faces) by skfem's facet map,
    whose vertex k is ``mesh.facets[k]``: barycentrics (1 - X0 - X1, X0, X1) on those vertices."""
    corners = mesh.facets[:, facets]  # (3, nfacets) global vertices of each facet, in the facet map's order
    match = mesh.t[:, elements][None, :, :] == corners[:, None, :]  # (3 facet vertices, 4 element vertices, n)
    if not match.any(axis=1).all():
        raise MeshError("facets: a facet is not a face of the element it is integrated from")
    local = match.argmax(axis=1)  # (3, nfacets) local vertex of each facet vertex
    barycentric = np.stack([1.0 - X[0] - X[1], X[0], X[1]])  # (3, npoints)
    return np.einsum("kfd,kq->dfq", _REFERENCE_TET[local], barycentric)


class _TetFacetMapping(MappingIsoparametric):
    """skfem's isoparametric tetrahedron map whose inverse is ``facet_reference_points`` for the quadrature points of
    its own facets (what ``FacetBasis`` asks, once per side) and skfem's Newton iteration for any other points."""

    def __init__(self, mesh, facets: np.ndarray, X: np.ndarray):
        super().__init__(mesh, mesh.elem(), mesh.bndelem)
        self.facets = facets
        self.X = X

    def invF(self, x, tind=None, **kwargs):  # noqa: N802 (skfem's name)
        if tind is not None and len(tind) == len(self.facets) and x.shape[1:] == (len(tind), self.X.shape[1]):
            Y = facet_reference_points(self.mesh, self.facets, tind, self.X)
            # the facet and element maps sum the same node coordinates: equal to round-off, eps |x|
            if np.abs(self.F(Y, tind) - x).max(initial=0.0) <= 1e-12 * np.abs(x).max(initial=1.0):
                return Y
        return super().invF(x, tind=tind, **kwargs)
