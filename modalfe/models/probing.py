"""Point probes on a finite-element basis: the sparse matrix that reads a field at given points (``probing``), with
the point search that works on the project's meshes (box grids, curved tetrahedra, thin hexahedra)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

# reference-coordinate tolerance of a probe's point search on hexahedra (``probing``): 1e-8 of an element's size,
# above the round-off floor eps |x| / h down to elements of 1e-9 |x|; Newton converges quadratically, so the point
# is then located to ~1e-16 of the element
PROBE_NEWTON_TOL = 1e-8


def probing(basis) -> _Probing:
    """Point probes (``_Probing``) of ``basis``, or of a basis standing in for it in the point search: on a curved
    mesh (skfem MeshTet2, whose isoparametric point search does not converge in the elements next to a point) the
    same element on the straight-sided tetrahedra of the same vertices: the DOF numbering is the same (vertices,
    then edges), the point is only located through the chords, off by at most the sagitta h^2 / (8 R) of an element
    of size h on a boundary of radius R. On the box grid, ``basis`` itself (``_Probing``). On other hexahedra
    (trilinear map) the point's reference coordinates are found by skfem's Newton iteration to ``PROBE_NEWTON_TOL``
    instead of its 1e-12: that iteration stalls at the round-off eps |x| / h of a thin element (measured: 1.2e-12 on
    an 11.7 um sliver at x = 61.6 mm of a tuned Cu-Be plate, and every point of a probe set must pass at once)."""
    import functools

    from skfem import Basis, MeshTet1, MeshTet2
    from skfem.mapping import MappingIsoparametric

    mesh = basis.mesh
    find = _box_grid(mesh)
    if find is not None:
        return _Probing(basis, find)
    if isinstance(mesh, MeshTet2):
        return _Probing(Basis(MeshTet1(np.ascontiguousarray(mesh.p[:, : mesh.nvertices]), mesh.t), basis.elem,
                              intorder=1))
    if not isinstance(basis.mapping, MappingIsoparametric):
        return _Probing(basis)
    mapping = MappingIsoparametric(mesh, mesh.elem(), mesh.bndelem)
    mapping.invF = functools.partial(MappingIsoparametric.invF, mapping, newton_tol=PROBE_NEWTON_TOL)
    return _Probing(Basis(mesh, basis.elem, mapping=mapping, intorder=1))


class _Probing:
    """Point probes of one basis: the matrix of skfem's ``CellBasis.probes``, or, on the structured grid of boxes
    (``_box_grid``: the box scenes' hexahedra), each point's element found by bisection in the grid's planes (skfem
    searches a tetrahedral split of the mesh, rebuilt at every call: 0.15 s a call on the glass plate's 33,272
    DOFs), its reference coordinates by the element's affine map (no Newton iteration), and the values of the
    scalar basis functions only, each copied to the components of the vector ones (scikit-fem evaluates every
    vector function's scalar with its gradient: ~3x the work)."""

    def __init__(self, basis, find=None):
        self.basis, self._find = basis, find

    def probes(self, x: np.ndarray) -> sp.coo_matrix:
        """(components x points, DOFs) matrix of the basis functions' values at the points ``x`` (3, n) [m];
        ValueError for a point in no element."""
        b = self.basis
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
