"""`modalfe show`: a mode named by label is sought near that working mode, a label's form is checked before the
solve, and an upper-case extension writes the file it names (issue 35)."""

import pytest

from modalfe.cli.main import main
from modalfe.errors import SolverError
from tests.hostile.cases import BIMORPH

pytest.importorskip("pyvista")


def test_a_working_mode_named_by_label_is_sought_near_its_own_frequency(monkeypatch, capsys):
    asked = []

    def solve(scene, **kw):
        asked.append(kw["near"])
        raise SolverError("stand-in solve: only what it was asked matters")

    monkeypatch.setattr("modalfe.solve.api.solve_modes", solve)
    for argv, near in ((["--mode", "(1,1)"], 896.0), (["--mode", "(1,1)#2"], 896.0), ([], 45.0),
                       (["--mode", "heave"], 45.0), (["--mode", "(1,1)", "--near", "700"], 700.0)):
        assert main(["show", "honeycomb_tile", "--out", "t.png", *argv]) == 1
        assert asked.pop() == near, argv
    capsys.readouterr()
    assert main(["show", "honeycomb_tile", "--mode", "twist", "--out", "t.png"]) == 2 and not asked  # no solve
    assert capsys.readouterr().err.startswith("modalfe: error: --mode: 'twist' is not a mode label")


@pytest.mark.parametrize("name", ["m.PNG", "m.Gif"])
def test_an_upper_case_extension_is_written(tmp_path, capsys, name):
    scene = tmp_path / "bimorph.toml"
    scene.write_text(BIMORPH)
    out = tmp_path / name
    assert main(["show", str(scene), "--out", str(out)]) == 0
    magic = {".png": b"\x89PNG", ".gif": b"GIF8"}[out.suffix.lower()]
    assert out.read_bytes().startswith(magic)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["bimorph.toml", name])  # no temporary left
