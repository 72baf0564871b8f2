"""``--html DIR``: the design page (``modalfe.report.page``) of the scenes a command solved: each scene's description
(as ``modalfe info`` gives it), pictures of its working modes rendered from the answers the command just resolved
(read back from the answer cache, ``modalfe.solve.resolved``: no new eigen solve, unless a plate or beam model
answered: the picture is then the 3-D solid's, solved as ``modalfe show`` does), and its forced-response and
admittance plots (the working mode's reduced model) where the scene names drive outputs."""

from __future__ import annotations

import logging
import re
import sys
from pathlib import Path

log = logging.getLogger(__name__)

PICTURE_SIZE = (1400, 520)  # two panels (iso and bottom) and the colour bar, as `show` draws them


def add_html_option(parser) -> None:
    """``--html DIR`` on a command's parser."""
    parser.add_argument("--html", metavar="DIR", help="also write a design page, DIR/index.html with its pictures: the "
                                                      "scene's parts, materials, supports and electrodes, its working "
                                                      "modes against their targets and drawn, forced response and "
                                                      "admittance, assumptions (the report's solve of the scene)")


def scene_page(args, scene) -> None:
    """``--html`` of a command that solves one scene: the report's rows of ``scene`` (``device_report``, at the
    command's solve options; answers already resolved are read back) on a page in ``args.html``."""
    from modalfe.cli.options import solve_keywords
    from modalfe.report.report import device_report

    if not getattr(args, "html", None):
        return
    keywords = solve_keywords(args)
    rows = device_report(scene, **keywords)
    page = write_design_page(args.html, [(scene, rows)], keywords=keywords, command=args.command_line)
    print(f"design page: {page}", file=sys.stderr if getattr(args, "json", False) else sys.stdout)


def write_design_page(directory: str, scenes: list, *, keywords: dict, command: str) -> Path:
    """Write the page of ``scenes``, (scene, its ``modalfe.report.report.ReportRow``s solved with the ``solve_modes``
    ``keywords``) pairs, made by ``command`` (the command line), and its pictures into ``directory``; returns the
    page's path."""
    import modalfe
    from modalfe.cli.info import scene_info
    from modalfe.errors import ModalfeError
    from modalfe.plot.render import mode_title, render_mode
    from modalfe.report.page import Picture, SceneSection, write_page
    from modalfe.report.report import window_modes, working_windows
    from modalfe.results.modes import select

    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    sections = []
    for scene, rows in scenes:
        name = scene.name
        pictures, notes = [], []
        for window in working_windows(scene):
            try:
                modes = window_modes(window, **keywords)  # the report's answer, from the cache
                if modes.fidelity != "solid":  # a plate or beam model answered: the picture is the 3-D solid's
                    modes = window_modes(window, **{**keywords, "fidelity": "solid"})
            except ModalfeError as exc:
                notes.append(f"no picture of {', '.join(w.selector for w in window.members)}: {exc}")
                continue
            for wm in window.members:
                mode = select(modes, wm.selector, wm.near)
                file = f"{name}_{_slug(mode.label)}.png"
                log.info("%s: drawing %s", name, mode.label)
                render_mode(mode, out=str(folder / file), window_size=PICTURE_SIZE, view="iso+bottom").close()
                pictures.append(Picture(file, f"{mode_title(mode)}; left: iso view, right: from below; colour: the "
                                              f"normal displacement, black lines: nodal lines"))
        plots = _forced_plots(scene, folder, keywords, notes)
        sections.append(SceneSection(scene_info(scene), rows, pictures, plots, notes))
    return write_page(folder, sections, command=command, version=modalfe.__version__)


def _forced_plots(scene, folder: Path, keywords: dict, notes: list[str]) -> list:
    """The working mode's FRF and admittance (``modalfe forced --plot``) in ``folder``; a scene without drive outputs,
    or whose reduced model fails, gets a note instead."""
    from modalfe.errors import ModalfeError
    from modalfe.plot.figures import write_forced_plots
    from modalfe.report.page import Picture
    from modalfe.response.figures import forced_figures

    if not scene.drive.outputs or not scene.working_modes:
        notes.append("no forced response drawn: the scene names no drive outputs or working mode")
        return []
    try:
        fig = forced_figures(scene, **keywords)
    except ModalfeError as exc:
        notes.append(f"no forced response drawn: {exc}")
        return []
    paths = write_forced_plots(fig, str(folder / f"{scene.name}_forced.png"), 1.0)
    captions = [f"forced response of {fig.rom.label} per {fig.load_unit} ({fig.load_description}), "
                f"{fig.rom.damping_description} ({fig.damping_source}); fr and fa dotted",
                "electrical admittance of the working mode's reduced model (its BVD circuit), fr and fa dotted"]
    return [Picture(Path(p).name, c) for p, c in zip(paths, captions)]


def _slug(label: str) -> str:
    """A file-name-safe form of a mode label: '(0,6)' -> '0_6', 'bending-z 6' -> 'bending-z_6'."""
    return re.sub(r"[^A-Za-z0-9-]+", "_", label).strip("_") or "mode"
