"""Point probes on a finite-element basis: the sparse matrix that reads a field at given points (``probing``), with
the point search that works on the project's meshes (box grids, curved tetrahedra, thin hexahedra)."""

from __future__ import annotations

import weakref

import numpy as np
import scipy.sparse as sp

import modalfe.caches as caches

# reference-coordinate tolerance of a probe's point search on hexahedra (``probing``): 1e-8 of an element's size,
# above the round-off floor eps |x| / h down to elements of 1e-9 |x|; Newton converges quadratically, so the point
# is then located to ~1e-16 of the element
PROBE_NEWTON_TOL = 1e-8
PROBE_NEWTON_ITERATIONS = 30  # a point in its element converges in a few; a far candidate may not, and is dropped
HEX_BOX_MARGIN = 0.05  # widening of a hexahedron's node bounding box, of its size, for its candidate points
PROBE_PAIRS = 4e6  # point-element bounding-box tests per block of points (bounds their memory)
KEPT_LOCATORS = 4  # the point locators of the last meshes probed (``_locator``)
_LOCATORS: list[tuple[weakref.ref, _HexLocator]] = []  # (mesh held weakly, its locator), newest last
caches.register("point locators of curved meshes", _LOCATORS.clear)


def probing(basis) -> _Probing:
    """Point probes (``_Probing``) of ``basis``, or of a basis standing in for it in the point search: on a curved
    mesh (skfem MeshTet2, whose isoparametric point search does not converge in the elements next to a point) the
    same element on the straight-sided tetrahedra of the same vertices: the DOF numbering is the same (vertices,
    then edges), the point is only located through the chords, off by at most the sagitta h^2 / (8 R) of an element
    of size h on a boundary of radius R. On the box grid, ``basis`` itself (``_Probing``). On other hexahedra
    (trilinear or curved 27-node maps) each point's element and reference coordinates by ``_HexLocator``."""
    from skfem import Basis, MeshTet1, MeshTet2
    from skfem.refdom import RefHex

    mesh = basis.mesh
    find = _box_grid(mesh)
    if find is not None:
        return _Probing(basis, find)
    if isinstance(mesh, MeshTet2):
        return _Probing(Basis(MeshTet1(np.ascontiguousarray(mesh.p[:, : mesh.nvertices]), mesh.t), basis.elem,
                              intorder=1))
    if mesh.refdom is RefHex:  # curved (swept) or distorted hexahedra
        return _Probing(basis, locate=_locator(mesh))
    return _Probing(basis)


