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

from modalfe.models.box_assembly import VOIGT


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


_REFERENCES: dict[tuple, _Reference] = {}  # by geometry element, scalar element and quadrature: a few MB in all


def _reference(mesh, scalar, intorder: int) -> _Reference:
    """The ``_Reference`` of ``mesh``'s geometry element and ``scalar`` at ``intorder``, made once: evaluating the
    27-node geometry element's gradients took 0.1 s each time (skfem's ``ElementHex2.lbasis``)."""
    key = (mesh.elem, type(scalar), getattr(scalar, "p", None), intorder)
    if key not in _REFERENCES:
        _REFERENCES[key] = _Reference(mesh, scalar, intorder)
    return _REFERENCES[key]


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


class Elements:
    """The mapped ``parts`` ((elements, material) pairs) of ``mesh``, whose element matrices are added in batches into
    CSR data shared with the box elements (``modalfe.models.box_assembly.assemble_elastic``, ``assemble_piezo``):
    one pattern for both, no sum of two matrices of the model's size afterwards (0.4 s and 1 GB of fresh memory on
    the round-feet plate's quartic model). ``dofs`` (nloc, all elements): canonical scalar DOFs
    (``canonical_dofs``)."""

    def __init__(self, mesh, scalar, intorder: int, dofs: np.ndarray, parts: list[tuple[np.ndarray, object]]):
        self.mesh, self.scalar, self.intorder = mesh, scalar, intorder
        self.parts = [(elements, mat) for elements, mat in parts if len(elements)]
        self.dofs = np.concatenate([dofs[:, elements] for elements, _ in self.parts] + [dofs[:, :0]], axis=1)

    def _batches(self):
        """(reference, material, batch index range, gradients, w |det DF|) of each batch of elements."""
        ref = _reference(self.mesh, self.scalar, self.intorder)
        start = 0
        for elements, mat in self.parts:
            for chunk in _chunks(elements, ref.phi.shape[1], len(ref.W)):
                yield ref, mat, (start, start + len(chunk)), *ref.gradients(self.mesh, chunk)
                start += len(chunk)

    def add_elastic(self, data: np.ndarray, pos: np.ndarray) -> None:
        """Add K's 3 x 3 blocks and the scalar mass (``data`` (nnz, 10)) at the element entries' positions ``pos``
        (element, a, b; flat, in ``dofs``' element order). K[3a+c, 3b+d] = sum_kl C_ckdl S[k, l, a, b] (C_ckdl the
        elastic tensor), M = rho M_ref x I_3, per element."""
        for ref, mat, (i, j), G, dx in self._batches():
            nloc = ref.phi.shape[1]
            C = mat.C[VOIGT[:, :, None, None], VOIGT].transpose(0, 2, 1, 3).reshape(9, 9)  # [(c, d), (k, l)]
            pairs = (ref.phi[:, :, None] * ref.phi[:, None, :]).reshape(len(ref.W), -1)  # (nq, nloc^2)
            mass = (mat.rho * dx @ pairs).reshape(-1, 1)
            _summed(data, pos[i * nloc * nloc:j * nloc * nloc], np.hstack([_stiffness_products(G, dx) @ C.T, mass]))

    def add_piezo(self, data: np.ndarray, pos: np.ndarray) -> None:
        """Add K_uphi's three components and K_phiphi (``data`` (nnz, 4)) at ``pos`` as ``add_elastic``:
        K_uphi[3a+c, b] = sum_kl e_l,ck S[k, l, a, b], K_phiphi[a, b] = sum_kl eps_kl S[k, l, a, b]."""
        for ref, mat, (i, j), G, dx in self._batches():
            nloc = ref.phi.shape[1]
            # [(k, l), c] e_l,ck for c = 0, 1, 2, then eps_kl
            tensors = np.hstack([np.einsum("lck->klc", mat.e[:, VOIGT]).reshape(9, 3), mat.eps_S.reshape(9, 1)])
            _summed(data, pos[i * nloc * nloc:j * nloc * nloc], _stiffness_products(G, dx) @ tensors)
