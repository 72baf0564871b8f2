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
    # issue 37: the device's own feet share the load (the Cu-Be plate's model has 4), unless --feet says otherwise
    assert out["parameters"]["n"] == 3  # one foot output says nothing of how many feet there are
    four = forced.ReducedModel(**{**rom.__dict__, "shapes": {f"foot_{i}": [0.0, 0.0, 1.0] for i in range(1, 5)},
                                  "feedthrough": {f"foot_{i}": [0.0, 0.0, 0.0] for i in range(1, 5)}})
    four.save(path)
    assert run(["friction", "--voltage", "1", "--rom", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"]["n"] == 4
    assert run(["friction", "--voltage", "1", "--rom", str(path), "--feet", "3", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"]["n"] == 3
    # the moving mass m: the device's mass the model carries, unless --set mass=... (a model without one: seed 000's)
    assert out["parameters"]["mass_kg"] == pytest.approx(0.0723)
    forced.ReducedModel(**{**four.__dict__, "device_mass": 0.065}).save(path)
    assert run(["friction", "--voltage", "1", "--rom", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"]["mass_kg"] == 0.065
    assert run(["friction", "--voltage", "1", "--rom", str(path), "--set", "mass=0.05", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"]["mass_kg"] == 0.05
    assert run(["friction", "--voltage", "1", "--rom", str(path)]) == 0
    assert "m = 0.065 kg (the device's mass)" in capsys.readouterr().out
    # a model saved before the device's mass was recorded (format /1) still reads, its mass unknown
    old = json.loads(four.to_json())
    old["format"] = "modalfe.ReducedModel/1"
    del old["device_mass"]
    assert np.isnan(forced.ReducedModel.from_json(json.dumps(old)).device_mass)


def test_reduced_model_carries_the_whole_devices_mass():
    # the Cu-Be plate (half model, mirrored): CuBe 64 x 38 x 3 mm at 8250 kg/m^3, ten 12 x 12 x 1 mm ceramics
    # (PZT-4, 7500 kg/m^3) and four 3 x 3 x 4 mm CuBe feet (seed 001 Table 1; Berlincourt 1964) = 72.2 g, the
    # mass seed 000's appendix gives as m = 0.0723 kg; r^T M r of the consistent mass is exact (rounding, 1e-9)
    from modalfe.response.forced import Damping, reduce
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    scene = load_scene("cube_plate", **{"mesh.elements_per_wavelength": 3.0})
    mode = solve_modes(scene, near=40e3, count=1, fidelity="solid", error_estimate=False)[0]
    rom = reduce(mode, outputs=("foot_1",), damping=Damping(Q=100))
    expected = 8250 * (64e-3 * 38e-3 * 3e-3 + 4 * 3e-3 * 3e-3 * 4e-3) + 7500 * 10 * 12e-3 * 12e-3 * 1e-3
    assert rom.device_mass == pytest.approx(expected, rel=1e-9)


def test_friction_at_zero_speed_prints_no_negative_zero_and_a_reduction_in_range(capsys):
    # issue 19: "--speed 0" printed 100.01 % and -0.0000 N.  Speed 0 is the limit V -> 0+ (no tangential
    # force after a touchdown, mu0 Rn without flight); every printed reduction lies in [0, 100] %.
    assert run(["friction", "--amplitude", "0:2e-6:41", "--preload", "10", "--speed", "0"]) == 0
    out = capsys.readouterr().out
    assert "-0.0" not in out and "speed 0" in out
    rows = [line.split() for line in out.splitlines() if line.strip().endswith(("0", "1")) and "%" in line]
    reductions = [float(r[3].rstrip("%")) for r in rows]
    assert len(reductions) == 41 and all(0.0 <= x <= 100.0 for x in reductions)


def test_finger_table_and_json_state_each_points_method(capsys):
    # Every point says how it was obtained: "periodic kT" (a stable orbit of period k T) or
    # "average +- u" (a time average and its uncertainty), in the table and in the JSON.
    assert run(["finger", "--frequency", "66e3", "--amplitude", "0.5e-6,0.75e-6,1.2e-6"]) == 0
    out = capsys.readouterr().out
    assert "periodic 1T" in out and "periodic 2T" in out and "average +- " in out
    assert run(["finger", "--frequency", "66e3", "--amplitude", "0.75e-6,1.2e-6", "--json"]) == 0
    (curve,) = json.loads(capsys.readouterr().out)["curves"]
    assert curve["method"][0] == "periodic 2T" and curve["method"][1].startswith("average +- ")
    assert curve["uncertainty"][0] == 0.0 and curve["uncertainty"][1] > 0


def test_default_finger_curves_are_fast():
    # issue 19 item 3: the default `modalfe finger` took ~51 s (66 kHz points 1-2.5 s each).  Its two
    # default curves now take ~3.4 s of CPU here (1.3-2.1 s before issue 35's honest uncertainty: 568-period
    # windows instead of 150); the bound is twice that, for a loaded machine, and still 7x below the old time.
    import time

    from modalfe.contact.finger import FREQUENCIES, simulate_finger

    parser = argparse.ArgumentParser(prog="modalfe")
    cli_contact.register(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(["finger"])
    start = time.process_time()
    curves = [simulate_finger(a, f) for f, a in zip(FREQUENCIES, cli_contact._finger_amplitudes(args, FREQUENCIES))]
    assert time.process_time() - start < 7.0
    assert all(len(c.amplitude_pp) == 25 for c in curves)
