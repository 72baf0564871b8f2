"""`modalfe show`: a mode named by label is sought near that working mode, a label's form is checked before the
solve, and an upper-case extension writes the file it names (issue 35)."""

from pathlib import Path

import pytest

from modalfe.cli.main import build_parser, main
from modalfe.errors import SolverError
from tests.hostile.cases import BIMORPH

pytest.importorskip("pyvista")


def test_a_working_mode_named_by_label_is_sought_near_its_own_frequency(monkeypatch, capsys):
    """A working mode named is asked as the scene's own question (the tile's band, which holds it: the answer
    ``modes`` gives); another label or --near, near that frequency."""
    asked = []

    def solve(scene, **kw):
        asked.append((kw.get("near"), kw.get("band"), kw.get("mode")))
        raise SolverError("stand-in solve: only what it was asked matters")

    build_parser()  # every command's module imported before the patch: none may bind the stand-in (tune's does)
    monkeypatch.setattr("modalfe.solve.api.solve_modes", solve)
    band = (1.0, 1500.0)  # honeycomb_tile's analysis band
    for argv, question in ((["--mode", "(1,1)"], (None, band, "(1,1)")),
                           (["--mode", "(1,1)#2"], (896.0, None, "(1,1)#2")),
                           ([], (None, band, "heave")), (["--mode", "heave"], (None, band, "heave")),
                           (["--mode", "(1,1)", "--near", "700"], (700.0, None, "(1,1)"))):
        assert main(["show", "honeycomb_tile", "--out", "t.png", *argv]) == 1
        assert asked.pop() == question, argv
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


@pytest.mark.parametrize("broken", ["start", "render"])
def test_a_rendering_process_that_fails_leaves_the_picture_to_this_one(tmp_path, monkeypatch, caplog, broken):
    # the PNG is drawn by a second process started before the solve; where it cannot start or fails, show draws it
    # itself and says why in the log
    import logging

    from modalfe.plot import render_process

    def fail(*args, **kwargs):
        raise render_process.RenderProcessError(f"stand-in failure at {broken}")

    monkeypatch.setattr(render_process.RenderProcess, "__init__" if broken == "start" else "render", fail)
    scene = tmp_path / "bimorph.toml"
    scene.write_text(BIMORPH)
    out = tmp_path / "m.png"
    with caplog.at_level(logging.INFO, logger="modalfe.cli.view"):
        assert main(["show", str(scene), "--out", str(out)]) == 0
    assert out.read_bytes().startswith(b"\x89PNG")
    assert f"stand-in failure at {broken}; drawing in this process" in caplog.text


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs /proc: a folder no one, root included, writes in")
def test_an_out_file_that_cannot_be_created_is_refused_before_the_solve(tmp_path, monkeypatch, capsys):
    # issue 35 (work thrown away late): `show --out /proc/m.png` rendered for 5 s, then failed naming no flag. The
    # folder passes os.access for root; creating the file is the check, made before the solve
    def no_solve(*_args, **_kw):
        raise AssertionError("solved before refusing")

    monkeypatch.setattr("modalfe.solve.api.solve_modes", no_solve)
    scene = tmp_path / "bimorph.toml"
    scene.write_text(BIMORPH)
    assert main(["show", str(scene), "--out", "/proc/modalfe-show.png"]) == 2
    assert capsys.readouterr().err.strip().startswith("modalfe: error: --out: '/proc/modalfe-show.png' cannot be "
                                                      "written")


def test_the_rendering_process_starts_with_the_command_only_for_a_png(monkeypatch):
    """`show` writing a PNG starts its drawing process from the command line as typed, before the parser loads the
    library; any other command, a GIF, a window or help starts none (``early_drawer``)."""
    from modalfe.cli import view

    monkeypatch.setattr(view, "_drawer", lambda shown: f"drawer of {shown}")
    monkeypatch.delenv("DISPLAY", raising=False)
    for argv in (["show", "cube_plate"], ["-v", "show", "x.toml", "--out", "m.png"], ["show", "--out=m.PNG", "x"]):
        assert view.early_drawer(argv) == "drawer of iso+bottom", argv
    for argv in (["show", "x", "--view", "top"], ["show", "--view=top", "x", "--out", "m.png"]):  # its plotter ahead
        assert view.early_drawer(argv) == "drawer of top", argv
    for argv in (["modes", "show"], ["show", "x", "--out", "m.gif"], ["show", "--out=m.GIF", "x"], ["show", "-h"],
                 ["show", "x", "--help"], [], ["export", "x", "--out", "m.png"]):
        assert view.early_drawer(argv) is None, argv
    monkeypatch.setenv("DISPLAY", ":0")
    assert view.early_drawer(["show", "x"]) is None  # a window: drawn in this process
    assert view.early_drawer(["show", "x", "--out", "m.png"]) == "drawer of iso+bottom"
