"""Tensor-product Lagrange hexahedra of any order p >= 1 on Gauss-Lobatto-Legendre nodes, for scikit-fem.

``ElementHexGLL(p)`` is a scalar H1 element on ``skfem.MeshHex`` (trilinear geometry): the (p+1)^3
nodes are the tensor grid of the p+1 Gauss-Lobatto-Legendre (GLL) points on [0, 1] (the ends and the
roots of P_p', Canuto, Hussaini, Quarteroni & Zang, Spectral Methods: Fundamentals in Single Domains,
2006, sec. 2.2.3), the shape functions products of 1-D Lagrange polynomials on them.  It plugs into
``skfem.Basis(mesh, ElementVector(ElementHexGLL(p)), intorder=2 * p)`` like scikit-fem's own elements.

Orientation.  scikit-fem numbers the p-1 DOFs of an edge and the (p-1)^2 of a face once per mesh
entity (``Dofs``: ``edge_dofs[k, edge]``, ``facet_dofs[k, facet]``) and hands element slot k of local
edge j the global DOF ``edge_dofs[k, t2e[j]]`` whatever the element's local orientation.  So here
the global DOF k of an entity is defined by the entity's global vertex indices alone:

- edge: the k-th interior GLL node counted from the edge's vertex of lower global index;
- face: origin at the face's corner of lowest global index, first axis toward the neighbouring
  corner of lower global index, second toward the other; DOF k = a (p-1) + b is the node
  (a+1, b+1) of the face's GLL grid in that frame.

Two elements sharing an edge or a face see the same global vertices, hence the same frame, and the
GLL grid is symmetric, so both place DOF k at the same physical point.  ``gbasis`` evaluates, in each
element, the local shape function sitting at that node (a per-element permutation of the edge and
face slots, computed once per mesh and cached on it).  Vertex and interior DOFs need none.

scikit-fem computes ``Basis.doflocs`` from the reference ``doflocs`` (the identity orientation), so for
p >= 3 the order of the DOFs *within* an edge or a face is not reliable there (the set on each edge
and face is); ``dof_locations`` gives the true node positions.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import legendre
from skfem.element import DiscreteField, ElementH1
from skfem.refdom import RefHex

_VERTICES = RefHex.p.T.astype(int)  # (8, 3) reference vertex coordinates, 0 or 1
_EDGES = np.array(RefHex.edges)  # (12, 2) local vertices
_FACETS = np.array(RefHex.facets)  # (6, 4) local vertices in cyclic order
_CACHE_ATTR = "_modalfe_hex_gll_slots"


def gll_points(p: int) -> np.ndarray:
    """The p+1 Gauss-Lobatto-Legendre points on [0, 1], ascending: 0, 1 and the roots of P_p'
    mapped from [-1, 1] (Canuto et al., Spectral Methods, 2006, eq. 2.2.20)."""
    if p < 1:
        raise ValueError(f"p: must be >= 1, got {p}")
    inner = np.sort(legendre.Legendre.basis(p).deriv().roots().real) if p > 1 else np.array([])
    x = np.concatenate([[-1.0], inner, [1.0]])
    x = 0.5 * (x - x[::-1])  # exact symmetry about 0 (the roots carry ~1e-16 asymmetry)
    return 0.5 * (x + 1.0)


def lagrange_1d(nodes: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and derivatives (len(nodes), *x.shape) of the Lagrange polynomials on ``nodes`` at ``x``
    (product form, e.g. Canuto et al. 2006, eq. 2.3.27; well conditioned for the GLL nodes)."""
    n = len(nodes)
    diff = x[None, ...] - nodes.reshape((n,) + (1,) * x.ndim)  # (n, *x.shape): x - x_m
    L = np.empty((n, *x.shape))
    dL = np.zeros((n, *x.shape))
    for a in range(n):
        others = [m for m in range(n) if m != a]
        scale = np.prod(nodes[a] - nodes[others])
        L[a] = np.prod(diff[others], axis=0) / scale
        for m in others:
            rest = [r for r in others if r != m]
            dL[a] += (np.prod(diff[rest], axis=0) if rest else 1.0) / scale
    return L, dL


