"""`modalfe show` (a mode-shape picture or animation) and `modalfe export` (VTU for ParaView)."""

from __future__ import annotations

import logging
import os
import time
from pathlib import Path

from modalfe.cli.options import frequency, positive_int, solve_options, stated
from modalfe.cli.page import add_html_option, scene_page
from modalfe.errors import SceneError

log = logging.getLogger(__name__)
VIEW = "iso+bottom"  # show's default view


def register(subparsers) -> None:
    p = subparsers.add_parser("show", help="render a mode shape (PNG, GIF, or a window when there is a display)")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--mode", help="mode label (e.g. '(0,6)') or index among the computed modes "
                                  "(default: the scene's first working mode)")
    p.add_argument("--near", type=frequency, help="frequency [Hz] to search near (default: the working mode's)")
    p.add_argument("--out", help="FILE.png or FILE.gif (default: a window if there is a display, "
                                 "else <scene>.png)")
    p.add_argument("--view", choices=("iso", "top", "bottom", "iso+bottom"), default=VIEW,
                   help="iso+bottom (default): two panels, so that markers under the device (feet, electrodes "
                        "on the lower face) show as well as those on top")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    solve_options(p)
    add_html_option(p)
    p.set_defaults(func=_show)

    p = subparsers.add_parser("export", help="write every computed mode to a VTU file (quadratic cells, part "
                                             "names, displacement, potential, strain, stress, von Mises, electric "
                                             "field, stated error) and its mode table CSV")
    p.add_argument("scene")
    p.add_argument("--vtu", required=True, help="output file (.vtu)")
    p.add_argument("--near", type=frequency)
    p.add_argument("--count", type=positive_int)
    p.add_argument("--set", action="append", metavar="KEY=VALUE")
    solve_options(p)
    add_html_option(p)
    p.set_defaults(func=_export)


def _modes(args, question):
    """(scene, the modes ``modes`` answers ``question(scene)`` with at the command's --tol): the solid's or the
    axisymmetric model's (drawn and exported revolved)."""
    from modalfe.cli.options import parse_overrides, solve_keywords
    from modalfe.models.estimate import estimate_size
    from modalfe.scene import load_scene
    from modalfe.solve.api import REVOLVED, solid_modes

    scene = load_scene(args.scene, **parse_overrides(args.set))
    asked = question(scene)
    log.info("%s: solving %s, %s", scene.name, asked, estimate_size(scene).describe())
    start = time.perf_counter()
    modes = solid_modes(scene, needs=f"modalfe {args.command}", takes=REVOLVED, **asked, **solve_keywords(args))
    log_timings(modes, time.perf_counter() - start)
    return scene, modes


def log_timings(modes, seconds: float) -> None:
    """One INFO line with the solve's stages and their seconds (mesh, assembly, factorization, eigensolve)."""
    stages = ", ".join(f"{k} {v:.2f} s" for k, v in modes.timings.items() if isinstance(v, int | float))
    log.info("%d modes, %d DOFs, %s model, in %.1f s (%s)", len(modes), modes.dofs, modes.fidelity, seconds, stages)


def _show(args) -> int:
    from modalfe.errors import SolverError
    from modalfe.results.labels import check_selector
    from modalfe.results.modes import select
    from modalfe.solve.api import seek, working_question

    index = args.mode is not None and args.mode.isdigit()  # --mode N: an index among the modes computed
    selector = None if args.mode is None or index else check_selector(args.mode, "--mode")  # before the solve

    def question(scene) -> dict:  # the working mode's (or the one named), as ``forced`` asks it; before the solve
        if not index and selector is None and not scene.working_modes:
            raise SolverError("show: the scene names no working mode; give --mode")
        if index:
            return {"near": args.near or seek(scene)[1]}
        return working_question(scene, selector, args.near)

    interactive, gif = _window_or_gif(args.out)
    # a PNG: drawn by a second process that loads VTK while this one solves (``render_process``), started with the
    # command where it could be (``early_drawer``)
    drawer = None if interactive or gif else (getattr(args, "early_drawer", None) or _drawer(args.view))
    try:
        scene, modes = _modes(args, question)
        if index:
            if int(args.mode) >= len(modes):
                raise SolverError(f"--mode: index {args.mode} out of range (0-{len(modes) - 1})")
            mode = modes[int(args.mode)]
        else:
            mode = select(modes, *seek(scene, selector, args.near))
        out = args.out or (None if interactive else f"{scene.name}.png")
        start = time.perf_counter()
        if gif:
            from modalfe.plot.render import animate_mode

            animate_mode(mode, out, view=args.view)
        elif interactive:
            from modalfe.plot.render import render_mode

            render_mode(mode, out=out, view=args.view, off_screen=False).show()
        else:
            _render_png(drawer, mode, out, args.view)
    finally:
        if drawer is not None:
            drawer.close()
    log.info("rendered in %.2f s", time.perf_counter() - start)
    scene_page(args, scene)
    if out:
        print(f"{scene.name}: {mode.label} at {mode.frequency:.2f} Hz (stated error {stated(mode.error_estimate)}) "
              f"-> {out}")
    return 0


