"""``modalfe friction``, ``finger`` and ``texture`` through a small argparse harness and through
``modalfe.cli.main.main``."""

import argparse
import json

import numpy as np
import pytest

from modalfe.cli import contact as cli_contact
from modalfe.errors import ContactError


def run(argv):
    parser = argparse.ArgumentParser(prog="modalfe")
    cli_contact.register(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    return args.func(args)


def test_friction_json(capsys):
    assert run(["friction", "--amplitude", "0:2e-6:5", "--preload", "3", "--speed", "0.01", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["amplitude_m"] == pytest.approx([0, 0.5e-6, 1e-6, 1.5e-6, 2e-6])
    assert out["friction_force_n"][0] == pytest.approx(0.2 * (3 + 0.0723 * 9.81), rel=1e-12)  # mu0 (Fn + m g)
    assert out["flight_ratio_percent"][0] == 0 and out["flight_ratio_percent"][-1] > 0


def test_friction_table_glass_and_plot(tmp_path, capsys):
    png = tmp_path / "friction.png"
    assert run(["friction", "--amplitude", "0,1e-6", "--preload", "3", "--substrate", "glass",
                "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "mu0 = 0.08" in out and png.stat().st_size > 0


def test_friction_from_voltage(capsys):
    assert run(["friction", "--voltage", "0:20:3", "--amplitude-per-volt", "5e-8", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["voltage_v"] == [0, 10, 20] and out["amplitude_m"] == pytest.approx([0, 5e-7, 1e-6])


def test_finger_json(capsys):
    assert run(["finger", "--frequency", "225e3", "--amplitude", "0:0.3e-6:4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    (curve,) = out["curves"]
    assert curve["frequency_hz"] == 225e3 and curve["friction_ratio"][0] == pytest.approx(1.0)
    assert out["equal_friction"] is None  # one frequency: no ratio


def test_texture_json(capsys):
    assert run(["texture", "--period", "8.7e-3", "--speed", "0.02", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["modulation_frequency_hz"] == pytest.approx(0.02 / 8.7e-3) and out["contrast_n"] > 0


@pytest.mark.parametrize("text, expected", [("0:1:3", [0, 0.5, 1]), ("1,2", [1, 2]), ("2e-6", [2e-6])])
def test_parse_values(text, expected):
    np.testing.assert_allclose(cli_contact.parse_values(text, "--x"), expected)


@pytest.mark.parametrize("text", ["0:1", "a,b", "0:1:0", ""])
def test_parse_values_rejects(text):
    with pytest.raises(ContactError, match=r"^--x:"):
        cli_contact.parse_values(text, "--x")


@pytest.mark.parametrize("argv, field", [
    (["friction", "--amplitude", "0,nan", "--preload", "3"], "amplitude[1]"),
    (["friction", "--amplitude", "1e-6", "--preload", "-3"], "preload"),
    (["friction", "--amplitude", "1e-6", "--set", "kn=-1"], "kn"),
    (["friction", "--amplitude", "1e-6", "--set", "mass=-0.1"], "mass"),
    (["friction", "--amplitude", "1e-6", "--frequency", "0"], "frequency"),
    (["friction", "--voltage", "1"], "amplitude_per_volt"),
    (["finger", "--frequency", "0", "--amplitude", "1e-7"], "frequency"),
    (["texture", "--period", "-1"], "period"),
])
def test_main_prints_one_line_errors(argv, field, capsys):
    # what a user sees: exit status 1 and one line on stderr naming the field, no traceback
    from modalfe.cli.main import main

    assert main([*argv, "--json"]) == 1
    err = capsys.readouterr().err.strip()
    assert err == err.splitlines()[-1] and err.startswith(f"modalfe: error: {field}:")


def test_friction_from_a_saved_reduced_model(tmp_path, capsys):
    # --rom: amplitude per volt = |FRF| of the reduced model at the drive frequency, its resonance by
    # default; a one-mode model built by hand so the expected amplitudes are known exactly.
    forced = pytest.importorskip("modalfe.response.forced")
    f, zeta, m = 40.0e3, 0.005, 0.02
    k = m * (2 * np.pi * f) ** 2
    rom = forced.ReducedModel(label="(0,6)", frequency=f, zeta=zeta, damping_description="zeta 0.005",
                              reference="foot_1", modal_mass=m, stiffness=k, damping=2 * zeta * np.sqrt(k * m),
                              force_factor=1e-5, capacitance=1e-9, shapes={"foot_1": [0.0, 0.0, 1.0]},
                              feedthrough={"foot_1": [0.0, 0.0, 0.0]})
    path = tmp_path / "rom.json"
    rom.save(path)
    assert run(["friction", "--voltage", "0,2", "--rom", str(path), "--preload", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["parameters"]["frequency_hz"] == f
    assert out["amplitude_m"] == pytest.approx([0.0, 2 * rom.amplitude_per_volt()], rel=1e-12)
    with pytest.raises(ContactError, match=r"^--rom:"):
        run(["friction", "--voltage", "1", "--rom", str(tmp_path / "missing.json")])