def _reference_slots(p: int) -> np.ndarray:
    """(nloc, 3) tensor-grid index of each local slot in scikit-fem's order (8 vertices, 12 x (p-1) edge
    nodes, 6 x (p-1)^2 face nodes, (p-1)^3 interior nodes) for the identity orientation (every entity's
    frame taken from its local vertex order)."""
    t = np.arange(8)[:, None]  # an element whose global vertex indices are its local ones
    return _slots(t, p)[:, :, 0].T


def _slots(t: np.ndarray, p: int) -> np.ndarray:
    """(3, nloc, nel) tensor-grid index (along reference x, y, z) of the node each element's slot
    carries, from the global vertex indices ``t`` (8, nel) (see the module docstring)."""
    nel = t.shape[1]
    rows: list[np.ndarray] = []
    for v in range(8):
        rows.append(np.repeat((p * _VERTICES[v])[:, None], nel, axis=1))
    for v0, v1 in _EDGES:
        axis = int(np.flatnonzero(_VERTICES[v0] != _VERTICES[v1])[0])
        flip = t[v0] > t[v1]  # the global frame runs from v1 to v0
        for k in range(p - 1):
            s = np.where(flip, p - 1 - k, k + 1)  # position counted from v0
            idx = np.repeat((p * _VERTICES[v0])[:, None], nel, axis=1)
            idx[axis] = s if _VERTICES[v0][axis] == 0 else p - s
            rows.append(idx)
    cols = np.arange(nel)
    for corners in _FACETS:
        g = t[corners]  # (4, nel)
        o = np.argmin(g, axis=0)
        n1, n3 = (o + 1) % 4, (o + 3) % 4
        first = np.where(g[n1, cols] < g[n3, cols], n1, n3)
        second = np.where(first == n1, n3, n1)
        P = _VERTICES[corners]  # (4, 3)
        origin, a1, a2 = P[o], P[first], P[second]  # (nel, 3) each
        axis1 = np.argmax(origin != a1, axis=1)
        axis2 = np.argmax(origin != a2, axis=1)
        for a in range(p - 1):
            for b in range(p - 1):
                idx = (p * P[0])[:, None].repeat(nel, axis=1)  # the fixed axis keeps the face's value
                for axis, s in ((axis1, a + 1), (axis2, b + 1)):
                    start = origin[cols, axis]
                    idx[axis, cols] = np.where(start == 0, s, p - s)
                rows.append(idx)
    for i in range(1, p):
        for j in range(1, p):
            for k in range(1, p):
                rows.append(np.repeat(np.array([[i], [j], [k]]), nel, axis=1))
    return np.stack(rows, axis=1)


