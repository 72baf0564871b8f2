"""A solve at one shift from the factorization kept at another (``shifted_solve``): as accurate as a new
factorization, without one; a factorization where the kept one cannot serve."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh, spsolve

from modalfe.errors import SolverError
from modalfe.solve import linalg


def _pencil(n: int = 400) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """A fixed-free string: K tridiagonal (stiffness), M diagonal (lumped mass), eigenvalues (k pi / 2n)^2 n^2-ish."""
    K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")
    K[n - 1, n - 1] = 1.0
    M = sp.diags(np.linspace(1.0, 2.0, n), format="csr")
    return K, M


def _count_factorizations(monkeypatch) -> list:
    made = []
    factorize = linalg.factorize

    def counted(A, **kwargs):
        made.append(A.shape)
        return factorize(A, **kwargs)

    monkeypatch.setattr(linalg, "factorize", counted)
    return made


def test_a_shift_beside_the_kept_one_solves_as_a_new_factorization_would_without_one(monkeypatch):
    K, M = _pencil()
    lam = np.sort(eigsh(K, k=6, M=M, sigma=0.0, which="LM")[0])
    sigma, shift = 0.5 * (lam[3] + lam[4]), 0.97 * lam[3]  # forced's: the eigen solve's shift, 0.97 omega_r^2
    kept = (linalg.factorize(K - sigma * M)[0], sigma)
    made = _count_factorizations(monkeypatch)
    b = np.random.default_rng(1).standard_normal(K.shape[0])
    x = linalg.shifted_solve(K, M, shift, kept)(b)
    assert made == []
    exact = spsolve((K - shift * M).tocsc(), b)
    # a direct solve's accuracy: relative residual below SHIFTED_RESIDUAL, the error its condition number times that
    assert np.linalg.norm(b - (K - shift * M) @ x) <= linalg.SHIFTED_RESIDUAL * np.linalg.norm(b)
    assert np.allclose(x, exact, rtol=0, atol=1e-8 * np.abs(exact).max())


def test_the_kept_shift_itself_is_the_kept_solve():
    K, M = _pencil()
    solve = linalg.factorize(K - 0.3 * M)[0]
    assert linalg.shifted_solve(K, M, 0.3, (solve, 0.3)) is solve


def test_where_the_kept_factorization_cannot_serve_the_shift_is_factorized(monkeypatch):
    K, M = _pencil()
    lam = np.sort(eigsh(K, k=3, M=M, sigma=0.0, which="LM")[0])
    kept = (linalg.factorize(K - 0.5 * lam[1] * M)[0], 0.5 * lam[1])
    made = _count_factorizations(monkeypatch)
    monkeypatch.setattr(linalg, "SHIFTED_ITERATIONS", 1)  # one Krylov step cannot converge: a factorization instead
    b = np.ones(K.shape[0])
    solve = linalg.shifted_solve(K, M, 0.9 * lam[1], kept)
    x, y = solve(b), solve(2 * b)
    assert len(made) == 1  # once, for every later solve too
    assert np.allclose(x, spsolve((K - 0.9 * lam[1] * M).tocsc(), b), rtol=1e-9) and np.allclose(y, 2 * x)


def test_a_singular_shift_fails_as_a_factorization_does(monkeypatch):
    K, M = _pencil(50)
    kept = (linalg.factorize(K - 0.1 * M)[0], 0.1)
    monkeypatch.setattr(linalg, "factorize", lambda A, **kw: (_ for _ in ()).throw(SolverError("singular")))
    with pytest.raises(SolverError):  # GMRES cannot converge on a singular matrix: the factorization says why
        linalg.shifted_solve(sp.csr_matrix(K.shape), M, 0.0, kept)(np.ones(50))  # the zero matrix
