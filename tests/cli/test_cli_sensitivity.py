"""``modalfe sensitivity``: the table and JSON of df/dp per mode and parameter, and its one-line errors."""

import json

import pytest

from modalfe.cli.main import main

STRIP = """
name = "strip"
units = "mm"
kind = "plate"
materials = { steel = { E = 200e9, nu = 0.3, rho = 7850.0 } }
analysis = { near = 3000.0, count = 4 }
mesh = { max_size = 2e-3, elements_per_wavelength = 1, min_layers = 1 }
parts = [{ name = "strip", material = "steel", origin = [0, 0, 0], size = [60, 10, 1] }]
"""


def test_json_gives_each_mode_and_parameter(tmp_path, capsys):
    """A free steel strip: f ~ sqrt(E) exactly in the discrete model (K linear in E at fixed nu), so d ln f / d ln E
    = 1/2 for every elastic mode to the central difference's round-off (1e-6 here; measured 3e-8,
    tests/response/test_sensitivity.py); rigid-body modes (0 Hz) have no derivative (null)."""
    path = tmp_path / "strip.toml"
    path.write_text(STRIP)
    assert main(["sensitivity", str(path), "--vary", "materials.steel.E,parts.strip.size.x", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["scene"] == "strip" and out["values"]["materials.steel.E"] == 200e9
    elastic = [m for m in out["modes"] if m["frequency_hz"] > 1.0]
    assert elastic and len(elastic) < len(out["modes"])
    for mode in elastic:
        assert mode["parameters"]["materials.steel.E"]["dlnf_dlnp"] == pytest.approx(0.5, abs=1e-6)
        # a bending mode of a 60 x 10 x 1 mm strip: f ~ 1 / length^2 (Kirchhoff), within shear effects
        assert mode["parameters"]["parts.strip.size.x"]["dlnf_dlnp"] == pytest.approx(-2.0, abs=0.02)
    rigid = [m for m in out["modes"] if m["frequency_hz"] <= 1.0]
    assert all(m["parameters"]["materials.steel.E"]["df_dp"] is None for m in rigid)


def test_table_names_each_parameter(tmp_path, capsys):
    path = tmp_path / "strip.toml"
    path.write_text(STRIP)
    assert main(["sensitivity", str(path), "--vary", "materials.steel.rho"]) == 0
    out = capsys.readouterr().out
    assert "materials.steel.rho = 7850" in out and "-0.5000" in out


@pytest.mark.parametrize(("vary", "message"), [
    ("nothing", "nothing: not a parameter a sensitivity can be taken to"),
    ("x0,x0", "--vary: give distinct parameter names"),
    (",", "--vary: give distinct parameter names"),
])
def test_bad_parameters_are_refused_in_one_line(capsys, vary, message):
    assert main(["sensitivity", "ciliary_beam", "--vary", vary]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err


CANTILEVER = """
name = "patch-cantilever"
units = "mm"
kind = "beam"
materials = { steel = { E = 200e9, nu = 0.3, rho = 7800.0 } }
analysis = { near = 16e3, count = 3 }
mesh = { elements_per_wavelength = 1.0, max_size = 2e-3, min_layers = 1 }
parts = [{ name = "plate", material = "steel", origin = [0, 0, 0], size = [30, 6, 1] },
         { name = "patch", region = "piezo", material = "PZT-5A", origin = [2, 0, 1], size = [12, 6, 0.5], poling = 1 }]
faces = { root = ["plate.xmin"], tip = ["plate.xmax"], top = ["patch.zmax"], bottom = ["patch.zmin"] }
clamps = { root = "xyz" }
springs = { tip = [0.0, 0.0, 1e4] }
electrodes = { top = "drive", bottom = "ground" }
"""
AMPLITUDE = ["--amplitude", "--mode", "bending-z 3", "--near", "16e3", "--damping", "Q=100", "--outputs", "tip"]


def test_amplitude_json_is_the_librarys(tmp_path, capsys):
    """--amplitude: the working mode's amplitude per volt and d ln A / d ln p are ``amplitude_sensitivities``' for the
    same mode, outputs and damping (verified against full solves in tests/response/test_sensitivity_amplitude.py),
    and the frequency table comes from the same pass."""
    from modalfe.response.forced import Damping
    from modalfe.response.sensitivity import amplitude_sensitivities
    from modalfe.scene import load_scene
    from modalfe.solve.api import solid_modes

    path = tmp_path / "cantilever.toml"
    path.write_text(CANTILEVER)
    names = ["parts.plate.size.x", "springs.tip.z"]
    assert main(["sensitivity", str(path), "--vary", ",".join(names), "--json", *AMPLITUDE]) == 0
    out = json.loads(capsys.readouterr().out)
    # the mode as every command answers it: ``modes``' resolved model for the question (near 16 kHz, the mode named)
    modes = solid_modes(load_scene(str(path)), needs="a test", near=16e3, count=3, mode="bending-z 3")
    found = amplitude_sensitivities(modes, names, mode=modes.labelled("bending-z 3"), outputs=["tip"],
                                    damping=Damping(Q=100))
    tip = out["amplitude"]["outputs"]["tip"]
    assert out["amplitude"]["mode"] == "bending-z 3" and "Q = 100" in out["amplitude"]["damping"]
    assert tip["amplitude_m_per_v"] == pytest.approx(found.amplitude[0], rel=1e-9)
    for j, name in enumerate(names):
        assert tip["parameters"][name]["dlnA_dlnp"] == pytest.approx(found.relative[0, j], rel=1e-6, abs=1e-9)
    # the plate's length moves the tip's amplitude (0.82 measured); the frequency table is there too
    assert tip["parameters"]["parts.plate.size.x"]["dlnA_dlnp"] > 0.5
    assert len(out["modes"]) == 3


def test_amplitude_table(tmp_path, capsys):
    path = tmp_path / "cantilever.toml"
    path.write_text(CANTILEVER)
    assert main(["sensitivity", str(path), "--vary", "springs.tip.z", *AMPLITUDE]) == 0
    out = capsys.readouterr().out
    assert "mode bending-z 3 at 16" in out and "amplitude per volt at resonance" in out
    assert out.splitlines()[-1].split()[0] == "tip"


@pytest.mark.parametrize(("extra", "message"), [
    (["--amplitude"], "--amplitude: the scene names no working mode; give --mode and --near"),
    (["--damping", "Q=100"], "--damping: applies to --amplitude only"),
    (["--amplitude", "--mode", "bending-z 3", "--near", "16e3", "--damping", "Q=-1"], "damping.Q: must be finite"),
    (["--amplitude", "--mode", "bending-z 3", "--near", "16e3", "--outputs", "nowhere"], "outputs: no face group"),
])
def test_amplitude_refusals_are_one_line(tmp_path, capsys, extra, message):
    path = tmp_path / "cantilever.toml"
    path.write_text(CANTILEVER)
    assert main(["sensitivity", str(path), "--vary", "springs.tip.z", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err
