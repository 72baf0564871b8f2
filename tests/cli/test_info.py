"""`modalfe info`: the scene described without meshing, text and pure JSON; `place` refuses a scene without feet."""

from __future__ import annotations

import json

import pytest

from modalfe.cli.main import main


def test_info_json_lists_parts_roles_symmetry_and_the_size_estimate(capsys, monkeypatch):
    import modalfe.models.mesh as mesh

    monkeypatch.setattr(mesh, "build_mesh", lambda *a, **k: pytest.fail("info must not mesh"))
    assert main(["info", "cube_plate", "--json"]) == 0
    out = capsys.readouterr().out
    info = json.loads(out)  # stdout is pure JSON
    parts = {p["name"]: p for p in info["parts"]}
    assert {f"foot_{i}" for i in range(1, 5)} <= set(parts) and len(parts) == 15  # the whole device
    assert parts["ceramic_1"]["size_m"] == pytest.approx([12e-3, 12e-3, 1e-3])
    assert parts["ceramic_1"]["poling"] == "+z" and parts["ceramic_3"]["poling"] == "-z"
    assert info["face_groups"]["electrode_top"]["role"] == "driven electrode"
    assert "Berlincourt" in info["materials"]["PZT-4"]["source"]
    assert info["symmetry"]["model"] == "half model" and info["symmetry"]["planes"][0]["axis"] == "y"
    assert info["estimate"]["solid"]["dofs"] > 1000 and info["estimate"]["solid"]["memory_bytes"] > 0


def test_info_text_names_supports_and_a_bad_override_in_one_line(capsys):
    assert main(["info", "honeycomb_tile"]) == 0
    text = capsys.readouterr().out
    assert "spring (kx, ky, kz)" in text and "mass 2.3 kg" in text and "symmetry: none" in text
    assert main(["info", "cube_plate", "--set", "ceramic_thickness=-1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "ceramic_thickness" in err[0]


def test_place_refuses_a_scene_without_feet(capsys):
    assert main(["place", "glass_plate"]) == 2
    assert "no feet" in capsys.readouterr().err
