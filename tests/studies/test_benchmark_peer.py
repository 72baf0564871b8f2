"""studies/benchmark_peer.py: its quick path runs both codes end to end, and its reference and
time-to-target arithmetic recovers known answers."""

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers import load_study

pytest.importorskip("ngsolve")

SCRIPT = Path(__file__).resolve().parents[2] / "studies" / "benchmark_peer.py"


def _study():
    return load_study("benchmark_peer")


def test_richardson_recovers_the_limit_of_a_power_law():
    study = _study()
    # f = f_inf + c N^(-4/3) (order 4 in h) on unevenly spaced DOF counts: the fit is exact
    points = [{"dofs": n, "frequency": 36e3 + 5e6 * n ** (-4 / 3)} for n in (3000, 8000, 21000, 70000)]
    f_inf, order = study.richardson(points)
    assert f_inf == pytest.approx(36e3, rel=1e-9)
    assert order == pytest.approx(4.0, rel=1e-6)
    # not monotone: no extrapolation, the finest point and no order
    f_inf, order = study.richardson([{"dofs": 1, "frequency": 3.0}, {"dofs": 2, "frequency": 1.0},
                                     {"dofs": 3, "frequency": 2.0}])
    assert f_inf == 2.0 and math.isnan(order)


def test_time_to_target_interpolates_log_log_between_bracketing_points():
    study = _study()
    points = [{"error": 1e-2, "total": 1.0, "dofs": 1000}, {"error": 1e-4, "total": 100.0, "dofs": 100000}]
    seconds, dofs, exact = study.time_to_target(points)
    # 1e-3 is halfway in log error between 1e-2 and 1e-4, so halfway in log time and log DOFs
    assert exact and seconds == pytest.approx(10.0) and dofs == pytest.approx(10000.0)
    assert study.time_to_target(points[:1])[2] is False and math.isnan(study.time_to_target(points[:1])[0])


def test_quick_run_both_codes_find_the_same_modes(tmp_path):
    done = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--repeats", "1", "--out", str(tmp_path)],
                          capture_output=True, text=True, check=False, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    results = json.loads((tmp_path / "benchmark_peer.json").read_text())
    assert (tmp_path / "benchmark_peer.png").stat().st_size > 0
    # finest quick levels: both codes converge from above to one frequency; on these meshes they are
    # 0.74 % apart on the plate (36.54 / 36.81 kHz) and 0.20 % on the beam (21.648 / 21.605 kHz). The
    # tolerances catch a wrong mode: the plate's (2,5) and (1,6) sit 2.9 % and 7.9 % above (0,6), the
    # beam's bending-y 6 1.0 % below bending-z 6
    for case, converged, rel in (("plate", 36.30e3, 0.02), ("beam", 21.54e3, 0.005)):
        ours, peer = results[case]["modalfe"], results[case]["NGSolve"]
        for points in (ours, peer):
            assert all(p["total"] > 0 and p["factorization"] > 0 and p["peak_rss_mb"] > 0 for p in points)
            assert [p["dofs"] for p in points] == sorted(p["dofs"] for p in points)
            # the coarse quick meshes sit 0.3-8.2 % above the converged modes (2026-11-23 quick run)
            assert all(0 < p["frequency"] / converged - 1 < 0.1 for p in points)
        assert ours[-1]["frequency"] == pytest.approx(peer[-1]["frequency"], rel=rel)
        # the two extrapolated references (or finest points) of the quick levels agree as well
        summary = results[case]["summary"]
        assert summary["reference"] == pytest.approx(summary["peer_reference"], rel=0.02)
