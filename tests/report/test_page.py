"""The design page (`modalfe report --html DIR`) opened in a real headless Chromium: it renders, with every picture
decoded at its own size; its sections hold the scene, the targets, the assumptions, the command and the version."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from modalfe.cli.main import main

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
# a script the test adds to a copy of the page: once every image has loaded (or failed), it writes their decoded
# widths into the DOM, which --dump-dom prints (0 for a picture the browser could not read)
PROBE = """<script>
window.addEventListener("load", () => {
  const widths = [...document.images].map(i => i.complete ? i.naturalWidth : 0);
  document.body.setAttribute("data-widths", widths.join(","));
});
</script></body>"""


def chromium(*args: str, profile: Path) -> str:
    """Run headless Chromium with no network, sync or first-run work and return its stdout."""
    command = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
               "--disable-component-update", "--disable-sync", "--no-first-run", f"--user-data-dir={profile}", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, check=True).stdout


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    """The ciliary beam's page at its scene's own mesh (no refinement: ~4 s of solving; the 4 seed devices at the
    default tolerance take ~8 s more and draw the same sections)."""
    folder = tmp_path_factory.mktemp("html")
    status = main(["report", "--scene", "ciliary_beam", "--no-error-estimate", "--jobs", "1", "--html", str(folder)])
    assert status == 0
    return folder / "index.html"


def test_the_page_holds_the_scene_the_table_and_where_it_came_from(page):
    text = page.read_text()
    for needed in ("brass-seed003", "seed 003 (E, rho)", "clamp (xyz fixed)", "driven electrode", "f_measured",
                   "Assumptions and their sources", "modalfe report --scene ciliary_beam", "modalfe 0."):
        assert needed in text, needed
    files = re.findall(r'<img src="([^"]+)"', text)
    # the working mode's picture, the FRF and the admittance, all in the page's folder
    assert len(files) == 3 and all((page.parent / f).is_file() for f in files)


@pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (apt-get install -y chromium; .ci/run does)")
def test_chromium_renders_the_page_with_every_picture_decoded(page, tmp_path):
    from PIL import Image

    probe = page.with_name("probe.html")  # beside the page: the pictures' relative paths hold
    probe.write_text(page.read_text().replace("</body>", PROBE))
    dom = chromium("--virtual-time-budget=10000", "--dump-dom", probe.as_uri(), profile=tmp_path / "profile")
    found = re.search(r'data-widths="([^"]*)"', dom)
    assert found, "the page did not finish loading in Chromium"
    widths = [int(w) for w in found.group(1).split(",")]
    files = re.findall(r'<img src="([^"]+)"', page.read_text())
    assert widths == [Image.open(page.parent / f).size[0] for f in files]  # each decoded at its own width

    shot = tmp_path / "page.png"
    chromium("--hide-scrollbars", "--window-size=1280,2000", f"--screenshot={shot}", page.as_uri(),
             profile=tmp_path / "profile")
    levels = Image.open(shot).convert("L").histogram()
    # not blank: a white page has one grey level; text, tables and the pictures give well over 50
    assert sum(count > 0 for count in levels) > 50


@pytest.mark.parametrize("command", [["report", "--scene", "ciliary_beam"], ["modes", "ciliary_beam"],
                                     ["forced", "ciliary_beam"],
                                     ["admittance", "ciliary_beam", "--band", "2e4", "3e4"],
                                     ["table", "ciliary_beam"], ["show", "ciliary_beam", "--out", "x.png"],
                                     ["export", "ciliary_beam", "--vtu", "x.vtu"], ["place", "cube_plate"],
                                     ["sensitivity", "ciliary_beam", "--vary", "length"],
                                     ["tune", "ciliary_beam", "--target", "bending-z 6=23.2e3", "--vary", "length"]])
def test_html_naming_a_file_is_refused_before_any_solve(command, tmp_path, capsys, monkeypatch):
    import modalfe.solve.api as api

    def no_solve(*_args, **_kw):
        raise AssertionError("solved before checking --html")

    monkeypatch.setattr(api, "solve_modes", no_solve)
    monkeypatch.setattr(api, "solid_modes", no_solve)
    taken = tmp_path / "page.html"
    taken.write_text("")
    assert main([*command, "--html", str(taken)]) == 2
    assert "error: --html: " in capsys.readouterr().err  # one line naming the flag


@pytest.mark.parametrize("command", [["table"], ["show", "--out", "m.png"], ["export", "--vtu", "m.vtu"]])
def test_every_command_that_solves_writes_the_scene_s_page(command, tmp_path, monkeypatch, capsys):
    # ``--html DIR`` on any command that solves a scene, as on modes, forced and admittance (the report's page)
    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "page"
    assert main([command[0], "ciliary_beam", *command[1:], "--no-error-estimate", "--html", str(folder)]) == 0
    page = (folder / "index.html").read_text()
    assert "ciliary_beam" in page and f"modalfe {command[0]} ciliary_beam" in page
    assert f"design page: {folder / 'index.html'}" in capsys.readouterr().out
