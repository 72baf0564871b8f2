"""The modalfe command: report rows, modes of a scene file, --set, errors and exit status."""

import json

import pytest

from modalfe.cli.main import main
from modalfe.cli.options import parse_overrides
from tests.scene.test_scenes import BEAM_FILE

REPORT_KEYS = {"scene", "mode", "frequency_hz", "targets", "error_estimate", "dofs", "fidelity", "seconds"}


def test_report_json_rows_carry_the_promised_keys(capsys):
    assert main(["report", "--scene", "ciliary_beam", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert len(rows) == 1
    row = rows[0]
    assert set(row) >= REPORT_KEYS
    assert row["mode"] == "bending-z 6"
    # 3-D solid with shear and rotary inertia: below the seed's Euler-Bernoulli 24,221 Hz
    assert 20e3 < row["frequency_hz"] < 24221.0
    names = {t["name"] for t in row["targets"]}
    assert {"f_analytic", "f_measured"} <= names
    for t in row["targets"]:
        assert t["deviation"] == pytest.approx(row["frequency_hz"] / t["value"] - 1)
    assert row["k_eff"] is not None and 0 < row["k_eff"] < 0.5


def test_the_report_text_is_one_screen_and_its_details_come_with_verbose(capsys):
    """Issue 37: rows, targets and deviations by default; how each row was resolved, notes and assumptions with -v."""
    assert main(["report", "--scene", "ciliary_beam"]) == 0
    short = capsys.readouterr().out.splitlines()
    assert len(short) == 1 + 1 + 2 + 1  # header, the row (with fa and k_eff), its two targets, where the rest is
    assert "21617" in short[1] and "report -v" in short[-1]
    assert not any("error estimate:" in line or "auto:" in line for line in short)
    assert main(["report", "--scene", "ciliary_beam", "-v"]) == 0
    detail = capsys.readouterr().out
    assert "error estimate: p-refinement" in detail and "auto: solid answered" in detail


def test_modes_of_a_scene_file(tmp_path, capsys):
    path = tmp_path / "bimorph.toml"
    path.write_text(BEAM_FILE)
    assert main(["modes", str(path), "--near", "2000", "--count", "4", "--json", "--no-error-estimate"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["scene"] == "bimorph" and len(out["modes"]) == 4
    assert out["modes"][0]["label"] == "bending-z 1"


def test_table_output_and_set(capsys):
    assert main(["modes", "ciliary_beam", "--near", "5000", "--count", "3", "--no-error-estimate",
                 "--set", "x0=0.05"]) == 0
    out = capsys.readouterr().out
    assert "ciliary_beam" in out and "bending-z" in out


def test_bad_input_is_one_line_and_exit_2(capsys):
    assert main(["modes", "cube_plate", "--set", "thickness=-1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "thickness" in err
    assert main(["modes", "nowhere.toml"]) == 2


def test_overrides_are_toml_literals():
    assert parse_overrides(["a=1e-3", "b=[1, 2]", "c=PZT-5A", 'd="x"']) == {
        "a": 1e-3, "b": [1, 2], "c": "PZT-5A", "d": "x"}


def test_import_is_light_and_the_api_mirrors_the_cli():
    import subprocess
    import sys

    # nothing loads until a name is used: `show`'s rendering process needs neither the solver nor the contact stack
    code = ("import sys, modalfe; heavy = [m for m in ('numpy', 'scipy', 'gmsh', 'pyvista', 'matplotlib', 'dask', "
            "'skfem') if m in sys.modules]; print(heavy); "
            "assert all(hasattr(modalfe, f) for f in ('load_scene', 'solve_modes', 'forced_response', 'reduce', "
            "'simulate_contact', 'simulate_finger', 'sweep')); "
            "assert all(hasattr(modalfe, f) for f in modalfe.__all__); "
            "assert modalfe.forced_response is modalfe.response.figures.forced_figures; "
            "assert not hasattr(modalfe, 'no_such_name')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_report_jobs_must_be_a_positive_integer(capsys):
    for bad in ("0", "two"):
        with pytest.raises(SystemExit) as info:
            main(["report", "--jobs", bad])
        assert info.value.code == 2
        assert "--jobs" in capsys.readouterr().err
