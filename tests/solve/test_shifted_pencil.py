"""A - s B not formed (``linalg.Shifted``): its upper triangle from the pair's pencil is the formed matrix's, its
factorization and Sturm count are the formed matrix's, for every pair of symmetric patterns (B's within A's, as a
stiffness and its mass, or not), A's rows unsorted as a projection leaves them."""

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.linalg import eigh

from modalfe.solve import linalg


def _symmetric(rng: np.random.Generator, n: int, density: float, positive: bool) -> sp.csr_matrix:
    """A random symmetric sparse matrix in scipy's non-canonical form (unsorted rows, as a triple product leaves
    them); diagonally dominant where ``positive``."""
    R = sp.random(n, n, density=density, random_state=rng, format="coo")
    S = (R + R.T).tocsr()
    if positive:
        S = S + sp.diags(np.abs(S).sum(axis=1).A1 + 1.0)
    S = sp.csr_matrix(S)
    for r in range(n):  # shuffle each row's entries: the pencil must sort them itself
        lo, hi = S.indptr[r], S.indptr[r + 1]
        perm = lo + rng.permutation(hi - lo)
        S.indices[lo:hi], S.data[lo:hi] = S.indices[perm], S.data[perm]
    S.has_sorted_indices = False
    return S


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 40), nested=st.booleans(),
       shift=st.floats(-5.0, 5.0, allow_nan=False))
def test_the_pencils_upper_triangle_is_the_formed_matrixs(seed, n, nested, shift):
    """Entry for entry (exact: one multiply and one subtract per entry either way), on B's pattern within A's (then
    on A's pattern, from the pair's pencil, the same index arrays on every shift: PARDISO's analysis shared) or
    across it (formed), in the sorted rows PARDISO reads."""
    rng = np.random.default_rng(seed)
    A = _symmetric(rng, n, 0.3, positive=False)
    B = _symmetric(rng, n, 0.1, positive=True)
    if nested:
        A = A + abs(B) + sp.diags(np.ones(n))  # B's pattern within A's, as a stiffness holds its mass's
    uppers = [linalg.Shifted(A, B, s).upper() for s in (shift, 0.5 * shift + 1.0)]
    for s, ours in zip((shift, 0.5 * shift + 1.0), uppers):
        formed = sp.triu(A - s * B).tocsr()
        assert ours.has_canonical_format
        assert abs(ours - formed).max() == 0.0
    if nested:
        assert all(np.shares_memory(getattr(uppers[0], k), getattr(uppers[1], k)) for k in ("indices", "indptr"))


def test_a_shifted_factorization_solves_and_counts_as_the_formed_one():
    """A stiffness-like and a mass-like pencil (eigenvalues known by a dense solve): PARDISO's (or SuperLU's) solve of
    the shifted form matches the dense solve to 1e-10 (the matrices' condition number ~1e3 times rounding), and its
    negative count is the number of eigenvalues below the shift."""
    rng = np.random.default_rng(1)
    n = 60
    K = _symmetric(rng, n, 0.15, positive=True)
    M = sp.diags(rng.uniform(1.0, 2.0, n)).tocsr()
    lam = eigh(K.toarray(), M.toarray(), eigvals_only=True)
    shift = 0.5 * (lam[20] + lam[21])
    b = rng.standard_normal(n)
    for solver in linalg.available_solvers():
        solve, _ = linalg.factorize(linalg.Shifted(K, M, shift), solver=solver)
        expected = np.linalg.solve(K.toarray() - shift * M.toarray(), b)
        assert np.allclose(solve(b), expected, rtol=1e-10, atol=1e-10 * np.abs(expected).max())
        assert linalg.negative_eigenvalue_count(linalg.Shifted(K, M, shift), solver=solver) == 21
