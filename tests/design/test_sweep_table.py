"""Sweep tables lose nothing and mix nothing: rows keyed on their whole definition, torn lines repaired,
one writer at a time, tracking through a working mode that leaves the search window, grid order.

A 40 x 4 x 2 mm steel cantilever (beam kind, a few dozen DOFs: ~0.1 s a point; the element size fixed by
``max_size`` [m], so a frequency scale does not change the mesh) swept over its Young's modulus, computed in
this process (``scheduler="inline"``)."""

import csv

import pytest

from modalfe.design.sweep import COLUMNS, INLINE, read_table, sweep, table_lock
from modalfe.errors import SceneError

BEAM = """
name = "tiny-beam"
units = "mm"
kind = "beam"
[analysis]
near = 1000.0
count = 4
[mesh]
elements_per_wavelength = 1.0
max_size = 0.005
min_layers = 1
[materials.m]
E = 200e9
nu = 0.3
rho = {rho}
[[parts]]
name = "beam"
material = "m"
origin = [0, 0, 0]
size = [40, 4, 2]
[faces]
clamp = ["beam.xmin"]
[clamps]
clamp = "xyz"
"""
E = [200e9, 150e9, 100e9]


@pytest.fixture
def beam(tmp_path):
    path = tmp_path / "beam.toml"
    path.write_text(BEAM.format(rho=7850.0))
    return path


def _run(scene, out, values=E, **kw):
    kw = {"selector": "bending-z 1", "near": 1000.0, "count": 2, "scheduler": INLINE, "progress": False, **kw}
    return sweep(str(scene), {"materials.m.E": list(values)}, out=out, **kw)


def _table(out):
    with open(out, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        lines = list(reader)
    return header, lines


def test_resume_does_not_reuse_rows_of_other_overrides_or_another_scene(beam, tmp_path):
    out = tmp_path / "s.csv"
    first = _run(beam, out)
    heavy = _run(beam, out, base={"materials.m.rho": 4 * 7850.0})
    # 4x the density halves every frequency: computed anew, not read back from the first sweep's rows
    for a, b in zip(first, heavy):
        assert b["frequency_hz"] == pytest.approx(a["frequency_hz"] / 2, rel=1e-6)
    edited = tmp_path / "edited" / "beam.toml"  # same file name, other content
    edited.parent.mkdir()
    edited.write_text(BEAM.format(rho=4 * 7850.0))
    again = _run(edited, out)
    for a, b in zip(first, again):
        assert b["frequency_hz"] == pytest.approx(a["frequency_hz"] / 2, rel=1e-6)
    rows = read_table(out)
    assert len(rows) == 3 * 3  # nothing lost: every sweep's rows are kept, each keyed on its definition
    assert len({(r["scene_sha256"], str(r["overrides"])) for r in rows.values()}) == 3


def test_a_torn_last_line_is_dropped_not_appended_to(beam, tmp_path):
    out = tmp_path / "s.csv"
    _run(beam, out)
    data = out.read_bytes()
    out.write_bytes(data[: len(data) - 40])  # a writer killed in the middle of the last row
    rows = _run(beam, out)
    header, lines = _table(out)
    assert len(lines) == 3 and all(len(line) == len(header) for line in lines)
    assert [r["point"] for r in rows] == [0, 1, 2]
    assert len(read_table(out)) == 3


def test_a_second_writer_is_refused_while_the_first_holds_the_table(beam, tmp_path):
    out = tmp_path / "s.csv"
    with table_lock(out), pytest.raises(SceneError) as info:
        _run(beam, out)
    assert str(info.value).startswith("--out:") and "another sweep" in str(info.value)
    assert not out.exists()  # nothing written by the refused sweep
    assert len(_run(beam, out)) == 3  # the lock is released with its holder


@pytest.mark.parametrize("workers", [0, -1, 1.5])
def test_workers_below_one_are_refused_before_any_work(beam, tmp_path, workers):
    with pytest.raises(SceneError) as info:
        _run(beam, tmp_path / "s.csv", scheduler=None, workers=workers)
    assert str(info.value).startswith("--workers:")


def test_a_mode_leaving_the_search_window_is_tracked_by_shape_and_marked(beam, tmp_path):
    # at E / 16 the frequencies quarter: bending-y 1 (545 Hz) is the one mode nearest 1 kHz (count 1), and the
    # labelled bending-z 1 (281 Hz) is outside the window; before, the sweep aborted with a SolverError
    rows = _run(beam, tmp_path / "s.csv", values=[200e9, 200e9 / 16], count=1)
    assert rows[0]["status"] == "ok" and not rows[0]["crossing"]
    assert rows[1]["status"].startswith("not found") and rows[1]["frequency_hz"] is None
    assert rows[1]["crossing"] and rows[1]["tracked_label"] == "bending-y 1"
    assert rows[1]["mac_previous"] < 0.8  # the only candidate has another shape: the MAC says so


def test_the_table_has_one_column_per_parameter_tracking_columns_and_grid_order(beam, tmp_path):
    out = tmp_path / "s.csv"
    _run(beam, out, values=E[::-1])  # computed in the opposite order ...
    rows = _run(beam, out, values=E)  # ... then resumed: every row reused, written in this grid's order
    header, lines = _table(out)
    assert "materials.m.E [Pa]" in header and set(COLUMNS) <= set(header)
    for column in ("tracked_label", "tracked_frequency_hz", "mac_previous", "crossing"):
        assert column in header
    table = [dict(zip(header, line)) for line in lines]
    assert [float(t["materials.m.E [Pa]"]) for t in table] == E
    assert [int(t["point"]) for t in table] == [0, 1, 2]
    assert [float(t["tracked_frequency_hz"]) for t in table] == [r["tracked_frequency_hz"] for r in rows]
    assert [t["crossing"] for t in table] == ["False"] * 3
    # sqrt(E) scaling of the tracked mode: the rows belong to their parameter values
    f = [r["tracked_frequency_hz"] for r in rows]
    assert f[0] / f[2] == pytest.approx(2**0.5, rel=1e-6)


@pytest.mark.slow
def test_a_one_worker_local_cluster_writes_the_same_table(beam, tmp_path):
    inline = _run(beam, tmp_path / "a.csv")
    dask = _run(beam, tmp_path / "b.csv", scheduler=None, workers=1)
    assert [r["frequency_hz"] for r in dask] == pytest.approx([r["frequency_hz"] for r in inline], rel=1e-9)
