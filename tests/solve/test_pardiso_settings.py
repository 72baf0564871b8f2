"""PARDISO's settings (``modalfe.solve.linalg``): MKL's defaults but for the ordering of dense-row matrices (minimum
degree) and the iterative refinement (off, back on where a factorization's residual needs it); the answers stay
those of SuperLU."""

import dataclasses

import numpy as np
import pytest

from modalfe.models.build import build_model
from modalfe.scene import load_scene
from modalfe.solve import linalg

pytestmark = pytest.mark.skipif("pardiso" not in linalg.available_solvers(), reason="PARDISO (MKL) not installed")


def _shifted(order: int, size_factor: float, hz: float = 24.2e3):
    """A - sigma B of the ciliary beam (PZT sheets: symmetric indefinite, potentials without inertia)."""
    scene = load_scene("ciliary_beam")
    scene = dataclasses.replace(scene, mesh=dataclasses.replace(scene.mesh, order=order,
                                                                 min_layers=1 if order > 2 else 3))
    model, _ = build_model(scene, "solid", size_factor=size_factor)
    T = model.constraints("short").T
    A, B = (T.T @ model.K @ T).tocsr(), (T.T @ model.M @ T).tocsr()
    return (A - (2 * np.pi * hz) ** 2 * B).tocsr()


@pytest.mark.parametrize(("order", "size_factor", "ordering"), [(4, 3.0, 0), (2, 1.5, 3)])
def test_orders_by_minimum_degree_only_dense_rows_and_solves_without_refinement(order, size_factor, ordering):
    # quartic Lagrange: ~530 nonzeros a row, minimum degree; quadratic serendipity: ~130, MKL's nested dissection (3)
    K = _shifted(order, size_factor)
    assert (K.nnz / K.shape[0] >= linalg.MINIMUM_DEGREE_ROWS) == (ordering == 0)
    solve, name = linalg.factorize(K, solver="pardiso")
    assert name == "pardiso" and solve._analysis._ps.iparm[1] == ordering and solve.iparm[7] == 0
    b = np.random.default_rng(2).standard_normal(K.shape[0])
    # bare solves of these models reach ~1e-12 (refinement stayed off): below the level that switches it on
    assert np.linalg.norm(K @ solve(b) - b) <= linalg.REFINED_ABOVE * np.linalg.norm(b)
    # the inertia (a Sturm count) does not depend on the ordering: SuperLU's LDL^T agrees
    assert linalg.negative_eigenvalue_count(K, solver="pardiso") == linalg.negative_eigenvalue_count(
        K, solver="superlu")


def test_a_residual_above_the_threshold_turns_refinement_on(monkeypatch):
    K = _shifted(4, 3.0)
    monkeypatch.setattr(linalg, "REFINED_ABOVE", 0.0)  # every residual is above it
    solve, _ = linalg.factorize(K, solver="pardiso")
    assert solve.iparm[7] == 2  # MKL's two steps on every solve from then on
    b = np.random.default_rng(5).standard_normal(K.shape[0])
    assert np.linalg.norm(K @ solve(b) - b) <= 1e-10 * np.linalg.norm(b)


def test_upper_triangle_is_scipys_triu():
    import scipy.sparse as sp

    rng = np.random.default_rng(5)
    keep = (np.arange(300) != 7).astype(float)  # row 7 empty
    R = sp.csr_matrix(sp.diags(keep) @ sp.random(300, 300, density=0.03, random_state=6, format="csr"))
    R.eliminate_zeros()
    assert R[7].nnz == 0
    for A in (R, R + R.T, _shifted(2, 3.0)):
        expected = sp.triu(A, format="csr")
        upper = linalg.upper_triangle(sp.csr_matrix(A))
        assert upper.shape == A.shape and (upper != expected).nnz == 0
    duplicated = sp.csr_matrix((rng.standard_normal(4), [1, 1, 2, 0], [0, 2, 3, 4]), shape=(3, 3))  # (0, 1) twice
    assert not duplicated.has_canonical_format
    assert np.array_equal(linalg.upper_triangle(duplicated).toarray(), sp.triu(duplicated).toarray())


