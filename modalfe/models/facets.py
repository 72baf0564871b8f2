"""Facet quadrature that also works on curved (isoparametric) elements: quadratic tetrahedra and 27-node hexahedra.

skfem's ``FacetBasis`` places its quadrature points on a facet through the facet's own map, then finds their
reference coordinates in the adjacent element by Newton's method on the element's isoparametric map
(``MappingIsoparametric.invF``: start at (1/2, 1/2, 1/2), clipped to [0, 1]^3, absolute tolerance 1e-12). On
quadratic tetrahedra along a concave wall (a round hole's wall) that iteration does not converge; on the swept
hexahedra of ``modalfe.models.swept`` it stalls at round-off (the residual's eps |x|, ~1e-16 m at centimetres from
the origin, over sub-millimetre elements is ~1e-12 in reference coordinates). No inversion is needed: a face of the
reference element is the affine image of the reference facet (triangle or square), and the element's map restricted
to that face is the facet's map through the same nodes (on a face the basis functions of the off-face nodes vanish,
the property that makes the elements conforming). So a point X of the reference facet, whose corners k are the
facet's vertices ``mesh.facets[k]``, sits at Y = sum_k N_k(X) V(v_k) in the element, N_k the facet's linear
(triangle) or bilinear (square) corner functions and V(v_k) the reference vertex of the element's local vertex v_k.
"""

from __future__ import annotations

import numpy as np
from skfem import FacetBasis
from skfem.mapping import MappingIsoparametric
from skfem.quadrature import get_quadrature

from modalfe.errors import MeshError


def facet_basis(mesh, elem, facets: np.ndarray, *, intorder: int | None = None) -> FacetBasis:
    """skfem ``FacetBasis`` of ``elem`` over the mesh ``facets`` (indices); on curved meshes (skfem MeshTet2,
    MeshHex2) its quadrature points' element coordinates come from each facet's local vertices (module docstring),
    not from skfem's Newton inversion. ``intorder`` as skfem's (default 2 x the element's degree)."""
    facets = np.asarray(facets, dtype=np.int64)
    curved = mesh.doflocs.shape[1] > mesh.nvertices
    if not (curved and isinstance(mesh.mapping(), MappingIsoparametric)):
        return FacetBasis(mesh, elem, facets=facets, intorder=intorder)
    quadrature = get_quadrature(mesh.brefdom, intorder if intorder is not None else 2 * elem.maxdeg)
    mapping = _FacetMapping(mesh, facets, quadrature[0])
    return FacetBasis(mesh, elem, mapping=mapping, quadrature=quadrature, facets=facets)


def facet_reference_points(mesh, facets: np.ndarray, elements: np.ndarray, X: np.ndarray) -> np.ndarray:
    """(3, nfacets, npoints) reference coordinates in element ``elements[i]`` of the points ``X`` (2, npoints) of the
    reference facet mapped onto facet ``facets[i]`` (one of that element's faces) by skfem's facet map, whose corner k
    is ``mesh.facets[k]``: the facet's corner functions of X on those vertices' reference positions."""
    corners = mesh.facets[:, facets]  # (nc, nfacets) global vertices of each facet, in the facet map's order
    match = mesh.t[:, elements][None, :, :] == corners[:, None, :]  # (facet vertices, element vertices, n)
    if not match.any(axis=1).all():
        raise MeshError("facets: a facet is not a face of the element it is integrated from")
    local = match.argmax(axis=1)  # (nc, nfacets) local vertex of each facet vertex
    vertices = mesh.elem.refdom.p.T  # (element vertices, 3) reference vertices in local order
    c = mesh.brefdom.p  # (2, nc) reference facet corners: the triangle's or the square's
    if c.shape[1] == 3:  # linear: barycentrics
        weights = np.stack([1.0 - X[0] - X[1], X[0], X[1]])
    else:  # bilinear on the unit square's corners
        weights = np.prod([np.where(c[d][:, None] == 1.0, X[d][None, :], 1.0 - X[d][None, :]) for d in range(2)],
                          axis=0)
    return np.einsum("kfd,kq->dfq", vertices[local], weights)


class _FacetMapping(MappingIsoparametric):
    """skfem's isoparametric element map whose inverse is ``facet_reference_points`` for the quadrature points of
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
