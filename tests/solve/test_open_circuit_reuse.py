"""An open-circuit solve of a model solved in short circuit borders that solve's matrices and, at its shift, reuses
its factorization (bordered by the floating electrode's potential), and gives the modes a fresh solve gives."""

import numpy as np

from modalfe import solve_modes
from modalfe.scene import load_scene
from modalfe.solve import levels, resolved


def test_open_circuit_reuses_the_short_circuit_factorization():
    scene = load_scene("ciliary_beam")
    options = {"near": 21.7e3, "count": 6, "fidelity": "solid", "error_estimate": False}
    short = solve_modes(scene, **options)
    reused = solve_modes(scene, circuit="open", **options)
    levels._SHORT_SOLVES.clear()
    resolved.clear(disk=True)  # the answer kept would be read back: solve it afresh
    fresh = solve_modes(scene, circuit="open", **options)
    assert reused.timings["solver"] == "reused" and fresh.timings["solver"] != "reused"
    # the same linear algebra up to round-off (ARPACK's tolerance 1e-8 bounds the eigenvalues' difference)
    assert np.allclose(reused.frequencies, fresh.frequencies, rtol=1e-8, atol=0)
    # open circuit stiffens the driven bending modes: fa > fr for the working mode
    fr, fa = short.nearest(21.7e3).frequency, reused.nearest(21.7e3).frequency
    assert fa > fr


def test_another_shift_factorizes_afresh():
    scene = load_scene("ciliary_beam")
    solve_modes(scene, near=21.7e3, count=4, fidelity="solid", error_estimate=False)
    other = solve_modes(scene, near=15e3, count=4, circuit="open", fidelity="solid", error_estimate=False)
    assert other.timings["solver"] != "reused"


def test_open_circuit_of_an_undriven_scene_after_a_short_one_at_the_same_shift():
    # no floating electrode: the open circuit is the short one (was a traceback: a border of no columns)
    from modalfe.scene import scene_from_dict

    scene = scene_from_dict({"name": "bare", "kind": "plate", "analysis": {"near": 36e3, "count": 4},
                             "parts": [{"name": "plate", "region": "plate", "material": "CuBe", "origin": [0, 0, 0],
                                        "size": [64e-3, 38e-3, 3e-3]}], "mesh": {"elements_per_wavelength": 3}})
    options = {"near": 36e3, "count": 4, "fidelity": "solid", "error_estimate": False}
    short = solve_modes(scene, **options)
    open_ = solve_modes(scene, circuit="open", **options)
    assert np.allclose(open_.frequencies, short.frequencies, rtol=1e-8, atol=0)


def test_a_kept_factorization_does_not_keep_its_model_alive():
    import gc
    import weakref

    from modalfe.models.build import forget_models

    levels._SHORT_SOLVES.clear()
    modes = solve_modes(load_scene("ciliary_beam"), near=21.7e3, count=4, fidelity="solid", error_estimate=False)
    model = weakref.ref(modes.model)
    assert [kept.model() for kept in levels._SHORT_SOLVES] == [model()]
    del modes
    forget_models()
    resolved.clear(disk=True)
    gc.collect()
    assert model() is None  # only the build cache held it; the kept factorization did not
    assert [kept.model() for kept in levels._SHORT_SOLVES] == [None]  # a dead entry, dropped at the next solve
    solve_modes(load_scene("ciliary_beam"), near=15e3, count=4, fidelity="beam", error_estimate=False)
    assert all(kept.model() is not None for kept in levels._SHORT_SOLVES)


def test_two_floating_electrodes_reuse_gives_the_fresh_modes():
    # two driven electrode groups float as two unknowns: the border has two columns, each solved through the
    # short-circuit factorization (a strided column of a C-ordered array was read as contiguous memory by
    # PARDISO: open-circuit frequencies off by up to the coupling itself, silently)
    from tests.oracles.cases import two_patch_bar_scene

    scene = two_patch_bar_scene()
    options = {"near": 47e3, "count": 6, "fidelity": "solid", "error_estimate": False}
    solve_modes(scene, **options)
    reused = solve_modes(scene, circuit="open", **options)
    levels._SHORT_SOLVES.clear()
    resolved.clear(disk=True)  # the answer kept would be read back: solve it afresh
    fresh = solve_modes(scene, circuit="open", **options)
    assert reused.timings["solver"] == "reused" and fresh.timings["solver"] != "reused"
    assert reused.model.constraints("open").floating == ("top_left", "top_right")
    assert np.allclose(reused.frequencies, fresh.frequencies, rtol=1e-8, atol=0), (reused.frequencies,
                                                                                   fresh.frequencies)


