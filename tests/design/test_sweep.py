"""Sweeps: kill a 2-worker dask sweep part-way, resume it, and get exactly the uninterrupted result."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from modalfe.design.sweep import grid_values, mac, read_table, sweep, track
from modalfe.errors import SceneError
from tests.oracles.discs import PZT5A_DISC

ARGS = ["sweep", "ciliary_beam", "--param", "x0=0.05:0.08:6", "--workers", "2", "--json",
        "--set", "mesh.elements_per_wavelength=4.0"]


def _run(out, env):
    return subprocess.Popen([sys.executable, "-m", "modalfe.cli.main", *ARGS, "--out", str(out)], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)


@pytest.mark.slow  # 8-25 s on a quiet 2-core machine: on demand (-m slow), the default run kept under 10 min
def test_killed_sweep_resumes_without_losing_or_recomputing(tmp_path):
    env = dict(os.environ, MODALFE_CACHE=str(tmp_path / "cache"))
    out = tmp_path / "sweep.csv"
    proc = _run(out, env)
    deadline = time.time() + 120
    while time.time() < deadline and len(read_table(out)) < 2:
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)  # the whole process group: client, scheduler, workers
    proc.wait()
    before = read_table(out)
    assert 2 <= len(before) < 6, "the kill must land part-way through the sweep"
    rows = sweep("ciliary_beam", {"x0": grid_values("0.05:0.08:6")}, out=out, selector="bending-z 6",
                 near=24.2e3, base={"mesh.elements_per_wavelength": 4.0}, workers=2, progress=False)
    after = read_table(out)
    assert len(after) == 6 and len(rows) == 6
    for pid, row in before.items():  # finished points are kept as they were, not recomputed
        assert after[pid]["seconds"] == row["seconds"]
    with open(out) as f:
        assert sum(1 for _ in f) == 1 + 6  # header and one line per point: nothing written twice
    fresh = sweep("ciliary_beam", {"x0": grid_values("0.05:0.08:6")}, out=tmp_path / "fresh.csv",
                  selector="bending-z 6", near=24.2e3, base={"mesh.elements_per_wavelength": 4.0}, workers=2,
                  progress=False)
    # the same deterministic computations: equal to an uninterrupted run to round-off
    np.testing.assert_allclose([r["frequency_hz"] for r in rows], [r["frequency_hz"] for r in fresh], rtol=1e-9)
    assert not any(r["crossing"] for r in rows)


def _row(f, candidates, label):
    return {"label": label, "frequency_hz": f, "candidates": candidates}


def test_tracking_follows_the_shape_and_reports_a_crossing():
    a = np.array([1.0, 0.5, -0.5, -1.0])
    b = np.array([1.0, -1.0, 1.0, -1.0])
    rows = [
        _row(100.0, [{"label": "A", "frequency_hz": 100.0, "shape": a}, {"label": "B", "frequency_hz": 110.0,
                                                                          "shape": b}], "A"),
        # the label picked by the solver jumps to B while shape A carries on at 104 Hz: a crossing
        _row(105.0, [{"label": "A", "frequency_hz": 104.0, "shape": a * 0.9}, {"label": "B", "frequency_hz": 105.0,
                                                                                "shape": b}], "B"),
    ]
    tracked = track(rows, "A")
    assert not tracked[0]["crossing"]
    assert tracked[1]["crossing"] and tracked[1]["tracked_label"] == "A"
    assert tracked[1]["mac_previous"] == pytest.approx(1.0)


def test_mac_and_grid_values():
    assert mac([1, 0], [2, 0]) == 1.0 and mac([1, 0], [0, 1]) == 0.0
    assert grid_values("1:2:3") == [1.0, 1.5, 2.0]
    for bad in ("1:2", "a:b:3", "1:2:0"):
        with pytest.raises(SceneError):
            grid_values(bad)


DISC = PZT5A_DISC  # a free 20 x 1 mm disc


def test_a_sweep_point_of_a_disc_samples_its_shapes_inside_it():
    """The shapes are sampled on a grid over the device's bounding box; a round main part leaves its corners outside
    the device: those samples are 0, the others the disc's motion (the probe of a corner point was refused before,
    and every point of a disc sweep failed)."""
    from modalfe.design.sweep import GRID, evaluate_point

    row = evaluate_point(str(DISC), {}, {"mesh.elements_per_wavelength": 4.0}, "R1", 99e3)
    assert row["status"] == "ok" and row["label"] == "R1"
    shape = np.array(next(c for c in row["candidates"] if c["label"] == "R1")["shape"])
    U, V = np.meshgrid(np.linspace(0.02, 0.98, GRID[0]), np.linspace(0.05, 0.95, GRID[1]))
    outside = np.hypot(U.ravel() - 0.5, V.ravel() - 0.5) > 0.5  # relative to the 20 mm bounding square
    assert len(shape) == U.size and np.all(shape[outside] == 0.0) and np.all(shape[~outside] != 0.0)
