"""`modalfe forced`: results per unit load whatever its size, one name per output, and flags that would be
ignored refused before any solve (issue 35)."""

import pytest

from modalfe.cli.main import main
from tests.hostile.cases import BIMORPH


@pytest.fixture()
def bimorph(tmp_path):
    path = tmp_path / "bimorph.toml"
    path.write_text(BIMORPH)
    return str(path)


def _forced(capsys, *argv: str) -> tuple[int, str, str]:
    status = main(["forced", *argv])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_per_newton_outputs_do_not_scale_with_the_force_given(bimorph, capsys):
    status, one, _ = _forced(capsys, bimorph, "--force", "tip=0,0,1", "--outputs", "tip")
    assert status == 0 and "force factor 1 N/N" in one
    status, two, _ = _forced(capsys, bimorph, "--force", "tip=0,0,2", "--outputs", "tip")
    assert status == 0 and two == one  # every figure, and the load's description, per N along +z


@pytest.mark.parametrize(("argv", "message"), [
    (("--point", "tip=0.04,0.002,0.001"), "--point: 'tip' is a face group of the scene"),
    (("--point", "p=0.02,0.002,0.001", "--point", "p=0.03,0.002,0.001"), "--point: 'p' given twice"),
    (("--outputs", "tip,tip"), "outputs: 'tip' given twice"),
    (("--outputs", "tip,mean:nowhere"), "outputs: no face group 'nowhere'"),
    (("--force", "tip=0,0,1", "--volts", "50", "--plot", "x.png"), "--volts: the load is a force along (0, 0, 1)"),
    (("--volts", "50",), "--volts: scales only the --plot curve"),
    (("--base-acceleration", "z", "--set", "clamps={}"), "drive.load: a base acceleration (--base-acceleration z)"),
    (("--mode", "0"), "--mode: '0' is a number, not a mode label"),
    (("--mode", "bending 1"), "--mode: 'bending 1' is not a mode label"),
])
def test_inputs_refused_before_the_solve(bimorph, capsys, monkeypatch, argv, message):
    def no_solve(*_args, **_kw):
        raise AssertionError("solved before refusing")

    monkeypatch.setattr("modalfe.solve.api.solve_modes", no_solve)
    status, _, err = _forced(capsys, bimorph, *argv)
    assert status == 2 and err.startswith(f"modalfe: error: {message}") and err.count("\n") == 1, err