class _Probing:
    """Point probes of one basis: the matrix of skfem's ``CellBasis.probes``, or, on the structured grid of boxes
    (``_box_grid``: the box scenes' hexahedra), each point's element found by bisection in the grid's planes (skfem
    searches a tetrahedral split of the mesh, rebuilt at every call: 0.15 s a call on the glass plate's 33,272
    DOFs), its reference coordinates by the element's affine map (no Newton iteration), and the values of the
    scalar basis functions only, each copied to the components of the vector ones (scikit-fem evaluates every
    vector function's scalar with its gradient: ~3x the work)."""

    def __init__(self, basis, find=None, locate=None):
        self.basis, self._find, self._locate = basis, find, locate

    def probes(self, x: np.ndarray) -> sp.coo_matrix:
        """(components x points, DOFs) matrix of the basis functions' values at the points ``x`` (3, n) [m];
        ValueError for a point in no element."""
        b = self.basis
        if self._locate is not None:
            return self.at(*self._locate(x))
        if self._find is None:
            return b.probes(x)
        cells = self._find(x)
        # the box's trilinear map is affine: x = F(0) + J X, J's columns F(e_k) - F(0)
        F = b.mapping.F(np.array([[0.0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]), tind=cells)  # (3, n, 4)
        J = F[:, :, 1:] - F[:, :, :1]
        return self.at(cells, np.linalg.solve(J.transpose(1, 0, 2), (x - F[:, :, 0]).T[:, :, None])[:, :, 0].T)

    def at(self, cells: np.ndarray, local: np.ndarray) -> sp.coo_matrix:
        """(components x points, DOFs) matrix of the basis functions' values at reference coordinates ``local``
        (3, n) of the elements ``cells`` (n,): no point search, no inverse map."""
        from skfem.element import ElementVector

        b = self.basis
        local = local[:, :, None]
        scalar, dim = (b.elem.elem, b.elem.dim) if isinstance(b.elem, ElementVector) else (b.elem, 1)
        count, n = b.Nbfun // dim, len(cells)
        if hasattr(scalar, "values_at"):  # the project's hexahedra: all functions at once, values only
            values = scalar.values_at(b.mapping.mesh, local[:, :, 0], cells)
        else:
            values = np.array([scalar.gbasis(b.mapping, local, i, tind=cells)[0] for i in range(count)])
        # vector function dim i + c is scalar i in component c (scikit-fem's ElementVector numbering)
        rows = np.broadcast_to(np.arange(dim * n).reshape(1, dim, n), (count, dim, n))
        cols = b.element_dofs.reshape(count, dim, -1)[:, :, cells]
        data = np.broadcast_to(values.reshape(count, 1, n), (count, dim, n))
        return sp.coo_matrix((data.ravel(), (rows.ravel(), cols.ravel())), shape=(dim * n, b.N))


def _box_grid(mesh):
    """Element finder for a mesh of axis-aligned boxes each spanning one cell of a tensor grid of planes (the
    structured box grid of ``modalfe.models.mesh``): points (3, n) -> element indices by bisection in the planes;
    None for any other mesh (tetrahedra, curved or swept hexahedra), which skfem's own search handles."""
    from skfem import MeshHex1

    if type(mesh) is not MeshHex1:
        return None
    corners = mesh.p[:, mesh.t]  # (3, 8, elements)
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    tol = 1e-9 * float(np.max(mesh.p.max(axis=1) - mesh.p.min(axis=1)))
    if not np.all((np.abs(corners - lo[:, None]) <= tol) | (np.abs(corners - hi[:, None]) <= tol)):
        return None  # not axis-aligned boxes
    planes, index = [], []
    for axis in range(3):
        values = np.sort(mesh.p[axis])
        kept = values[np.concatenate([[True], np.diff(values) > tol])]
        first, last = np.searchsorted(kept, lo[axis] - tol), np.searchsorted(kept, hi[axis] - tol)
        if np.any(last != first + 1):
            return None  # an element spans several cells: not one tensor grid
        planes.append(kept)
        index.append(first)
    cell = np.full([len(p) - 1 for p in planes], -1, dtype=np.int64)
    cell[tuple(index)] = np.arange(mesh.t.shape[1])

    def find(x: np.ndarray) -> np.ndarray:
        found = np.full(x.shape[1], -1, dtype=np.int64)
        for side in ("right", "left"):  # a point on a plane: the element above it, else the one below
            ijk = [np.searchsorted(p, x[axis], side=side) - 1 for axis, p in enumerate(planes)]
            within = np.all([(i >= 0) & (i < len(p) - 1) & (np.abs(np.clip(x[axis], p[0], p[-1]) - x[axis]) <= tol)
                             for axis, (i, p) in enumerate(zip(ijk, planes))], axis=0)
            ijk = [np.clip(i, 0, len(p) - 2) for i, p in zip(ijk, planes)]
            missing = found < 0
            found[missing] = np.where(within, cell[tuple(ijk)], -1)[missing]
        if np.any(found < 0):
            raise ValueError(f"{int(np.sum(found < 0))} probe point(s) lie in no element")
        return found

    return find


class LagrangeHex:
    """The tensor-product Lagrange basis of a hexahedral geometry element whose nodes sit at ``reference`` (ngeo, 3)
    on the unit cube's grid of 1-D nodes (0, 1 or 0, 1/2, 1: skfem's ElementHex1, ElementHex2), all functions at
    once: the same values as the element's ``lbasis`` one function at a time (tests/models/test_probes.py), which
    cost 0.3 s a search on the round-feet plate."""

    def __init__(self, reference: np.ndarray):
        self.points = np.unique(reference)  # the 1-D nodes
        self.index = np.searchsorted(self.points, reference).T  # (3, ngeo): each node's 1-D node per axis

    def _one_d(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Values and derivatives (m, n) of the 1-D Lagrange polynomials on ``points`` at ``t`` (n,)."""
        m = len(self.points)
        values, slopes = np.ones((m, t.size)), np.zeros((m, t.size))
        for i, a in enumerate(self.points):
            for j, b in enumerate(self.points):
                if j == i:
                    continue
                factor = (t - b) / (a - b)
                slopes[i] = slopes[i] * factor + values[i] / (a - b)
                values[i] = values[i] * factor
        return values, slopes

    def __call__(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(values (ngeo, n), gradients (ngeo, 3, n)) at the reference points ``X`` (3, n)."""
        one_d = [self._one_d(X[k]) for k in range(3)]
        factors = [(v[self.index[k]], d[self.index[k]]) for k, (v, d) in enumerate(one_d)]
        values = factors[0][0] * factors[1][0] * factors[2][0]
        grads = np.stack([factors[0][1] * factors[1][0] * factors[2][0], factors[0][0] * factors[1][1] * factors[2][0],
                          factors[0][0] * factors[1][0] * factors[2][1]], axis=1)
        return values, grads


def _locator(mesh) -> _HexLocator:
    """The ``_HexLocator`` of ``mesh``, one for every basis on it (the orders 2-3-4 of one grid, whose estimate pairs
    modes at the same points: each point is located once), kept while the mesh lives."""
    _LOCATORS[:] = [(ref, found) for ref, found in _LOCATORS if ref() is not None]
    found = next((found for ref, found in _LOCATORS if ref() is mesh), None)
    if found is None:
        found = _HexLocator(mesh)
        _LOCATORS[:] = [*_LOCATORS[-(KEPT_LOCATORS - 1):], (weakref.ref(mesh), found)]
    return found


class _HexLocator:
    """Element and reference coordinates of points in a hexahedral mesh with an isoparametric map (skfem MeshHex1
    that is not a box grid, MeshHex2: curved swept hexahedra): the candidates of a point are the elements whose
    geometry nodes' bounding box, widened by ``HEX_BOX_MARGIN`` of its size, holds it (a curved side may bulge a
    little beyond its nodes), their reference coordinates by Newton's iteration
    on the element's map (``PROBE_NEWTON_TOL``), and of the candidates whose coordinates lie in the reference cube
    within ``PROBE_NEWTON_TOL`` the one that holds the point deepest is its element (where a distorted quadratic
    element folds near a corner, a neighbour holds the point too). skfem's search splits every hexahedron into
    tetrahedra and inverts them all at every call (1.2 s a call on the round-feet plate's 7,274 swept hexahedra)."""

    def __init__(self, mesh):
        self.geometry = LagrangeHex(mesh.elem().doflocs)
        self.nodes = mesh.doflocs[:, mesh.dofs.element_dofs]  # (3, ngeo, nel)
        lo, hi = self.nodes.min(axis=1), self.nodes.max(axis=1)
        pad = HEX_BOX_MARGIN * (hi - lo).max(axis=0)
        self.lo, self.hi = lo - pad, hi + pad
        self._last: tuple[bytes, tuple[np.ndarray, np.ndarray]] | None = None  # the last points and their answer

    def _newton(self, x: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(reference coordinates (3, n) of the points ``x`` (3, n) in ``cells`` (n,), whether the iteration
        converged there); not clipped, so that a point outside its candidate lands outside the cube."""
        X = np.full(x.shape, 0.5)
        nodes = self.nodes[:, :, cells]  # (3, ngeo, n)
        converged = np.zeros(x.shape[1], dtype=bool)
        for _ in range(PROBE_NEWTON_ITERATIONS):
            values, grads = self.geometry(X)
            F = np.einsum("ian,an->in", nodes, values)
            DF = np.einsum("ian,ajn->nij", nodes, grads)
            with np.errstate(all="ignore"):
                dX = np.linalg.solve(DF, (x - F).T[:, :, None])[:, :, 0].T
            X = X + dX
            converged = np.abs(dX).max(axis=0) < PROBE_NEWTON_TOL
            if converged.all():
                break
        return X, converged & np.isfinite(X).all(axis=0)

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(elements (n,), reference coordinates (3, n) clipped to the cube) of the points ``x`` (3, n) [m], the
        last points' answer given again; ValueError for a point in no element."""
        key = np.ascontiguousarray(x, dtype=float).tobytes()
        if self._last is None or self._last[0] != key:
            self._last = (key, self._located(x))
        cells, local = self._last[1]
        return cells.copy(), local.copy()

    def _located(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``__call__``'s answer, searched."""
        cells = np.full(x.shape[1], -1)
        local = np.zeros(x.shape)
        step = max(1, int(PROBE_PAIRS // self.lo.shape[1]))
        for start in range(0, x.shape[1], step):  # points x elements candidate tests in blocks
            block = x[:, start:start + step]
            inside = (block.T[:, :, None] >= self.lo[None]) & (block.T[:, :, None] <= self.hi[None])
            point, cell = np.nonzero(np.all(inside, axis=1))
            X, ok = self._newton(block[:, point], cell)
            depth = np.minimum(X, 1 - X).min(axis=0)  # how far inside the cube: the deepest candidate wins
            ok &= depth >= -PROBE_NEWTON_TOL
            order = np.flatnonzero(ok)[np.lexsort((-depth[ok], point[ok]))]
            found, first = np.unique(point[order], return_index=True)
            cells[start + found] = cell[order[first]]
            local[:, start + found] = np.clip(X[:, order[first]], 0.0, 1.0)
        if np.any(cells < 0):
            raise ValueError(f"{int(np.sum(cells < 0))} probe point(s) lie in no element")
        return cells, local