def test_a_factorization_solves_strided_and_block_right_hand_sides():
    import scipy.sparse as sp

    from modalfe.solve.linalg import available_solvers, factorize

    rng = np.random.default_rng(3)
    n = 200
    R = sp.random(n, n, density=0.05, random_state=4)
    A = (R + R.T + sp.diags(np.linspace(-3, 5, n))).tocsr()  # symmetric indefinite, regular
    B = rng.standard_normal((n, 3))
    for name in available_solvers():
        solve, _ = factorize(A, solver=name)
        X = solve(B)
        assert X.shape == B.shape
        assert np.linalg.norm(A @ X - B) <= 1e-10 * np.linalg.norm(B), name
        for j in range(3):  # a column of a C-ordered array is strided
            assert np.allclose(solve(B[:, j]), X[:, j], rtol=1e-10, atol=1e-12), name


def test_the_open_circuit_partner_is_found_among_few_modes_by_shape(monkeypatch):
    # the partner by shape (mass-weighted MAC on the same model) from a solve of a few modes is the label-paired
    # one of the solve of all the short circuit's modes; modes that do not hold it are refused, not paired
    import pytest

    from modalfe.errors import SolverError
    from modalfe.results.coupling import antiresonance
    from modalfe.solve import api

    scene = load_scene("ciliary_beam")
    short = solve_modes(scene, near=21.7e3, count=10, fidelity="solid", error_estimate=False)
    mode = short.nearest(21.7e3)
    asked = []
    solve_open, solve_few = api.open_circuit_modes, api._open_solve
    monkeypatch.setattr(api, "_open_solve", lambda model, near, count, solver, known: asked.append(count)
                        or solve_few(model, near, count, solver, known))
    partner = api.open_circuit_partner(mode, among=short, near=21.7e3)
    every = solve_open(short, near=21.7e3, count=10)
    labelled = min((m for m in every if m.label == mode.label), key=lambda m: abs(m.frequency - mode.frequency))
    assert asked and asked[0] < 10
    assert partner.frequency == pytest.approx(labelled.frequency, rel=1e-8) and partner.frequency > mode.frequency
    far = solve_open(short, near=2 * mode.frequency, count=2)  # two modes far above: not the partner
    with pytest.raises(SolverError, match="no open-circuit mode with the shape"):
        antiresonance(mode, far)


def test_a_kept_solve_holds_its_factorization_and_projects_its_pencil_when_asked():
    """The short-circuit solve kept for its model holds the factorization, not the projected pencil (A, B) it solved
    on (~40 % of the model's memory, under every solve that follows: ``levels._ShortSolve.projected``). The open
    circuit at its shift reuses the factorization and projects its own, bordered pencil only (not the short one
    too); a forced response asks for the short pencil (``short_circuit_pencil``): it is projected then, once, equal
    to the pencil a fresh projection gives."""
    levels._SHORT_SOLVES.clear()
    resolved.clear(disk=True)
    scene = load_scene("ciliary_beam")
    options = {"near": 21.7e3, "count": 4, "fidelity": "solid", "error_estimate": False}
    short = solve_modes(scene, **options)
    (kept,) = [k for k in levels._SHORT_SOLVES if k.model() is short.model]
    assert kept.pencil is None and kept.factor is not None
    reused = solve_modes(scene, circuit="open", **options)
    assert reused.timings["solver"] == "reused" and kept.pencil is None
    A, B, factor = levels.short_circuit_pencil(short.model)
    assert factor is kept.factor and kept.pencil is not None
    constraints = short.model.constraints("short")
    for kept_matrix, matrix in zip((A, B), (short.model.K, short.model.M), strict=True):
        assert abs(kept_matrix - constraints.project(matrix)).max() == 0.0
    assert kept.projected()[0] is A  # projected once