class ElementHexGLL(ElementH1):
    """Lagrange hexahedron of order ``p`` (Q_p) on the tensor grid of Gauss-Lobatto-Legendre nodes;
    nodes shared between elements are matched whatever each element's local orientation."""

    refdom = RefHex

    def __init__(self, p: int = 3):
        if int(p) != p or p < 1:
            raise ValueError(f"p: must be an integer >= 1, got {p}")
        self.p = int(p)
        self.nodal_dofs = 1
        self.edge_dofs = self.p - 1
        self.facet_dofs = (self.p - 1) ** 2
        self.interior_dofs = (self.p - 1) ** 3
        self.maxdeg = 3 * self.p  # x^p y^p z^p: scikit-fem counts the total degree
        self.dofnames = ["u"] * (self.nodal_dofs + self.facet_dofs + self.edge_dofs + self.interior_dofs)
        self.nodes = gll_points(self.p)
        self.reference_slots = _reference_slots(self.p)
        self.doflocs = self.nodes[self.reference_slots]  # (nloc, 3), identity orientation
        self._last_factors: tuple | None = None
        self._last_invDF: tuple | None = None

    def __repr__(self) -> str:
        return f"ElementHexGLL({self.p})"

    def slots(self, mesh) -> np.ndarray:
        """(3, nloc, nel) tensor-grid index of the node carried by each slot of each element of ``mesh``
        (computed once per mesh and order, cached on the mesh object)."""
        cache = mesh.__dict__.setdefault(_CACHE_ATTR, {})
        if self.p not in cache:
            cache[self.p] = _slots(np.asarray(mesh.t), self.p).astype(np.int16)
        return cache[self.p]

    def _factors(self, X: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        """1-D Lagrange values and derivatives along each reference axis at X; the last X's are kept, as
        scikit-fem evaluates every basis function (three times for ``ElementVector``) at the same points."""
        key = (X.shape, X.tobytes())
        if self._last_factors is None or self._last_factors[0] != key:
            self._last_factors = (key, [lagrange_1d(self.nodes, X[d]) for d in range(3)])
        return self._last_factors[1]

    def _tensor(self, X: np.ndarray, idx: np.ndarray):
        """Value (nel, nq) and reference gradient (3, nel, nq) of the tensor shape function of grid index
        ``idx`` (3, nel) at reference points X, (3, nq) shared or (3, nel, nq) per element."""
        factors = []
        for d, (L, dL) in enumerate(self._factors(X)):
            if X.ndim == 2:
                factors.append((L[idx[d]], dL[idx[d]]))
            else:
                pick = idx[d][None, :, None]
                factors.append((np.take_along_axis(L, pick, 0)[0], np.take_along_axis(dL, pick, 0)[0]))
        (Lx, dLx), (Ly, dLy), (Lz, dLz) = factors
        return Lx * Ly * Lz, np.array([dLx * Ly * Lz, Lx * dLy * Lz, Lx * Ly * dLz])

    def _inverse_jacobian(self, mapping, X: np.ndarray, tind) -> np.ndarray:
        """``mapping.invDF(X, tind)``, kept for the next basis function at the same points."""
        key = (id(mapping), X.shape, X.tobytes(), None if tind is None else np.asarray(tind).tobytes())
        if self._last_invDF is None or self._last_invDF[0] != key:
            self._last_invDF = (key, mapping.invDF(X, tind))
        return self._last_invDF[1]

    def lbasis(self, X: np.ndarray, i: int):
        """Reference basis function ``i`` in the identity orientation (value, gradient)."""
        if not 0 <= i < len(self.reference_slots):
            self._index_error()
        idx = self.reference_slots[i][:, None]
        phi, dphi = self._tensor(np.asarray(X)[:, None, :] if np.ndim(X) == 2 else X, idx)
        return (phi[0], dphi[:, 0]) if np.ndim(X) == 2 else (phi, dphi)

    def values_at(self, mesh, X: np.ndarray, tind: np.ndarray) -> np.ndarray:
        """(nloc, n) every global basis function's value at one reference point per element, ``X`` (3, n), of the
        elements ``tind`` (n,) of ``mesh``: ``gbasis``' values, oriented per element, all functions at once and
        without the gradients or the inverse map a point probe does not read."""
        slots = self.slots(mesh)[:, :, tind]  # (3, nloc, n)
        L = [lagrange_1d(self.nodes, X[d][:, None])[0][:, :, 0] for d in range(3)]  # (p + 1, n) each, as _tensor
        element = np.arange(X.shape[1])
        return L[0][slots[0], element] * L[1][slots[1], element] * L[2][slots[2], element]

    def gbasis(self, mapping, X: np.ndarray, i: int, tind=None):
        """Global basis function ``i`` on the elements ``tind`` (all when None), oriented per element."""
        if not 0 <= i < len(self.reference_slots):
            self._index_error()
        slots = self.slots(mapping.mesh)[:, i]
        idx = slots if tind is None else slots[:, tind]
        phi, dphi = self._tensor(np.asarray(X), idx)
        invDF = self._inverse_jacobian(mapping, X, tind)
        return (DiscreteField(value=phi, grad=np.einsum("ijkl,ikl->jkl", invDF, dphi)),)


def dof_locations(basis) -> np.ndarray:
    """(3, N) true positions of the nodes of a scalar ``ElementHexGLL`` basis (scikit-fem's
    ``basis.doflocs`` uses the identity orientation, see the module docstring)."""
    elem = basis.elem
    slots = elem.slots(basis.mesh)  # (3, nloc, nel)
    X = elem.nodes[slots]  # (3, nloc, nel) reference coordinates of each slot's node
    x = basis.mapping.F(X.transpose(0, 2, 1), tind=np.arange(X.shape[2]))  # (3, nel, nloc)
    out = np.zeros((3, basis.N))
    dofs = basis.dofs.element_dofs  # (nloc, nel) over all elements
    out[:, dofs.T.ravel()] = x.reshape(3, -1)
    return out


def _serendipity_exponents() -> np.ndarray:
    """(32, 3) exponents of the cubic serendipity space S_3 on the cube: the monomials of superlinear degree
    <= 3 (total degree not counting variables that enter linearly; Arnold & Awanou, Found. Comput. Math. 11,
    2011, def. 2.1): the complete cubic (20), x^3 y and x^2 y z types (9) and x^3 y z types (3)."""
    grid = np.array(np.meshgrid(*[np.arange(4)] * 3, indexing="ij")).reshape(3, -1).T
    superlinear = np.where(grid >= 2, grid, 0).sum(axis=1)
    return grid[superlinear <= 3]


class ElementHexS3(ElementHexGLL):
    """32-node cubic serendipity hexahedron (Ergatoudis, Irons & Zienkiewicz 1968; Zienkiewicz, Taylor & Zhu,
    The Finite Element Method, 7th ed., sec. 6.5): a node at each vertex and two on each edge, none on faces
    or inside. Its space S_3 holds every cubic and the edge traces of Q_3, so it converges at the order of the
    Lagrange Q_3 on undistorted boxes with 12 nodes per element of a layer instead of 27-36. The edge nodes
    sit at the interior Gauss-Lobatto points of order 3 (oriented like ``ElementHexGLL``'s), the shape
    functions are the S_3 Lagrange basis on those 32 nodes (inverse Vandermonde of the monomials)."""

    def __init__(self):
        super().__init__(3)
        self.facet_dofs = 0
        self.interior_dofs = 0
        self.maxdeg = 5  # x^3 y z
        nloc = 8 + 12 * 2
        self.dofnames = ["u"] * nloc
        self.reference_slots = self.reference_slots[:nloc]  # vertices then edges: face and interior slots follow
        self.doflocs = self.nodes[self.reference_slots]
        self.exponents = _serendipity_exponents()
        vandermonde = np.prod(self.doflocs[:, None, :] ** self.exponents[None, :, :], axis=2)  # (node, monomial)
        self.coefficients = np.linalg.inv(vandermonde)  # (monomial, node): column a is node a's shape function
        self.node_of = np.full(4 ** 3, -1)
        self.node_of[(self.reference_slots[:, 0] * 4 + self.reference_slots[:, 1]) * 4 + self.reference_slots[:, 2]] \
            = np.arange(nloc)

    def __repr__(self) -> str:
        return "ElementHexS3()"

    def slots(self, mesh) -> np.ndarray:
        """(3, 32, nel) grid index (on the 4^3 grid of order-3 Gauss-Lobatto points) of each slot's node."""
        cache = mesh.__dict__.setdefault(_CACHE_ATTR, {})
        if "S3" not in cache:
            cache["S3"] = _slots(np.asarray(mesh.t), 3)[:, :32].astype(np.int16)
        return cache["S3"]

    def values_at(self, mesh, X: np.ndarray, tind: np.ndarray) -> np.ndarray:
        """``ElementHexGLL.values_at`` for this element's own shape functions (each node's at its element's point)."""
        slots = self.slots(mesh)[:, :, tind]  # (3, 32, n)
        nloc, n = slots.shape[1], slots.shape[2]
        at = np.broadcast_to(X[:, None, :], (3, nloc, n)).reshape(3, nloc * n, 1)
        return self._tensor(at, slots.reshape(3, nloc * n))[0].reshape(nloc, n)

    def _tensor(self, X: np.ndarray, idx: np.ndarray):
        """Value (nel, nq) and reference gradient (3, nel, nq) of the shape function of the node at grid index
        ``idx`` (3, nel), at X (3, nq) shared or (3, nel, nq) per element."""
        e = self.exponents.T.reshape(3, 32, *([1] * (X.ndim - 1)))  # (3, 32, 1...)
        powers = X[:, None] ** e  # (3, 32, ...)
        lower = np.where(e > 0, e * X[:, None] ** np.maximum(e - 1, 0), 0.0)
        P = np.prod(powers, axis=0)
        dP = np.array([lower[d] * np.prod(np.delete(powers, d, axis=0), axis=0) for d in range(3)])
        C = self.coefficients[:, self.node_of[(idx[0] * 4 + idx[1]) * 4 + idx[2]]]  # (32, nel)
        if X.ndim == 2:
            return np.einsum("mn,mq->nq", C, P), np.einsum("mn,dmq->dnq", C, dP)
        return np.einsum("mn,mnq->nq", C, P), np.einsum("mn,dmnq->dnq", C, dP)
