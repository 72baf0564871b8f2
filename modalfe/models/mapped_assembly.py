"""Batched assembly on isoparametric (curved or distorted) hexahedra.

scikit-fem builds a basis per batch of elements by evaluating every reference shape function and the mapping's
Jacobian anew, one function at a time (``MappingIsoparametric.J`` loops over the 27 geometry nodes for each of the
nine entries, ``invDF`` for each basis function). Here the reference values and gradients of the scalar element
and of the mesh's geometry element are evaluated once at the quadrature points, and per element only the
Jacobian DF = sum_a x_a (x) grad N_a (one ``einsum``), its inverse and determinant, and the physical gradients
grad phi_b = DF^-T grad_ref phi_b are formed, for all elements of a batch at once. The element matrices are
sums over the quadrature points,

    S[k, l, a, b] = sum_q w_q |det DF| dphi_a/dx_k dphi_b/dx_l,    M_ref[a, b] = sum_q w_q |det DF| phi_a phi_b,

taken as one batched matrix product, and combined with a part's constant material tensors as in
``modalfe.models.box_assembly`` (which integrates the same S on axis-aligned boxes in closed form), then summed
into its CSR pattern. The quadrature is scikit-fem's (``get_quadrature(RefHex, intorder)``) and the mapping the
mesh's own (``mesh.elem`` on ``mesh.doflocs``): the matrices are scikit-fem's to round-off
(tests/models/test_mapped_assembly.py).

Each element's DOFs are taken in the *canonical* order (the reference element's own, identity orientation): the
Gauss-Lobatto elements orient their edge and face nodes per element (``ElementHexGLL.slots``), so that one set of
reference shape functions serves every element.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from modalfe.models.box_assembly import VOIGT, elastic_matrices, pattern, piezo_matrices


def applies(mesh) -> bool:
    """Whether ``mesh`` is hexahedral (isoparametric mapping), where this assembly replaces scikit-fem's bases."""
    from skfem.refdom import RefHex

    return mesh.refdom is RefHex


def canonical_dofs(mesh, scalar, element_dofs: np.ndarray) -> np.ndarray:
    """Scalar DOFs (nloc, nel) of every element of ``mesh`` in the canonical order: row r holds the DOF of
    reference shape function r (``scalar.lbasis(X, r)``); ``element_dofs`` (nloc, nel) in scikit-fem's slots."""
    from modalfe.models.hex_elements import ElementHexGLL

    if not isinstance(scalar, ElementHexGLL):
        return element_dofs  # no per-element orientation
    q = scalar.p + 1
    ref = scalar.reference_slots  # (nloc, 3)
    lookup = np.full(q**3, -1)
    lookup[(ref[:, 0] * q + ref[:, 1]) * q + ref[:, 2]] = np.arange(len(ref))
    G = scalar.slots(mesh).astype(int)  # (3, nloc, nel): the grid node each slot carries
    rank = lookup[(G[0] * q + G[1]) * q + G[2]]  # (nloc, nel): the canonical row of each slot
    out = np.empty_like(element_dofs)
    out[rank, np.arange(element_dofs.shape[1])[None, :]] = element_dofs
    return out


