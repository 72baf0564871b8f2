"""The map from a model's free unknowns to its full DOF vector (supports, grounded and floating electrodes), and
the projection of a full matrix onto the free unknowns that every solve starts from."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp


def free_values(T: sp.spmatrix, x_full: np.ndarray) -> np.ndarray:
    """Free unknowns x with T x = x_full, for x_full (ndofs,) or (ndofs, k) (T's columns are disjoint: a weighted
    pick)."""
    weights = np.asarray(T.multiply(T).sum(axis=0)).ravel()
    return (T.T @ x_full) / (weights if np.ndim(x_full) == 1 else weights[:, None])


def shared_unknowns(n: int, groups: list[np.ndarray], clamped: np.ndarray) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """(clamped, shared) of ``n`` DOFs where each of ``groups`` (DOF index arrays) is to move as one unknown (a
    multi-point constraint u_i = u_group, x_full = T x_free with one column summing the group): groups that share a
    DOF merge into one; a group holding a ``clamped`` DOF is clamped whole (its common value is zero)."""
    from scipy.sparse.csgraph import connected_components

    links = np.concatenate([np.stack([g[:-1], g[1:]]) for g in groups] + [np.zeros((2, 0), dtype=int)], axis=1)
    on = np.unique(np.concatenate([*groups, np.zeros(0, dtype=int)])).astype(int)
    if len(on) == 0:
        return clamped, ()
    _, label = connected_components(sp.coo_matrix((np.ones(links.shape[1]), (links[0], links[1])), shape=(n, n)),
                                    directed=False)
    held = np.isin(label[on], label[clamped])
    free = on[~held]
    order = np.argsort(label[free], kind="stable")
    shared = np.split(free[order], np.flatnonzero(np.diff(label[free][order])) + 1)
    return np.union1d(clamped, on[held]).astype(int), tuple(g for g in shared if len(g) > 1)


@dataclass(frozen=True, eq=False)
class Constraints:
    """x_full = T @ x_free; ``floating`` electrodes each carry one potential unknown (last columns)."""

    T: sp.csr_matrix
    potential_scale: float
    floating: tuple[str, ...]

    @cached_property
    def _picked(self) -> tuple[np.ndarray, np.ndarray, sp.csr_matrix] | None:
        """(rows, scales, rest): T's columns before the floating electrodes', each taking one full DOF (a free
        displacement, a scaled interior potential), as that DOF's row and scale; ``rest`` the floating electrodes'
        columns (each a sum of DOFs, or one DOF on a reduced model). None if a column before them is not one DOF."""
        Tc = sp.csc_matrix(self.T)
        n_picked = Tc.shape[1] - len(self.floating)
        if not np.all(np.diff(Tc.indptr[: n_picked + 1]) == 1):
            return None
        first = Tc.indptr[:n_picked]
        return Tc.indices[first], Tc.data[first], sp.csr_matrix(Tc[:, n_picked:])

    def _below(self, X: sp.csr_matrix) -> sp.csr_matrix:
        """rest^T X: the floating electrodes' rows of X summed and scaled (CSR by CSR: a CSC left factor would
        convert X whole)."""
        return sp.csr_matrix(self._picked[2].T) @ X

    def border(self, X: sp.spmatrix) -> tuple[np.ndarray, np.ndarray]:
        """(b (n - m, m), c (m, m)): the last m rows and columns of T^T X T (symmetric ``X``; m floating electrodes),
        their coupling with the other unknowns and their own block, without the rest of the projection."""
        X, m = sp.csr_matrix(X), len(self.floating)
        if self._picked is None:
            full = self.project(X)
            n = full.shape[0] - m
            return full[n:, :n].toarray().T, full[n:, n:].toarray()
        rows, scales, rest = self._picked
        below = self._below(X)
        return (below[:, rows] @ sp.diags(scales)).toarray().T, (below @ rest).toarray()

    def project(self, X: sp.spmatrix, *, picked: sp.csr_matrix | None = None) -> sp.csr_matrix:
        """T^T X T (CSR) of a full (ndofs, ndofs) matrix ``X``: the picked block by row and column indexing, scaled,
        bordered by the few ``rest`` columns and rows. Same result as the sparse triple product, which for quartic
        elements (~550 nonzeros a row) took ~4x as long (0.45 s against 0.12 s on the Cu-Be plate's 32,184 DOFs).
        ``picked``: that block when already made (an open circuit's is the short circuit's whole projection). Any
        other T: the triple product."""
        X = sp.csr_matrix(X)
        if self._picked is None:
            return (self.T.T @ X @ self.T).tocsr()
        rows, scales, rest = self._picked
        if picked is None:
            picked = X[rows][:, rows]
            picked.data *= scales[picked.indices]
            picked.data *= np.repeat(scales, np.diff(picked.indptr))
        elif picked.shape != (len(rows), len(rows)):
            raise ValueError(f"picked: a {picked.shape} block for {len(rows)} picked unknowns")
        if rest.shape[1] == 0:
            return picked
        right = sp.csr_matrix(sp.diags(scales) @ (X @ rest)[rows])
        below = self._below(X)
        bottom = sp.hstack([below[:, rows] @ sp.diags(scales), below @ rest], format="csr")
        return bordered(picked, right, bottom)


def bordered(block: sp.csr_matrix, right: sp.csr_matrix, bottom: sp.csr_matrix) -> sp.csr_matrix:
    """[block, right; bottom] in CSR for a large ``block`` (n, n) bordered by a few columns ``right`` (n, m) and rows
    ``bottom`` (m, n + m): right's entries inserted at the end of their rows, bottom's after the last row, so that
    block's entries are copied once (none where the border is empty: its arrays are shared), explicit zeros kept, and
    the result canonical where the blocks are. A general hstack and vstack copied the block twice, through slower
    paths (0.32 s against 0.05 s on the Cu-Be plate's projection; 0.3-0.9 s and 240 MB of fresh memory on its quartic
    round-feet model's K)."""
    n = block.shape[0] + right.shape[1]
    if right.nnz == 0 and bottom.nnz == 0:  # (a mass matrix: no inertia on the potentials)
        indptr = np.concatenate([block.indptr, np.full(right.shape[1], block.nnz, dtype=block.indptr.dtype)])
        return sp.csr_matrix((block.data, block.indices, indptr), shape=(n, n))
    at = np.concatenate([block.indptr[np.repeat(np.arange(block.shape[0]), np.diff(right.indptr)) + 1],
                         np.full(bottom.nnz, block.nnz)])
    data = np.insert(block.data, at, np.concatenate([right.data, bottom.data]))
    indices = np.insert(block.indices, at, np.concatenate([right.indices + block.shape[0], bottom.indices]))
    top_indptr = block.indptr + right.indptr
    indptr = np.concatenate([top_indptr, top_indptr[-1] + bottom.indptr[1:]])
    return sp.csr_matrix((data, indices, indptr), shape=(n, n))
