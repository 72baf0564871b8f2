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
