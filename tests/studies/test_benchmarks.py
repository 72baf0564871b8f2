"""The quick paths of studies/benchmark_fidelity.py and studies/benchmark_solvers.py (issue 6, items 3 and 4):
they run end to end and measure something real. No timing is asserted beyond being positive: these
machines are shared and noisy."""

import csv
import math

import pytest

from modalfe.solve.linalg import available_solvers
from tests.helpers import load_study

FIDELITY = load_study("benchmark_fidelity")  # first: benchmark_solvers imports it by name
SOLVERS = load_study("benchmark_solvers")


def test_fidelity_benchmark_quick(tmp_path):
    result = FIDELITY.main(["--quick", "--out", str(tmp_path)])
    curves = {(p.device, p.fidelity) for p in result.points}
    assert curves == {("ciliary_beam", "solid"), ("ciliary_beam", "beam")}
    for p in result.points:
        assert p.dofs > 0 and p.total > 0 and p.peak_rss_mb > 0
        assert all(p.seconds[s] > 0 for s in FIDELITY.FITTED)
        # every point is compared with the extrapolated 3-D reference; the beam model and the coarse
        # solid levels are within 20 % of it (the quick levels are coarse, not converged)
        assert 0 < p.error < 0.2
    f_ref, spread = result.references["ciliary_beam"]
    assert math.isfinite(f_ref) and math.isfinite(spread)
    assert all(math.isfinite(v) for fit in result.exponents.values() for v in fit.values())
    assert set(result.dominant.values()) <= set(FIDELITY.FITTED)
    with (tmp_path / "benchmark_fidelity.csv").open() as fh:
        assert len(list(csv.DictReader(fh))) == len(result.points)
    assert (tmp_path / "benchmark_fidelity.png").stat().st_size > 0


@pytest.mark.skipif("pardiso" not in available_solvers(), reason="PARDISO (MKL) not available: nothing to compare")
def test_solver_benchmark_quick(tmp_path):
    result = SOLVERS.main(["--quick", "--out", str(tmp_path)])
    assert len(result.rows) == len(SOLVERS.QUICK_FACTORS)
    for superlu, pardiso in result.rows:
        assert superlu.dofs == pardiso.dofs > 0
        assert superlu.total > 0 and pardiso.total > 0
        # both factorizations pass modalfe's residual check (< 1e-6) and ARPACK runs at tol 1e-8:
        # the same eigenvalues to far better than 1e-6 relative
        assert SOLVERS.frequency_difference(superlu, pardiso) < 1e-6
    assert all(math.isfinite(v) for fit in result.exponents.values() for v in fit.values())
    assert "PARDISO faster at" in result.conclusion
    with (tmp_path / "benchmark_solvers.csv").open() as fh:
        assert len(list(csv.DictReader(fh))) == 2 * len(result.rows)


def test_bad_cli_input_is_one_line_error(capsys):
    with pytest.raises(SystemExit):
        FIDELITY.main(["--solid-factors", "1.0"])
    assert "at least two" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        SOLVERS.main(["--factors", "0"])
    assert "must be positive" in capsys.readouterr().err
