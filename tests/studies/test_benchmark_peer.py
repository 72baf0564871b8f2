"""studies/benchmark_peer.py: its quick path runs every code and order end to end (box and curved devices), its
reference, time-to-accuracy, ratio and growth arithmetic recovers known answers, and its rim test knows a body of
revolution's mode by its waves."""

import dataclasses
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.helpers import load_study

pytest.importorskip("ngsolve")

SCRIPT = Path(__file__).resolve().parents[2] / "studies" / "benchmark_peer.py"
RING_N2, DISC_R1 = 1553.9946, 99364.806  # Hz: curved cases' references (2026-11-28 run, docs/benchmark_peer.md)
PLATE_06 = 36294.4  # Hz: Richardson through modalfe p=4 and NGSolve p=4 agree within 0.001 % (2026-11-23)


def _study():
    return load_study("benchmark_peer")


def test_richardson_recovers_the_limit_of_a_power_law():
    study = _study()
    # f = f_inf + c N^(-4/3) (order 4 in h) on unevenly spaced DOF counts: the fit is exact
    points = [{"dofs": n, "frequency": 36e3 + 5e6 * n ** (-4 / 3)} for n in (3000, 8000, 21000, 70000)]
    f_inf, order = study.richardson(points)
    assert f_inf == pytest.approx(36e3, rel=1e-9)
    assert order == pytest.approx(4.0, rel=1e-6)
    # not monotone, or under three points: no extrapolation, the finest point and no order
    for points in ([{"dofs": 1, "frequency": 3.0}, {"dofs": 2, "frequency": 1.0}, {"dofs": 3, "frequency": 2.0}],
                   [{"dofs": 1, "frequency": 3.0}, {"dofs": 2, "frequency": 2.0}]):
        f_inf, order = study.richardson(points)
        assert f_inf == 2.0 and math.isnan(order)


def test_time_to_target_interpolates_log_log_between_bracketing_points():
    study = _study()
    points = [{"error": 1e-2, "total": 1.0, "dofs": 1000}, {"error": 1e-4, "total": 100.0, "dofs": 100000}]
    # 1e-3 is halfway in log error between 1e-2 and 1e-4, so halfway in log time and log DOFs
    seconds, dofs, how = study.time_to_target(points, 1e-3)
    assert how == "interpolated" and seconds == pytest.approx(10.0) and dofs == pytest.approx(10000.0)
    assert study.time_to_target(points, 1e-1)[::2] == (1.0, "bound")
    seconds, _, how = study.time_to_target(points, 1e-5)
    assert how == "not reached" and math.isnan(seconds)


def test_growth_fits_the_exponent_per_stage():
    study = _study()
    points = [{"dofs": n, "assembly": 1e-5 * n, "eigensolve": 1e-8 * n**1.5, "mesh": 0.0} for n in (1e3, 1e4, 1e5)]
    assert study.growth(points, "assembly") == pytest.approx(1.0)
    assert study.growth(points, "eigensolve") == pytest.approx(1.5)
    assert math.isnan(study.growth(points, "mesh"))  # under 1 ms: not timed


def test_report_ratios_against_each_peer_order_and_the_best(capsys):
    study = _study()

    def sweep(code, order, seconds):  # errors 1 %, 0.05 %, 0.005 % against the reference point
        f = [1.01, 1.0005, 1.00005, 1.0]
        return {"code": code, "order": order, "points": [
            {"level": (1.0, 1) if code == "modalfe" else 1e-3, "dofs": 1000 * 10**i, "frequency": 36e3 * f[i],
             "total": seconds * 10**i, "mesh": 0.1, "assembly": 0.1, "factorization": 0.1, "eigensolve": 0.1,
             "peak_rss_mb": 100.0} for i in range(4)]}

    sweeps = [sweep("modalfe", 4, 1.0), sweep("NGSolve", 2, 4.0), sweep("NGSolve", 3, 2.5), sweep("NGSolve", 4, 3.0)]
    summary = study.report("plate", sweeps)
    ratios = summary["ratios"][str(1e-3)]
    # the errors are alike in every sweep, so the ratios are those of the time scales
    assert ratios["NGSolve 3"] == pytest.approx(0.4) and ratios["NGSolve 2"] == pytest.approx(0.25)
    assert ratios["best NGSolve"] == pytest.approx(0.4) and summary["best"][str(1e-3)]["NGSolve"] == "NGSolve 3"
    assert summary["goal"] == {"against": "NGSolve 3", "ratio": pytest.approx(0.4), "met": True}
    assert summary["reference"]["reference"]["frequency"] == pytest.approx(36e3, rel=1e-5)
    assert "goal: modalfe / NGSolve p=3 to 0.1 % <= 0.5: ratio 0.400, met" in capsys.readouterr().out