def _window_or_gif(out: str | None) -> tuple[bool, bool]:
    """(drawn in a window, animated into a GIF) for ``show --out out``; else a PNG."""
    return out is None and bool(os.environ.get("DISPLAY")), out is not None and Path(out).suffix.lower() == ".gif"


def early_drawer(argv: list[str]):
    """The rendering process of ``show`` writing a PNG (its plotter made for the view typed), started from the command
    line as typed, before the parser loads the library (~0.6 s of one core on the 2-core machine, which the second
    process' own loading of VTK then shares; ``_show`` takes it from ``args.early_drawer``); None for any other
    command, a window, a GIF or help. A command line that then fails to parse only stops it."""
    words = [w for w in argv if w not in ("-v", "--verbose")]
    if not words or words[0] != "show" or "-h" in words or "--help" in words:
        return None
    return None if any(_window_or_gif(_typed(words, "--out"))) else _drawer(_typed(words, "--view") or VIEW)


def _typed(words: list[str], flag: str) -> str | None:
    """The value typed for ``flag`` (``--out x``, else ``--out=x``), None where it is not typed."""
    value = next((w.split("=", 1)[1] for w in words if w.startswith(f"{flag}=")), None)
    if flag in words and words.index(flag) + 1 < len(words):
        value = words[words.index(flag) + 1]
    return value


def _drawer(view: str):
    """The second process that will draw the PNG of ``view`` (``modalfe.plot.render_process``), None where it cannot
    start."""
    from modalfe.plot.render_process import RenderProcess, RenderProcessError

    try:
        return RenderProcess(view)
    except RenderProcessError as exc:
        log.info("%s; drawing in this process", exc)
        return None


def _render_png(drawer, mode, out: str, view: str) -> None:
    """``mode`` drawn into ``out`` by the second process (``drawer``), else (None, or it failed: said in the log)
    here."""
    from modalfe.plot.render_process import RenderProcessError

    try:
        if drawer is None:
            raise RenderProcessError("no rendering process")
        drawer.render(mode, out, view)
    except RenderProcessError as exc:
        log.info("%s; drawing in this process", exc)
        from modalfe.plot.render import render_mode

        try:
            render_mode(mode, out=out, view=view, off_screen=True).close()
        except OSError as exc:  # the file became unwritable during the solve (checked before it)
            raise SceneError(f"--out: '{out}' cannot be written ({exc.strerror or exc})") from None


def _export(args) -> int:
    from modalfe.report.export import export_vtu, table_path

    scene, modes = _modes(args, lambda scene: {"near": args.near, "count": args.count})
    path = export_vtu(modes, args.vtu)
    scene_page(args, scene)
    cells = "the axisymmetric answer revolved: linear cells" if modes.fidelity == "axisymmetric" else "quadratic cells"
    what = (f"{cells}, part names; per mode displacement [m] and potential [V] at the nodes, strain, stress, von Mises "
            f"and electric field as cell means")
    print(f"{scene.name}: {len(modes)} modes -> {path} ({what}; each mode's stated error), frequency table -> "
          f"{table_path(path)}")
    return 0
