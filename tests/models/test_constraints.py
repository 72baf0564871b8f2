"""``Constraints.project`` (T^T X T by indexing, bordered by the floating electrodes' columns) against the sparse
triple product it replaces, for both circuits, a clamped piezo model with two floating electrodes, and matrices that
are not symmetric or not real."""

import numpy as np
import pytest
import scipy.sparse as sp

from modalfe.models.build import build_model
from tests.oracles.cases import two_patch_bar_scene


@pytest.fixture(scope="module")
def model():
    scene = two_patch_bar_scene(faces={"end": ["left.xmin"]}, clamps={"end": "xyz"})
    return build_model(scene, "solid")[0]


def _same(A, T, X) -> bool:
    """A equals T^T X T up to round-off: each entry is the same few products (the potentials scaled by ~1e9, so
    the entries span ~20 decades: relative 1e-12 each, and 1e-14 of the largest for the entries that cancel)."""
    expected = (T.T @ X @ T).toarray()
    return np.allclose(A.toarray(), expected, rtol=1e-12, atol=1e-14 * np.abs(expected).max())


@pytest.mark.parametrize("circuit", ["short", "open"])
def test_projection_is_the_triple_product(model, circuit):
    constraints = model.constraints(circuit)
    assert len(model.clamped) > 0 and model.n_phi > 0
    assert len(constraints.floating) == (2 if circuit == "open" else 0)
    for X in (model.K, model.M):
        A = constraints.project(X)
        assert A.format == "csr" and A.shape == (constraints.T.shape[1],) * 2
        assert _same(A, constraints.T, X)


def test_projection_of_a_matrix_neither_symmetric_nor_real(model):
    rng = np.random.default_rng(1)
    n = model.ndofs
    R = sp.random(n, n, density=0.01, random_state=2, format="csr")
    X = (model.K + 1e9 * R + 1j * 1e8 * R.T).tocsr()
    constraints = model.constraints("open")
    A = constraints.project(X)
    assert _same(A, constraints.T, X)
    x = rng.standard_normal(A.shape[0])
    assert np.allclose(A @ x, constraints.T.T @ (X @ (constraints.T @ x)), rtol=1e-12, atol=0)


def test_open_circuit_borders_the_short_circuit_projection(model):
    short, open_ = model.constraints("short"), model.constraints("open")
    A_short = short.project(model.K)
    bordered = open_.project(model.K, picked=A_short)
    assert np.allclose(bordered.toarray(), open_.project(model.K).toarray(), rtol=0, atol=0)
    with pytest.raises(ValueError, match="picked"):
        open_.project(model.K, picked=A_short[:-1, :-1])


def test_a_floating_electrode_of_one_unknown_and_other_maps():
    # a reduced model's electrode can be one potential unknown: its column picks one DOF, yet it is the border
    from modalfe.models.constraints import Constraints

    rng = np.random.default_rng(7)
    R = sp.random(6, 6, density=0.6, random_state=8, format="csr")
    X = (R + R.T + sp.eye(6)).tocsr()
    one = sp.csr_matrix((np.array([1.0, 1.0, 2.0, 2.0]), ([0, 1, 3, 5], [0, 1, 2, 3])), shape=(6, 4))
    short = Constraints(one[:, :3], 2.0, ())
    open_ = Constraints(one, 2.0, ("top",))
    for c in (short, open_):
        assert _same(c.project(X), c.T, X)
    assert _same(open_.project(X, picked=short.project(X)), open_.T, X)
    general = Constraints(sp.csr_matrix(rng.standard_normal((6, 3))), 1.0, ())  # no column picks one DOF
    assert general._picked is None and _same(general.project(X), general.T, X)