def test_round_fits_knows_a_mode_by_the_waves_of_its_rim():
    study = _study()
    ring = study.CASES["ring"]  # in-plane n = 2, rim at radius 20 mm, height 1 mm
    radius, z = ring.rim

    def field(u_r, u_t, u_z):  # a displacement (n, 3) from cylindrical components, functions of the angle
        def displacement(points):
            theta = np.arctan2(points[:, 1], points[:, 0])
            assert np.allclose(np.hypot(points[:, 0], points[:, 1]), radius) and np.allclose(points[:, 2], z)
            r, t = u_r(theta), u_t(theta)
            return np.stack([r * np.cos(theta) - t * np.sin(theta), r * np.sin(theta) + t * np.cos(theta),
                             u_z(theta)], axis=1)
        return displacement

    zero = np.zeros_like
    # the inextensional n = 2 ring mode, u_r = -d u_theta / d theta (Blevins 1979, Table 9-1): u_theta = -sin(2 t) / 2
    assert study.round_fits(ring, field(lambda t: np.cos(2 * t), lambda t: -0.5 * np.sin(2 * t), zero))
    assert not study.round_fits(ring, field(lambda t: np.cos(3 * t), lambda t: np.sin(3 * t) / 3, zero))  # n = 3
    out_of_plane = field(lambda t: np.cos(2 * t), zero, lambda t: 0.2 * np.cos(2 * t))  # u_z 20 % of u_r
    assert not study.round_fits(ring, out_of_plane)
    assert not study.round_fits(ring, field(lambda t: 0.1 * np.cos(2 * t), lambda t: np.ones_like(t), zero))  # torsion
    disc = dataclasses.replace(ring, harmonic=0)  # the radial mode: uniform u_r
    assert study.round_fits(disc, field(np.ones_like, zero, zero))
    # pick: among the fitting modes the one nearest the case's frequency (here the lower of a split pair)
    n2 = field(lambda t: np.cos(2 * t), lambda t: -0.5 * np.sin(2 * t), zero)
    n3 = field(lambda t: np.cos(3 * t), zero, zero)
    assert study.pick(ring, [(1500.0, n3), (1554.0, n2), (1560.0, n2), (2000.0, n2)]) == 1554.0


def test_report_states_each_modalfe_model_against_the_best_peer(capsys):
    study = _study()

    def sweep(code, order, seconds, level):  # errors 1 %, 0.05 %, 0.005 %, 0 against the reference point
        f = [1.01, 1.0005, 1.00005, 1.0]
        return {"code": code, "order": order, "points": [
            {"level": level, "dofs": 1000 * 10**i, "frequency": 99e3 * f[i], "total": seconds * 10**i, "mesh": 0.1,
             "assembly": 0.1, "factorization": 0.1, "eigensolve": 0.1, "peak_rss_mb": 100.0} for i in range(4)]}

    sweeps = [sweep("modalfe", 2, 2.0, (1.0, 1)), sweep("modalfe-axi", 4, 0.1, 1.0), sweep("NGSolve", 3, 1.0, 1e-3),
              sweep("NGSolve", 4, 1.6, 1e-3)]
    summary = study.report("disc", sweeps)
    # alike errors in every sweep: the ratios are those of the time scales, the reference modalfe-axi p=4's
    assert summary["reference"]["reference"]["code"] == "modalfe-axi"
    assert summary["best"][str(1e-3)] == {"modalfe": "modalfe-axi 4", "NGSolve": "NGSolve 3"}
    assert summary["per_model"][str(1e-3)] == {"modalfe": pytest.approx(2.0), "modalfe-axi": pytest.approx(0.1)}
    assert summary["goal"] == {"against": "best NGSolve", "ratio": pytest.approx(0.1), "met": True}
    assert "per model, fastest order / best NGSolve: modalfe (modalfe p=2) 2.000" in capsys.readouterr().out