def test_shifts_of_one_pattern_share_one_analysis_and_each_keeps_its_own_numbers():
    K = _shifted(2, 3.0)
    M = _shifted(2, 3.0, hz=30e3)  # the same pattern, other values (a second shift of the same pencil)
    solve_k, _ = linalg.factorize(K, solver="pardiso")
    solve_m, _ = linalg.factorize(M, solver="pardiso")
    assert solve_k._analysis is solve_m._analysis and solve_k._mnum != solve_m._mnum
    b = np.random.default_rng(3).standard_normal(K.shape[0])
    for A, solve in ((K, solve_k), (M, solve_m)):  # each slot solves its own matrix to a direct solve's residual
        assert np.linalg.norm(A @ solve(b) - b) <= linalg.REFINED_ABOVE * np.linalg.norm(b)
    analysis = solve_k._analysis
    del solve_k, solve_m, solve  # the last factorization frees the handle; a new one analyses afresh
    assert not analysis.analysed and len(analysis.free) == linalg.SHARED_FACTORS
    again, _ = linalg.factorize(K, solver="pardiso")
    assert np.linalg.norm(K @ again(b) - b) <= linalg.REFINED_ABOVE * np.linalg.norm(b)


def test_more_factorizations_than_slots_open_another_analysis():
    K = _shifted(2, 3.0)
    kept = [linalg.factorize(K * (1 + 0.01 * i), solver="pardiso")[0] for i in range(linalg.SHARED_FACTORS + 1)]
    assert len({id(s._analysis) for s in kept}) == 2
    b = np.random.default_rng(4).standard_normal(K.shape[0])
    assert np.linalg.norm(K * (1 + 0.01 * linalg.SHARED_FACTORS) @ kept[-1](b) - b) <= 1e-10 * np.linalg.norm(b)


def test_an_analysis_is_shared_only_under_its_own_thread_count():
    # a numeric factorization under one MKL thread on an analysis made with two crashed MKL (segmentation fault)
    K = _shifted(2, 3.0)
    from threadpoolctl import threadpool_limits

    outside, _ = linalg.factorize(K, solver="pardiso")
    with threadpool_limits(limits=1, user_api="blas"):  # every BLAS, MKL included (a caller's own limit)
        inside, _ = linalg.factorize(K * 1.01, solver="pardiso")
        again, _ = linalg.factorize(K * 1.02, solver="pardiso")
    assert (inside._analysis is outside._analysis) == (inside._analysis.threads == outside._analysis.threads)
    assert again._analysis is inside._analysis
    b = np.random.default_rng(6).standard_normal(K.shape[0])
    assert np.linalg.norm(K * 1.01 @ inside(b) - b) <= linalg.REFINED_ABOVE * np.linalg.norm(b)


def test_a_handle_solved_under_other_threads_is_not_shared_again():
    # a solve under one MKL thread on a factorization made with two, then a numeric factorization with two on the same
    # handle, crashed MKL (the sensitivities' factorization beside a kept eigen solve that GMRES had used)
    K = _shifted(2, 3.0)
    kept, _ = linalg.factorize(K, solver="pardiso")
    b = np.random.default_rng(7).standard_normal(K.shape[0])
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):  # every BLAS, MKL included (a caller's own limit)
        kept(b)
    other, _ = linalg.factorize(K * 1.01, solver="pardiso")
    assert (other._analysis is kept._analysis) == (kept._analysis.threads == 1)  # shared only on a 1-thread machine
    assert np.linalg.norm(K * 1.01 @ other(b) - b) <= linalg.REFINED_ABOVE * np.linalg.norm(b)


def test_single_threaded_blas_leaves_pardiso_its_threads():
    # the context limits OpenBLAS only: a limit on every BLAS reached MKL only where it was loaded before the context
    # was entered, so that the same factorization ran on one or two threads by call order
    from threadpoolctl import threadpool_info

    linalg.factorize(_shifted(2, 3.0), solver="pardiso")  # MKL loaded
    before = {d["internal_api"]: d["num_threads"] for d in threadpool_info()}
    with linalg.single_threaded_blas():
        inside = [(d["internal_api"], d["num_threads"]) for d in threadpool_info()]
    assert ("mkl", before["mkl"]) in inside
    assert all(n == 1 for api, n in inside if api == "openblas")


def test_one_matrix_factorizes_to_the_same_bits_every_time():
    # issue 35, determinism: MKL's conditional numerical reproducibility on PARDISO's threads (iparm[33]); without it
    # five factorizations of this matrix solved to different bits in 2 of 4 runs (the Cu-Be plate: 2 of 3)
    A = _shifted(2, 0.7)
    b = np.random.default_rng(1).standard_normal(A.shape[0])
    solves = [linalg.factorize(A, solver="pardiso")[0](b) for _ in range(5)]
    assert all(np.array_equal(x, solves[0]) for x in solves[1:])