class _Reference:
    """Quadrature (X (3, nq), W (nq,)) of order ``intorder`` on the reference cube, and at its points the scalar
    element's values ``phi`` (nq, nloc) and gradients ``dphi`` (nq, 3, nloc), and the geometry element's gradients
    ``dgeo`` (nq, 3, ngeo)."""

    def __init__(self, mesh, scalar, intorder: int):
        from skfem.quadrature import get_quadrature

        self.X, self.W = get_quadrature(mesh.refdom, intorder)
        values, grads = zip(*(scalar.lbasis(self.X, r) for r in range(len(scalar.doflocs))), strict=True)
        self.phi = np.array(values).T
        self.dphi = np.array(grads).transpose(2, 1, 0)
        geo = mesh.elem()  # the mesh's geometry element (a class on skfem meshes)
        self.dgeo = np.array([geo.lbasis(self.X, a)[1] for a in range(geo.doflocs.shape[0])]).transpose(2, 1, 0)

    def gradients(self, mesh, elements: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(physical gradients (nel, nq, nloc, 3) of the scalar shape functions, w_q |det DF| (nel, nq)) on
        ``elements`` of ``mesh``: DF[i, j] = sum_a x_a,i dN_a/dX_j over the geometry nodes x_a."""
        x = mesh.doflocs[:, mesh.dofs.element_dofs[:, elements]]  # (3, ngeo, nel)
        DF = np.einsum("iae,qja->eqij", x, self.dgeo, optimize=True)
        det = np.linalg.det(DF)
        inv = np.linalg.inv(DF)  # inv[..., i, j] = dX_i / dx_j
        G = np.einsum("eqij,qib->eqbj", inv, self.dphi, optimize=True)
        return G, np.abs(det) * self.W


_BATCH_BYTES = 150e6  # per batch of elements (its element matrices and gradients)


def _chunks(elements: np.ndarray, nloc: int, nq: int) -> list[np.ndarray]:
    """``elements`` in batches whose (3 nloc)^2 element matrices and nq x 3 nloc gradients stay near
    ``_BATCH_BYTES``."""
    size = max(1, int(_BATCH_BYTES // (8 * (9 * nloc * nloc + 4 * nq * 3 * nloc))))
    return [elements[i:i + size] for i in range(0, len(elements), size)]


def _stiffness_products(G: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """S (nel * nloc^2 (e, a, b), 9 (k, l)): S[k, l, a, b] = sum_q dx dphi_a/dx_k dphi_b/dx_l per element, from the
    gradients G (nel, nq, nloc, 3)."""
    nel, nq, nloc, _ = G.shape
    flat = G.reshape(nel, nq, 3 * nloc)
    # (nel, (a, k), (b, l)); einsum's BLAS route, 6x np.matmul's on stacks of small matrices (80 of 64 x 192)
    S = np.einsum("eqi,eqj->eij", flat * dx[:, :, None], flat, optimize=True)
    return S.reshape(nel, nloc, 3, nloc, 3).transpose(0, 1, 3, 2, 4).reshape(-1, 9)


def _summed(out: np.ndarray, at: np.ndarray, weights: np.ndarray) -> None:
    """Add the element entries ``weights`` (m, c) at the pattern positions ``at`` (m,) into ``out`` (nnz, c): sorted
    by position and reduced, so that a batch costs its own m entries, not the pattern's nnz (``np.bincount`` over the
    whole pattern cost 2.4 s a batch on a 138,000-DOF cubic model, this 0.45 s)."""
    order = np.argsort(at, kind="stable")
    rows, start = np.unique(at[order], return_index=True)
    out[rows] += np.add.reduceat(weights[order], start, axis=0)


def assemble_elastic(mesh, scalar, intorder: int, dofs: np.ndarray, parts: list[tuple[np.ndarray, object]],
                     n: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """K_uu and M_uu (3n, 3n) over the ``elements`` of ``parts`` ((elements, material) pairs, a material with
    constant ``C`` (6, 6) [Pa] and ``rho`` [kg/m^3]); ``dofs`` (nloc, all elements) canonical scalar DOFs
    (``canonical_dofs``), n scalar DOFs.

    K[3a+c, 3b+d] = sum_kl C_ckdl S[k, l, a, b] (C_ckdl the elastic tensor), M = rho M_ref x I_3, per element.
    """
    parts = [(elements, mat) for elements, mat in parts if len(elements)]
    if not parts:
        return sp.csr_matrix((3 * n, 3 * n)), sp.csr_matrix((3 * n, 3 * n))
    ref = _Reference(mesh, scalar, intorder)
    nloc = ref.phi.shape[1]
    pairs = (ref.phi[:, :, None] * ref.phi[:, None, :]).reshape(len(ref.W), -1)  # (nq, nloc^2)
    indptr, indices, pos = pattern(np.concatenate([dofs[:, elements] for elements, _ in parts], axis=1), n)
    data = np.zeros((len(indices), 10))  # K's 3 x 3 block, then the scalar mass
    start = 0
    for elements, mat in parts:
        C = mat.C[VOIGT[:, :, None, None], VOIGT].transpose(0, 2, 1, 3).reshape(9, 9)  # [(c, d), (k, l)]
        for chunk in _chunks(elements, nloc, len(ref.W)):
            G, dx = ref.gradients(mesh, chunk)
            at = pos[start * nloc * nloc:(start + len(chunk)) * nloc * nloc]
            mass = (mat.rho * dx @ pairs).reshape(-1, 1)
            _summed(data, at, np.hstack([_stiffness_products(G, dx) @ C.T, mass]))
            start += len(chunk)
    return elastic_matrices(indptr, indices, data[:, :9].reshape(-1, 3, 3), data[:, 9], n)


def assemble_piezo(mesh, scalar, intorder: int, dofs: np.ndarray, parts: list[tuple[np.ndarray, object]],
                   index: np.ndarray, n_phi: int, n_u: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """K_uphi (n_u, n_phi) and K_phiphi (n_phi, n_phi) over the ``elements`` of the piezo ``parts`` ((elements,
    material) pairs, constant ``e`` (3, 6) [C/m^2] and ``eps_S`` (3, 3) [F/m]); ``index`` maps scalar DOFs to
    potential unknowns.

    K_uphi[3a+c, b] = sum_kl e_l,ck S[k, l, a, b], K_phiphi[a, b] = sum_kl eps_kl S[k, l, a, b], per element.
    """
    parts = [(elements, mat) for elements, mat in parts if len(elements)]
    if not parts:
        return sp.csr_matrix((n_u, n_phi)), sp.csr_matrix((n_phi, n_phi))
    ref = _Reference(mesh, scalar, intorder)
    nloc = ref.phi.shape[1]
    indptr, indices, pos = pattern(np.concatenate([index[dofs[:, elements]] for elements, _ in parts], axis=1), n_phi)
    data = np.zeros((len(indices), 4))  # K_uphi's three components, then K_phiphi
    start = 0
    for elements, mat in parts:
        # [(k, l), c] e_l,ck for c = 0, 1, 2, then eps_kl
        tensors = np.hstack([np.einsum("lck->klc", mat.e[:, VOIGT]).reshape(9, 3), mat.eps_S.reshape(9, 1)])
        for chunk in _chunks(elements, nloc, len(ref.W)):
            G, dx = ref.gradients(mesh, chunk)
            at = pos[start * nloc * nloc:(start + len(chunk)) * nloc * nloc]
            _summed(data, at, _stiffness_products(G, dx) @ tensors)
            start += len(chunk)
    return piezo_matrices(indptr, indices, data[:, :3], data[:, 3], index, n_phi, n_u)
