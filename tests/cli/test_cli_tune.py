"""``modalfe tune``: the progress log, the JSON result, exit status 1 when the target is not reached, and
one-line errors for malformed options."""

import json

import pytest

from modalfe.cli.main import main
from tests.cli.test_cli_sensitivity import STRIP


@pytest.fixture
def strip(tmp_path):
    path = tmp_path / "strip.toml"
    path.write_text(STRIP)
    return str(path)


def test_json_reports_the_solves_and_the_final_design(strip, capsys):
    assert main(["tune", strip, "--target", "(0,2)=1300", "--vary", "parts.strip.size.x", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["converged"] and out["solves"] == len(out["iterates"]) >= 2
    assert abs(out["frequency_hz"] / 1300 - 1) <= 1e-3
    assert out["parameters"]["parts.strip.size.x"] > 0.060  # longer strip, lower frequency


def test_the_log_has_one_line_per_solve(strip, capsys):
    assert main(["tune", strip, "--target", "(0,2)=1300", "--vary", "materials.steel.E"]) == 0
    out = capsys.readouterr().out
    assert "reached: (0,2)" in out and "  1  " in out and "  2  " in out


def test_an_unreachable_target_exits_1(strip, capsys):
    argv = ["tune", strip, "--target", "(0,2)=1200", "--vary", "parts.strip.size.x", "--bounds",
            "parts.strip.size.x=0.055:0.062"]
    assert main(argv) == 1
    captured = capsys.readouterr()
    assert "NOT reached" in captured.out and "the parameters sit on their bounds" in captured.err


@pytest.mark.parametrize(("extra", "message"), [
    (["--target", "(0,2)"], "--target: expected LABEL=HZ"),
    (["--target", "(0,2)=-3"], "--target: expected LABEL=HZ"),
    (["--target", "(0,2)=1300", "--bounds", "parts.strip.size.x=0.07:0.06"], "--bounds: expected NAME=LOW:HIGH"),
])
def test_malformed_options_are_refused_in_one_line(strip, capsys, extra, message):
    assert main(["tune", strip, "--vary", "parts.strip.size.x", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err
