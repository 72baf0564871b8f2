"""An open-circuit solve at the shift of a short-circuit one reuses its factorization (bordered by the floating
electrode's potential) and gives the modes a fresh factorization gives."""

import numpy as np

from modalfe import solve_modes
from modalfe.scene import load_scene
from modalfe.solve import levels


def test_open_circuit_reuses_the_short_circuit_factorization():
    scene = load_scene("ciliary_beam")
    options = {"near": 21.7e3, "count": 6, "fidelity": "solid", "error_estimate": False}
    short = solve_modes(scene, **options)
    reused = solve_modes(scene, circuit="open", **options)
    levels._SHORT_FACTORS.clear()
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
