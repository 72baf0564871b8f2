"""Fast assembly on axis-aligned box elements.

A hexahedron whose eight vertices are the corners of an axis-aligned box (edges h = (hx, hy, hz)) maps its
reference cube by a signed permutation of the axes and a scaling.  The nodal elements used here (Hex1,
serendipity S2, Gauss-Lobatto Q_p) have their nodes on a tensor grid symmetric under those maps, so the
shape function at a physical node is the same whatever the element's local orientation: in the *canonical*
order (the reference element's own nodes, reference axes along x, y, z) every box shares the reference
integrals M_ref = int N_a N_b and S[k, l] = int dN_a/dX_k dN_b/dX_l over the unit cube (the general path's
quadrature), and its element matrices are sums of them with per-element factors V / (h_k h_l) (V the
volume) times the material's constants.  These are summed through each element's canonical DOF map into
a CSR pattern built once (``np.bincount``).

The vector field numbers its DOFs 3 s + c (scalar DOF s, component c; scikit-fem's ``ElementVector``), so
K is assembled in 3 x 3 blocks on the scalar pattern.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

BOX_TOLERANCE = 1e-12  # vertices within this fraction of the edge lengths of a box's corners
VOIGT = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]])  # Voigt index of the strain component (i, j)


@dataclass(frozen=True)
class Boxes:
    """Box elements of one material: scalar DOFs (nloc, nel) in the canonical order, edge lengths (3, nel) [m]."""

    dofs: np.ndarray
    h: np.ndarray


def _grid(scalar) -> tuple[int, np.ndarray, bool] | None:
    """(q, (nloc, 3) index of each reference node on the (q+1)^3 grid of GLL points, whether each element
    orients its nodes (``ElementHexGLL.slots``)), None for an element without a fast path."""
    from skfem import ElementHex1, ElementHexS2

    from modalfe.models.hex_elements import ElementHexGLL

    if isinstance(scalar, ElementHexGLL):
        return scalar.p, scalar.reference_slots, True
    for kind, q in ((ElementHex1, 1), (ElementHexS2, 2)):  # their nodes: the GLL grids {0, 1}, {0, 1/2, 1}
        if type(scalar) is kind:
            return q, np.rint(q * scalar.doflocs).astype(int), False
    return None


def find_boxes(mesh, scalar, element_dofs: np.ndarray, elements: np.ndarray) -> tuple[Boxes, np.ndarray]:
    """Split ``elements`` into axis-aligned boxes (with their canonical scalar DOFs, from ``element_dofs``
    (nloc, all elements)) and the rest, left to the general path."""
    from skfem.refdom import RefHex

    grid = _grid(scalar)
    none = Boxes(np.zeros((element_dofs.shape[0], 0), dtype=int), np.zeros((3, 0)))
    if grid is None or len(elements) == 0:
        return none, elements
    curved = elements[:0]
    if mesh.doflocs.shape[1] > mesh.nvertices:  # MeshHex2 (swept): a box's corners need not make it a box
        straight = _trilinear(mesh, elements)
        elements, curved = elements[straight], elements[~straight]
        if len(elements) == 0:
            return none, curved
    q, ref, oriented = grid
    P = mesh.p[:, mesh.t[:, elements]]  # (3, 8, nel)
    lo = P.min(axis=1)
    h = P.max(axis=1) - lo
    with np.errstate(divide="ignore", invalid="ignore"):
        Y = np.nan_to_num((P - lo[:, None]) / h[:, None], nan=0.5)
    corner = np.rint(Y).astype(int)  # each vertex's box corner, 0 or 1 per axis
    Xv = RefHex.p.T.astype(int)  # (8, 3) reference vertices
    origin = int(np.flatnonzero((Xv == 0).all(axis=1))[0])
    axes = [int(np.flatnonzero((Xv == np.eye(3, dtype=int)[k]).all(axis=1))[0]) for k in range(3)]
    c = corner[:, origin]  # (3, nel): the reference origin's corner
    Q = np.stack([corner[:, a] - c for a in axes], axis=1)  # (3, 3, nel): reference axis k -> Q[:, k]
    ok = (np.all(np.abs(Y - corner) <= BOX_TOLERANCE, axis=(0, 1)) & np.all(h > 0, axis=0)
          & np.all(corner == c[:, None] + np.einsum("jke,vk->jve", Q, Xv), axis=(0, 1))
          & np.all(np.abs(Q).sum(axis=0) == 1, axis=0) & np.all(np.abs(Q).sum(axis=1) == 1, axis=0))
    if oriented:
        G = scalar.slots(mesh)[:, :, elements].astype(int)  # (3, nloc, nel) per-element node of each slot
    else:
        G = np.broadcast_to(ref.T[:, :, None], (3, ref.shape[0], len(elements)))
    Yg = q * c[:, None, :] + np.einsum("jke,kie->jie", Q, G)  # canonical grid index of each slot's node
    lookup = np.full((q + 1) ** 3, -1)
    lookup[(ref[:, 0] * (q + 1) + ref[:, 1]) * (q + 1) + ref[:, 2]] = np.arange(len(ref))
    flat = (Yg[0] * (q + 1) + Yg[1]) * (q + 1) + Yg[2]
    canon = lookup[np.clip(flat, 0, len(lookup) - 1)]  # (nloc, nel) canonical slot of each slot
    ok &= np.all(np.sort(canon, axis=0) == np.arange(len(ref))[:, None], axis=0)
    dofs = np.empty((len(ref), int(ok.sum())), dtype=element_dofs.dtype)
    dofs[canon[:, ok], np.arange(dofs.shape[1])] = element_dofs[:, elements[ok]]
    return Boxes(dofs, h[:, ok]), np.concatenate([elements[~ok], curved])


def _trilinear(mesh, elements: np.ndarray) -> np.ndarray:
    """Whether each of ``elements`` of a hexahedral mesh with geometry nodes beyond its vertices (MeshHex2) has
    every node at the trilinear map of its eight vertices (within ``BOX_TOLERANCE`` of its extent): a straight
    element, a box if its vertices make one (a swept section's rectangles)."""
    from skfem.refdom import RefHex

    from modalfe.models.probing import LagrangeHex

    # the trilinear shape functions of the vertices (in the order of ``mesh.t``) at the geometry nodes: (8, ngeo)
    N = LagrangeHex(RefHex.p.T)(mesh.elem.doflocs.T)[0]
    corners = mesh.p[:, mesh.t[:, elements]]  # (3, 8, nel)
    nodes = mesh.doflocs[:, mesh.dofs.element_dofs[:, elements]]  # (3, ngeo, nel)
    extent = np.ptp(corners, axis=1).max(axis=0)  # (nel,)
    off = np.abs(nodes - np.einsum("vg,ive->ige", N, corners)).max(axis=(0, 1))
    return off <= BOX_TOLERANCE * extent


def _reference(scalar, intorder: int) -> tuple[np.ndarray, np.ndarray]:
    """Mass (nloc, nloc) and gradient products S (3, 3, nloc, nloc), S[k, l, a, b] = int dN_a/dX_k dN_b/dX_l,
    on the unit cube, in the canonical order, with the general path's quadrature."""
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefHex

    X, W = get_quadrature(RefHex, intorder)
    values, grads = zip(*(scalar.lbasis(X, j) for j in range(len(scalar.doflocs))), strict=True)
    phi, dphi = np.array(values), np.array(grads)
    return (phi * W) @ phi.T, np.tensordot(dphi * W, dphi, axes=(2, 2)).transpose(1, 3, 0, 2)


def _scales(h: np.ndarray) -> np.ndarray:
    """(nel, 3, 3) volume / (h_k h_l): the factor of S[k, l] in a box of edges h (3, nel)."""
    return np.prod(h, axis=0)[:, None, None] / (h.T[:, :, None] * h.T[:, None, :])


def pattern(dofs: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """CSR pattern (indptr, indices) of the DOF pairs sharing an element, and the position in it of each
    element entry (element, row, column; flat) of ``dofs`` (nloc, nel) over n unknowns."""
    nloc, nel = dofs.shape
    E = sp.csr_matrix((np.ones(dofs.size), dofs.T.ravel(), np.arange(0, dofs.size + 1, nloc)), shape=(nel, n))
    A = (E.T @ E).tocsr()
    A.sort_indices()
    keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(A.indptr)) * n + A.indices
    order = np.argsort(dofs, axis=0)
    s = np.take_along_axis(dofs, order, axis=0).T.astype(np.int64)  # ascending per element: sorted queries
    pos = np.searchsorted(keys, (s[:, :, None] * n + s[:, None, :]).ravel()).reshape(nel, nloc, nloc)
    rank = np.argsort(order, axis=0).T  # (nel, nloc): where each canonical slot sits in the sorted order
    rows = np.arange(nel)[:, None, None]
    return A.indptr, A.indices, pos[rows, rank[:, :, None], rank[:, None, :]].ravel()


def _sum(pos: np.ndarray, coef: np.ndarray, S: np.ndarray, nnz: int) -> np.ndarray:
    """Pattern data of the element matrices coef @ S: per-element factors (nel, 9) of the reference integrals
    S (9, nloc^2), summed at the elements' positions ``pos``."""
    return np.bincount(pos, weights=np.einsum("ek,kq->eq", coef, S).ravel(), minlength=nnz)


def _interleave(A: sp.csr_matrix) -> sp.csr_matrix:
    """kron(A, I_3) for a scalar CSR matrix A (the same operator on each displacement component), built
    directly: row 3 r + c holds row r of A at columns 3 s + c."""
    n = A.shape[0]
    lens = np.repeat(np.diff(A.indptr), 3)
    indptr = np.r_[0, np.cumsum(lens)]
    src = np.arange(indptr[-1]) - np.repeat(indptr[:-1] - np.repeat(A.indptr[:-1], 3), lens)
    comp = np.repeat(np.tile(np.arange(3), n), lens)
    return sp.csr_matrix((A.data[src], 3 * A.indices[src] + comp, indptr), shape=(3 * n, 3 * n))


def assemble_elastic(scalar, intorder: int, parts: list[tuple[Boxes, object]], n: int,
                     mapped=None) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """K_uu and M_uu (3n, 3n) over the box elements of ``parts`` ((Boxes, material) pairs) and the ``mapped``
    elements (``modalfe.models.mapped_assembly.Elements``, added into the same pattern), n scalar DOFs.

    K[3a+c, 3b+d] = sum_kl C_ckdl V / (h_k h_l) S[k, l, a, b] (C_ckdl the elastic tensor), M = rho V M_ref x I_3.
    """
    parts = [(boxes, mat) for boxes, mat in parts if boxes.dofs.shape[1]]
    dofs = [boxes.dofs for boxes, _ in parts] + ([mapped.dofs] if mapped is not None else [])
    if not any(d.shape[1] for d in dofs):
        return sp.csr_matrix((3 * n, 3 * n)), sp.csr_matrix((3 * n, 3 * n))
    indptr, indices, pos = pattern(np.concatenate(dofs, axis=1), n)
    data = np.zeros((len(indices), 10))  # K's 3 x 3 blocks, then the scalar mass
    if parts:
        M_ref, S = _reference(scalar, intorder)
        coef = np.concatenate([np.einsum("ekl,ckdl->ecdkl", _scales(boxes.h), mat.C[VOIGT[:, :, None, None], VOIGT])
                               for boxes, mat in parts]).reshape(-1, 9, 9)
        mass = np.concatenate([mat.rho * np.prod(boxes.h, axis=0) for boxes, mat in parts])
        at = pos[:len(mass) * M_ref.size]
        S = S.reshape(9, -1)
        for cd in range(9):
            data[:, cd] = _sum(at, coef[:, cd], S, len(indices))
        data[:, 9] = np.bincount(at, weights=np.outer(mass, M_ref).ravel(), minlength=len(indices))
    if mapped is not None:
        mapped.add_elastic(data, pos[len(pos) - mapped.dofs.shape[1] * mapped.dofs.shape[0] ** 2:])
    return elastic_matrices(indptr, indices, data[:, :9].reshape(-1, 3, 3), data[:, 9], n)


def scatter(rows: np.ndarray, cols: np.ndarray, Ke: np.ndarray, n_rows: int, n_cols: int) -> sp.csr_matrix:
    """The (n_rows, n_cols) sum of element matrices ``Ke`` (nel, nA, nB) on the rows ``rows`` (nA, nel) and columns
    ``cols`` (nB, nel) of each element (repeated pairs summed)."""
    nA, nB = rows.shape[0], cols.shape[0]
    r = np.repeat(rows.T, nB, axis=1).ravel()
    c = np.tile(cols.T, (1, nA)).ravel()
    return sp.coo_matrix((Ke.ravel(), (r, c)), shape=(n_rows, n_cols)).tocsr()


def elastic_matrices(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray, Ms: np.ndarray,
                     n: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """K_uu and M_uu (3n, 3n) from their data on the scalar CSR pattern (indptr, indices) of n DOFs: K's 3 x 3
    blocks ``data`` (nnz, 3, 3), the scalar mass ``Ms`` (nnz,) on each component alike."""
    Kuu = sp.bsr_matrix((data, indices, indptr), shape=(3 * n, 3 * n)).tocsr()
    return Kuu, _interleave(sp.csr_matrix((Ms, indices, indptr), shape=(n, n)))


def assemble_piezo(scalar, intorder: int, parts: list[tuple[Boxes, object]], index: np.ndarray, n_phi: int,
                   n_u: int, mapped=None) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """K_uphi (n_u, n_phi) and K_phiphi (n_phi, n_phi) over the box elements of the piezo ``parts`` and the
    ``mapped`` elements (as ``assemble_elastic``); ``index`` maps scalar DOFs to potential unknowns (-1 off the
    piezo parts).

    K_uphi[3a+c, b] = sum_kl e_l,ck V / (h_k h_l) S[k, l, a, b] (e_l,ck the piezoelectric tensor),
    K_phiphi[a, b] = sum_kl eps_kl V / (h_k h_l) S[k, l, a, b].
    """
    parts = [(boxes, mat) for boxes, mat in parts if boxes.dofs.shape[1]]
    dofs = [index[boxes.dofs] for boxes, _ in parts] + ([index[mapped.dofs]] if mapped is not None else [])
    if not any(d.shape[1] for d in dofs):
        return sp.csr_matrix((n_u, n_phi)), sp.csr_matrix((n_phi, n_phi))
    indptr, indices, pos = pattern(np.concatenate(dofs, axis=1), n_phi)
    data = np.zeros((len(indices), 4))  # K_uphi's three components, then K_phiphi
    if parts:
        _, S = _reference(scalar, intorder)
        S = S.reshape(9, -1)
        scales = [_scales(boxes.h) for boxes, _ in parts]
        tensors = np.concatenate([np.concatenate([np.einsum("ekl,lck->eckl", g, mat.e[:, VOIGT]).reshape(-1, 3, 9),
                                                  (g * mat.eps_S).reshape(-1, 1, 9)], axis=1)
                                  for g, (_, mat) in zip(scales, parts)])
        at = pos[:len(tensors) * S.shape[1]]
        for c in range(4):
            data[:, c] = _sum(at, tensors[:, c], S, len(indices))
    if mapped is not None:
        mapped.add_piezo(data, pos[len(pos) - mapped.dofs.shape[1] * mapped.dofs.shape[0] ** 2:])
    return piezo_matrices(indptr, indices, data[:, :3], data[:, 3], index, n_phi, n_u)


def piezo_matrices(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray, Kpp: np.ndarray, index: np.ndarray,
                   n_phi: int, n_u: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """K_uphi (n_u, n_phi) and K_phiphi from their data on the CSR pattern (indptr, indices) of the potential
    unknowns: K_uphi's columns of 3 (component c of the row's u DOF) ``data`` (nnz, 3), ``Kpp`` (nnz,);
    ``index`` maps scalar DOFs to potential unknowns (-1 off the piezo parts)."""
    small = sp.bsr_matrix((data[:, :, None], indices, indptr), shape=(3 * n_phi, n_phi)).tocsr()  # rows 3 i + c
    used = np.flatnonzero(index >= 0)
    rows = (3 * used[:, None] + np.arange(3)).ravel()
    spread = sp.csr_matrix((np.ones(3 * n_phi), (rows, np.arange(3 * n_phi))), shape=(n_u, 3 * n_phi))
    return (spread @ small).tocsr(), sp.csr_matrix((Kpp, indices, indptr), shape=(n_phi, n_phi))
