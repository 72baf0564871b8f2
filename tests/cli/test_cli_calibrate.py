"""``modalfe calibrate``: the progress log and tables, the JSON result, multi-start through run_starts, and
one-line errors for malformed options and measurement files."""

import json

import pytest

from modalfe.cli.main import main
from tests.cli.test_cli_sensitivity import STRIP as SENSITIVITY_STRIP

# a free 59 x 10 x 1 mm steel strip on 3 mm elements (as tests/design/test_calibration.py): (0,2) at 1492.2 Hz;
# f ~ sqrt(E) exactly (K linear in E), so 1492.2 * sqrt(1.1) = 1565.0 Hz is the strip with E = 220 GPa
STRIP = SENSITIVITY_STRIP.replace("[60, 10, 1]", "[59, 10, 1]").replace("max_size = 2e-3", "max_size = 3e-3")
MEASURED = '[[mode]]\nlabel = "(0,2)"\nfrequency = 1565.0\nsigma = 1.0\n'


@pytest.fixture
def files(tmp_path):
    scene, measured = tmp_path / "strip.toml", tmp_path / "measured.toml"
    scene.write_text(STRIP)
    measured.write_text(MEASURED)
    return str(scene), str(measured)


def test_the_log_has_one_line_per_solve_and_the_tables(files, capsys):
    scene, measured = files
    assert main(["calibrate", scene, "--measured", measured, "--vary", "materials.steel.E"]) == 0
    out = capsys.readouterr().out
    assert "  1  chi2" in out and "  2  chi2" in out and "converged after" in out
    assert "(0,2) frequency" in out and "every parameter is identified by the data" in out
    assert "stated sigmas (no residual dof)" in out  # one frequency, one parameter: nothing left to scale by


def test_json_gives_estimates_and_a_named_unidentifiable_pair(files, capsys):
    """E = 220 GPa within 0.1 % (1492.2 Hz is rounded to 1e-4 of E; the 1-Hz sigma on 1565 Hz is 0.13 % of E,
    sd = 2 E sigma / f since d ln f / d ln E = 1/2); E with rho: one
    frequency fixes only E / rho, and the document says so."""
    scene, measured = files
    # the data are exact on the scene's own mesh: fitted there (--no-error-estimate), sd is the measurement's alone
    assert main(["calibrate", scene, "--measured", measured, "--vary", "materials.steel.E", "--json",
                 "--no-error-estimate"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["converged"] and out["parameters"]["materials.steel.E"]["estimate"] == pytest.approx(220e9, rel=1e-3)
    assert out["parameters"]["materials.steel.E"]["sd"] == pytest.approx(2 * 220e9 / 1565.0, rel=1e-2)
    # on the resolved model (the default) the frequency's stated error joins the 1 Hz sigma: a wider sd, said so
    assert main(["calibrate", scene, "--measured", measured, "--vary", "materials.steel.E", "--json"]) == 0
    resolved = json.loads(capsys.readouterr().out)
    assert resolved["parameters"]["materials.steel.E"]["sd"] > out["parameters"]["materials.steel.E"]["sd"]
    assert "stated discretization error added" in resolved["reason"]
    assert out["unidentified"] == [] and out["measurements"][0]["quantity"] == "(0,2) frequency"
    assert main(["calibrate", scene, "--measured", measured, "--vary", "materials.steel.E,materials.steel.rho",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["unidentified"] == ["materials.steel.E and materials.steel.rho are not separately identifiable: "
                                   "only materials.steel.E*materials.steel.rho^-1 is"]


def test_starts_run_inline_and_report_the_best(files, capsys):
    scene, measured = files
    argv = ["calibrate", scene, "--measured", measured, "--vary", "materials.steel.E", "--starts", "2",
            "--scheduler", "inline", "--bounds", "materials.steel.E=150e9:300e9", "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["starts"]) == 2 and all(s["converged"] for s in out["starts"])
    assert out["chi2"] == min(s["chi2"] for s in out["starts"])
    assert out["parameters"]["materials.steel.E"]["estimate"] == pytest.approx(220e9, rel=1e-3)


@pytest.mark.parametrize(("extra", "message"), [
    (["--vary", "materials.steel.E", "--starts", "2"], "--starts: needs --bounds for every varied parameter"),
    (["--vary", "materials.steel.E,materials.steel.E"], "--vary: give distinct parameter names"),
    (["--vary", "materials.steel.E", "--bounds", "materials.steel.E=3e11:2e11"], "--bounds: expected NAME=LOW:HIGH"),
    (["--vary", "length"], "length: not a parameter"),
])
def test_malformed_options_are_refused_in_one_line(files, capsys, extra, message):
    scene, measured = files
    assert main(["calibrate", scene, "--measured", measured, *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err


def test_a_bad_measurement_file_is_refused_in_one_line(files, tmp_path, capsys):
    scene, _ = files
    bad = tmp_path / "bad.toml"
    bad.write_text('[[mode]]\nlabel = "(0,2)"\nfrequency = 1500.0\n')
    assert main(["calibrate", scene, "--measured", str(bad), "--vary", "materials.steel.E"]) == 2
    err = capsys.readouterr().err.strip()
    assert "mode[0].sigma: required" in err and "\n" not in err
    assert main(["calibrate", scene, "--measured", str(tmp_path / "missing.toml"), "--vary", "x"]) == 1
    assert "missing.toml" in capsys.readouterr().err


@pytest.mark.parametrize("content", [bytes(range(256)), MEASURED.replace("(0,2)", "(0,2) \xe9").encode("latin-1")])
def test_a_measurement_file_that_is_not_utf8_is_refused_in_one_line(files, tmp_path, capsys, content):
    """issue 35: a binary (or Latin-1) --measured file raised UnicodeDecodeError (exit 70)."""
    scene, _ = files
    binary = tmp_path / "binary.toml"
    binary.write_bytes(content)
    assert main(["calibrate", scene, "--measured", str(binary), "--vary", "materials.steel.E"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"modalfe: error: {binary}: not UTF-8 text") and "--measured" in err and "\n" not in err


def test_a_measured_label_of_no_label_form_is_refused_before_any_solve(files, tmp_path, capsys):
    scene, _ = files
    bad = tmp_path / "bad.toml"
    bad.write_text(MEASURED.replace('"(0,2)"', '"mode 2"'))
    assert main(["calibrate", scene, "--measured", str(bad), "--vary", "materials.steel.E"]) == 2
    assert capsys.readouterr().err.startswith(f"modalfe: error: {bad}: mode[0].label: 'mode 2' is not a mode label")


def test_the_printed_set_lines_give_the_fitted_scene():
    """issue 34: the reproduce line left out the springs a tie fitted; now every member, at full precision."""
    from types import SimpleNamespace

    from modalfe.cli.calibrate import _reproduce
    from modalfe.cli.options import parse_overrides
    from modalfe.response.sensitivity import with_values
    from tests.design.test_calibration import _strip_on_springs

    base = _strip_on_springs(1.5e4, 1.5e4)
    fitted = with_values(base, {"springs.foot_1.z": 2.0123456789e4, "springs.foot_2.z": 2.0123456789e4,
                                "materials.steel.E": 2.0987654321e11})
    lines = _reproduce(SimpleNamespace(parameters=("springs.foot_*.z", "materials.steel.E"), scene=fitted))
    assert len(lines) == 3 and all(line.startswith("--set ") for line in lines)
    again = base.with_overrides(**parse_overrides([line.split(" ", 1)[1].strip("'") for line in lines]))
    assert again.springs == fitted.springs and again.materials == fitted.materials