def _quick(tmp_path: Path, case: str) -> tuple[dict, str]:
    done = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--repeats", "1", "--cases", case,
                           "--out", str(tmp_path)], capture_output=True, text=True, check=False, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    assert (tmp_path / "benchmark_peer.png").stat().st_size > 0
    return json.loads((tmp_path / "benchmark_peer.json").read_text())[case], done.stdout


def _check_quick(result: dict, out: str, converged: float, orders: dict[str, set[int | str]], *,
                 apart: float = 0.1, below: float = 0.0) -> None:
    """The quick run's tables, sweeps and reference: every point's frequency within ``apart`` above ``converged``
    (nearer than any other mode) and at most ``below`` under it (conforming elements on the exact geometry
    converge from above; curved elements approximate the geometry)."""
    for title in ("time [s] and DOFs to each accuracy", "goal: modalfe / ", "growth with DOFs"):
        assert title in out
    assert {s["code"] for s in result["sweeps"]} == set(orders)
    for code, wanted in orders.items():
        assert {s["order"] for s in result["sweeps"] if s["code"] == code} == wanted
    for sweep in result["sweeps"]:
        pts = sweep["points"]
        assert all(p["total"] > 0 and p["factorization"] > 0 and p["peak_rss_mb"] > 0 for p in pts)
        assert [p["dofs"] for p in pts] == sorted(p["dofs"] for p in pts)
        assert all(-below < p["frequency"] / converged - 1 < apart for p in pts)
    # the reference (the case's reference code's highest order) and the cross-check (NGSolve's) are the same mode, and
    # both already within 0.2 % of the converged frequency on the quick meshes
    ref = result["summary"]["reference"]
    assert abs(ref["difference"]) < 2e-3
    assert ref["reference"]["frequency"] == pytest.approx(converged, rel=2e-3)


@pytest.mark.slow  # 17 s, the default run's heaviest test; the disc and ring runs keep the script's path by default
def test_quick_plate_run_prints_the_tables_and_a_consistent_reference(tmp_path):
    result, out = _quick(tmp_path, "plate")
    # 10 % catches a wrong mode only on the coarsest order-2 meshes, the closer ones sit 2.9 % (plate (2,5)) and
    # 1.0 % (beam bending-y 6) away
    _check_quick(result, out, PLATE_06, {"modalfe": {2, 3, "3S", 4}, "NGSolve": {2, 3, 4}})


@pytest.mark.slow
def test_quick_beam_run_prints_the_tables_and_a_consistent_reference(tmp_path):
    result, out = _quick(tmp_path, "beam")
    _check_quick(result, out, 21542.0, {"modalfe": {2, 3, 4}, "NGSolve": {2, 3}})


def test_quick_ring_run_prints_the_tables_and_a_consistent_reference(tmp_path):
    result, out = _quick(tmp_path, "ring")
    # the steel ring's in-plane n = 2 mode: modalfe-axi p=4 Richardson, NGSolve p=4 +4e-6 (2026-11-28);
    # 10 % catches a wrong mode: the nearest others are the rigid motions and the out-of-plane (2,0) pair at 2.48 kHz;
    # below: the curved elements' geometry error, under 1e-5 at the quick levels (NGSolve p=4 h 5 mm: +5e-6)
    _check_quick(result, out, RING_N2, {"modalfe": {2}, "modalfe-axi": {2, 4}, "NGSolve": {4}}, below=1e-5)


def test_quick_disc_run_prints_the_tables_and_a_consistent_reference(tmp_path):
    result, out = _quick(tmp_path, "disc")
    # the PZT-5A disc's R1 (short circuit): modalfe-axi p=4, NGSolve p=4 curved agree to 1e-7 (2026-11-28); 0.5 %
    # catches the nearest other mode, the flexural (8,0) at +2.6 %, with the quick levels' largest error 0.02 %;
    # below: NGSolve p=4 h 10 mm is 3e-7 under it (geometry error of the curved elements)
    _check_quick(result, out, DISC_R1, {"modalfe": {2}, "modalfe-axi": {2, 4}, "NGSolve": {4}}, apart=5e-3,
                 below=1e-5)
