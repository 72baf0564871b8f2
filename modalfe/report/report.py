"""The eigenfrequency report: each device's working modes beside the seeds' targets."""

from __future__ import annotations

import functools
import math
import multiprocessing
import os
import signal
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace

from modalfe.errors import SceneError, SolverError
from modalfe.results.labels import RIGID_NAMES
from modalfe.results.modes import select
from modalfe.solve.api import DEFAULT_TOL

REPORT_COUNT = 10  # modes asked around a target at least (the labels of a dense spectrum need neighbours)
_MAX_COUNT = 80  # modes searched around a target before a working mode is declared missing


@dataclass(frozen=True)
class ReportRow:
    """One working mode of one device against its targets.

    frequency_hz [Hz]; wavelength_m [m] (plate modes, else None); error_estimate relative;
    seconds: wall time of the ``device_report`` call that made it (in ``run_report``, its window's solves);
    targets: name, value, unit, kind, source, deviation.
    """

    scene: str
    mode: str
    frequency_hz: float
    targets: list[dict]
    error_estimate: float | None
    dofs: int
    fidelity: str
    seconds: float
    wavelength_m: float | None = None
    antiresonance_hz: float | None = None
    k_eff: float | None = None
    notes: list[str] = field(default_factory=list)
    fidelity_note: str = ""
    estimate_method: str = ""
    assumptions: list[str] = field(default_factory=list)

    def to_json(self) -> dict:
        """Plain JSON: an unresolved (infinite) error estimate becomes null with ``error_unresolved``."""
        out = asdict(self)
        out["error_unresolved"] = self.error_estimate is not None and math.isinf(self.error_estimate)
        if out["error_unresolved"]:
            out["error_estimate"] = None
        return out


def device_report(scene, *, error_estimate: bool = True, fidelity: str = "auto", tol: float = DEFAULT_TOL,
                  windows: Sequence[int] | None = None) -> list[ReportRow]:
    """Rows for each working mode of ``scene`` (of the ``working_windows`` numbered ``windows``; default all);
    solves once per window (a frequency window on the working modes' mirror family), and once more in open circuit
    where the scene has a driven electrode (antiresonance and k_eff): at the solid when it answered, else from the
    solid's fa / fr at the cross-check level (``coupling_check_level``). With ``fidelity="auto"`` the working modes
    of the window must meet ``tol``."""
    from modalfe.response.forced import open_circuit
    from modalfe.results.coupling import k_eff
    from modalfe.solve.fidelity import coupling_check_level

    start = time.perf_counter()
    every = working_windows(scene)
    windows = [every[k] for k in (range(len(every)) if windows is None else windows)]
    solved = {id(w): window_modes(w, error_estimate=error_estimate, fidelity=fidelity, tol=tol) for w in windows}
    rows = []
    for wm in scene.working_modes:
        window = next((w for w in windows if wm in w.members), None)
        if window is None:
            continue  # a working mode of a window not asked for
        modes = solved[id(window)]
        mode = select(modes, wm.selector, wm.near)
        family, band = window.scene, window.near is None
        targets = []
        for t in wm.targets:
            value = mode.wavelength if t.unit == "m" else mode.frequency
            deviation = (value - t.value) / t.value if math.isfinite(value) else None
            targets.append({"name": t.name, "value": t.value, "unit": t.unit, "kind": t.kind,
                            "source": t.source, "deviation": deviation})
        fa = coupling = None
        notes = device_notes(family, modes, mode) + ([window.note] if window.note else [])
        if "drive" in family.electrodes.values() and modes.fidelity == "solid":
            both = open_circuit(mode, among=modes, near=mode.frequency if band else wm.near)
            fa, coupling = both.fa, both.k_eff
        elif "drive" in family.electrodes.values():
            fr_solid, fa_solid = coupling_check_level(modes, mode)
            fa, coupling = mode.frequency * fa_solid / fr_solid, k_eff(fr_solid, fa_solid)
            notes.append(f"k_eff and fa / fr from the 3-D solid at the cross-check's coarse level "
                         f"({fr_solid:.0f} / {fa_solid:.0f} Hz): the {modes.fidelity} model's piezo layers misplace "
                         f"k_eff by 10-15 % on the seed devices")
        rows.append(ReportRow(
            scene=scene.name, mode=mode.label, frequency_hz=mode.frequency, targets=targets,
            error_estimate=None if math.isnan(mode.error_estimate) else mode.error_estimate,
            dofs=modes.dofs, fidelity=modes.fidelity, fidelity_note=modes.fidelity_note,
            estimate_method=modes.estimate_method, seconds=0.0,
            wavelength_m=None if math.isnan(mode.wavelength) else mode.wavelength,
            antiresonance_hz=fa, k_eff=coupling, notes=notes,
            assumptions=list(scene.assumptions),
        ))
    seconds = time.perf_counter() - start
    return [ReportRow(**{**asdict(r), "seconds": seconds}) for r in rows]


@dataclass(frozen=True)
class Window:
    """One solve of the report: the scene solved (the working modes' mirror family, ``WorkingMode.family_scene``),
    the target ``near`` [Hz] (None: the scene's band), the working modes it holds, and why the family could not be
    used (else empty)."""

    scene: object
    near: float | None
    members: tuple
    note: str = ""


def working_windows(scene) -> list[Window]:
    """The report's solves of ``scene``: one per target frequency (or the band) and mirror family."""
    windows: dict = {}
    for wm in scene.working_modes:
        key = (None if scene.analysis.band is not None else wm.near, wm.symmetric, wm.antisymmetric)
        if key in windows:
            windows[key] = replace(windows[key], members=(*windows[key].members, wm))
        else:
            family, note = wm.family_scene(scene)
            windows[key] = Window(family, key[0], (wm,), note)
    return list(windows.values())


def window_modes(window: Window, **options):
    """The modes of one window, solved with ``options`` (and the members as ``check``); a dense spectrum is
    searched with twice the modes until every member is found, up to ``_MAX_COUNT``."""
    from modalfe.solve.api import solve_modes

    scene, check = window.scene, tuple((w.selector, w.near) for w in window.members)
    count = max(scene.analysis.count, REPORT_COUNT)
    while True:
        modes = (solve_modes(scene, check=check, **options) if window.near is None
                 else solve_modes(scene, near=window.near, count=count, check=check, **options))
        try:
            for w in window.members:
                select(modes, w.selector, w.near)
            return modes
        except SolverError:
            if window.near is None or count >= _MAX_COUNT:
                raise
            count *= 2  # dense spectrum: look at more modes around the target


def device_notes(scene, modes, mode) -> list[str]:
    """Computed remarks that explain a row: other modes of interest, model limits."""
    notes = []
    if scene.mirror_axes:
        notes.append(f"solved on the modes {scene.mirror_family} mid-plane(s) (half or quarter model); the others "
                     f"are not computed (modalfe modes with --set 'symmetry=[]' for all)")
    if math.isfinite(mode.wavelength) and scene.kind == "plate":
        main = scene.assembly().main_part
        f_thin = kirchhoff_frequency(scene.material(main.material).C, scene.material(main.material).rho,
                                     main.size[2], mode.wavelength)
        notes.append(f"Kirchhoff thin-plate theory at this wavelength: {f_thin:.0f} Hz "
                     f"({100 * (f_thin / mode.frequency - 1):+.1f}% vs the {modes.fidelity} model; "
                     f"thickness / wavelength "
                     f"{main.size[2] / mode.wavelength:.2f})")
    if scene.analysis.band is not None:
        rigid = [m for m in modes if m.label in RIGID_NAMES]
        # a mirror family holds only its share of them: said, with the command for all
        family = (f" (of the family solved; all: modalfe modes {scene.name} --band {scene.analysis.band[0]:g} "
                  f"{scene.analysis.band[1]:g} --set 'symmetry=[]')") if scene.mirror_axes else ""
        if rigid and mode.label in ("heave",):
            notes.append("suspension modes: " + ", ".join(f"{m.label} {m.frequency:.1f} Hz" for m in rigid)
                         + family + _reference(scene, "suspension"))
        plate = [m for m in modes if m not in rigid]
        if plate and mode.label not in ("heave",):
            notes.append("plate modes: " + ", ".join(f"{m.label} {m.frequency:.0f} Hz" for m in plate[:6])
                         + family + _reference(scene, "plate"))
    return notes


def _reference(scene, family: str) -> str:
    """`` (the seed's spectrum)`` of that family where the scene carries one, else nothing."""
    text = scene.reference_spectra.get(family)
    return f" ({text})" if text else ""


def kirchhoff_frequency(C, rho: float, thickness: float, wavelength: float) -> float:
    """Straight-crested flexural wave in a thin plate: f = k^2 sqrt(D / (rho h)) / (2 pi), k = 2 pi / wavelength,
    D = E' h^3 / 12 with E' = C11 - C13^2 / C33 = E / (1 - nu^2) (Kirchhoff; Graff, Wave Motion in
    Elastic Solids, 1975, sec. 4.2)."""
    modulus = C[0, 0] - C[0, 2] ** 2 / C[2, 2]
    k = 2 * math.pi / wavelength
    return k**2 * math.sqrt(modulus * thickness**2 / (12 * rho)) / (2 * math.pi)


def run_report(names: list[str] | None = None, *, progress: bool = True, error_estimate: bool = True,
               overrides: dict | None = None, fidelity: str = "auto", tol: float = DEFAULT_TOL,
               jobs: int | None = None) -> list[ReportRow]:
    """Report rows for the named built-in scenes (all of them by default), each at ``fidelity``, in the scenes'
    and their working modes' order; each window of each scene (``working_windows``) is one task, the tasks solved
    ``jobs`` at a time in separate processes (default: one per core), the most work first (``solve_order``)."""
    from modalfe.scene import load_scene
    from modalfe.scene.builtin import BUILTIN

    if jobs is not None and not (isinstance(jobs, int) and jobs >= 1):
        raise SceneError(f"jobs: must be a positive integer, got {jobs!r}")
    names = names or list(BUILTIN)
    # a bad name or override fails here, before any solve
    scenes = {name: load_scene(name, **(overrides or {})) for name in names}
    tasks = solve_order(scenes)
    jobs = min(jobs or os.cpu_count() or 1, len(tasks))
    task = functools.partial(window_rows, overrides=overrides or {}, error_estimate=error_estimate,
                             fidelity=fidelity, tol=tol)

    def progress_bar():
        if not progress:
            return None
        from tqdm import tqdm

        return tqdm(total=len(tasks), desc="modalfe report", unit="solve", leave=False)

    if jobs == 1:
        results, bar = {}, progress_bar()
        try:
            for name_window in tasks:
                results[name_window] = task(name_window)
                if bar is not None:
                    bar.update()
        finally:
            if bar is not None:
                bar.close()  # clears its line: an error or "interrupted" starts on a clean line
    else:
        results = _in_processes(task, tasks, jobs, progress_bar)
    return [row for name in names
            for _, row in sorted((pair for (n, _), pairs in results.items() if n == name for pair in pairs),
                                 key=lambda pair: pair[0])]


def solve_order(scenes: dict) -> list[tuple[str, int]]:
    """(scene name, window index) of every ``working_windows`` window of ``scenes``, the most work first, so that the
    processes finish together (longest-processing-time order). A window's work is guessed, without meshing, as the
    estimated DOFs of the 3-D solid it solves (its mirror family; ``modalfe.models.estimate.estimate_size``) times
    how near its working modes lie to the frequency the mesh resolves (``Scene.max_frequency``): a mode at the
    mesh's limit is the one whose estimate exceeds the tolerance and is refined (the glass plate's (0,16) at
    225 kHz of 250 kHz: 10 of its scene's 11 s in the report), one far below it is answered on the scene's grid
    or by a reduced model (the tile's heave at 45 Hz of 1.5 kHz). A scene's windows are tasks of their own."""
    from modalfe.models.estimate import estimate_size

    work = {(name, k): estimate_size(w.scene).dofs * max(wm.near for wm in w.members) / w.scene.max_frequency
            for name, scene in scenes.items() for k, w in enumerate(working_windows(scene))}
    return sorted(work, key=lambda name_window: -work[name_window])


def _in_processes(task, items: list, jobs: int, progress_bar) -> dict:
    """{item: ``task(item)``} of every item in ``jobs`` fresh processes, each with one MKL thread (two
    multithreaded PARDISO solves on two cores wait on each other); ``progress_bar()`` (a tqdm bar or None) is made
    once the workers have started (a forked worker copies no thread of its parent's: tqdm's monitor is one)."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    saved = os.environ.get("MKL_NUM_THREADS")
    os.environ["MKL_NUM_THREADS"] = "1"  # inherited by the workers, read when they load MKL
    bar = None
    try:
        pool = ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context(_start_method()),
                                   initializer=_ignore_sigint)
        try:
            # the workers start with SIGINT ignored (inherited): a Ctrl-C while they import prints nothing
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
            try:
                futures = {pool.submit(task, item): item for item in items}
            finally:
                signal.signal(signal.SIGINT, previous)
            bar = progress_bar()
            results = {}
            for future in as_completed(futures):
                results[futures[future]] = future.result()
                if bar is not None:
                    bar.update()
        except BaseException:  # Ctrl-C or a failed device: stop the workers now, not after their solves
            for process in list(getattr(pool, "_processes", {}).values()):
                process.terminate()
            pool.shutdown(wait=False, cancel_futures=True)
            raise
        pool.shutdown()
    finally:
        if bar is not None:
            bar.close()  # clears its line: an error or "interrupted" starts on a clean line
        if saved is None:
            os.environ.pop("MKL_NUM_THREADS")
        else:
            os.environ["MKL_NUM_THREADS"] = saved
    return results


def _start_method() -> str:
    """``fork`` where the system has it and this process has not loaded MKL or an OpenMP runtime (whose threads a
    fork does not copy): the workers start with modalfe already imported (~0.5 s of each worker's import saved, the
    report's start); else ``spawn``, fresh interpreters."""
    if "fork" not in multiprocessing.get_all_start_methods():
        return "spawn"
    try:
        with open("/proc/self/maps") as maps:
            loaded = maps.read()
    except OSError:
        return "spawn"
    return "spawn" if any(name in loaded for name in ("libmkl", "libiomp", "libgomp")) else "fork"


def _ignore_sigint() -> None:
    """Workers leave Ctrl-C to the parent, which stops them (no traceback from every worker), and their progress to
    the parent's bar (a forked worker would otherwise draw its steps over it)."""
    from modalfe.progress import hide

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    hide()


def window_rows(name_window: tuple[str, int], *, overrides: dict, error_estimate: bool, fidelity: str,
                tol: float) -> list[tuple[int, ReportRow]]:
    """(working-mode index, row) of each working mode of one window of a built-in scene; a solver failure becomes
    one FAILED row."""
    from modalfe.scene import load_scene

    name, window = name_window
    scene = load_scene(name, **overrides)
    members = working_windows(scene)[window].members
    indices = [i for i, wm in enumerate(scene.working_modes) if wm in members]  # device_report's row order
    try:
        rows = device_report(scene, error_estimate=error_estimate, fidelity=fidelity, tol=tol, windows=[window])
    except SolverError as exc:
        return [(indices[0], ReportRow(scene=name, mode="FAILED", frequency_hz=float("nan"), targets=[],
                                       error_estimate=None, dofs=0, fidelity="solid", seconds=0.0, notes=[str(exc)]))]
    return list(zip(indices, rows))


def format_rows(rows: list[ReportRow], *, detail: bool = False) -> str:
    """A plain-text table, one screen: one line per working mode (frequency, stated error, DOFs, fidelity, seconds, fa
    and k_eff), then its targets and deviations; with ``detail`` also the wavelength, how auto answered and how the
    error was estimated, the notes and each device's assumptions."""
    lines = [f"{'scene':<15} {'mode':<12} {'f [Hz]':>10} {'err est':>8} {'DOFs':>7} {'fidelity':>8} {'s':>6}  "
             f"fa, k_eff"]
    for r in rows:
        err = "n/a" if r.error_estimate is None else "unresolved" if math.isinf(r.error_estimate) else \
            f"{100 * r.error_estimate:.2f}%"
        coupling = f"  {r.antiresonance_hz:.1f} Hz, {r.k_eff:.4f}" if r.k_eff is not None else ""
        lines.append(f"{r.scene:<15} {r.mode:<12} {r.frequency_hz:>10.1f} {err:>8} {r.dofs:>7} "
                     f"{r.fidelity:>8} {r.seconds:>6.1f}{coupling}")
        for t in r.targets:
            dev = f"{100 * t['deviation']:+.1f}%" if t["deviation"] is not None else "n/a"
            value = f"{t['value']:.6g} {t['unit']}"
            lines.append(f"{'':<15} vs {t['name']:<20} {value:>14}  {dev:>7}  ({t['kind']}: {t['source']})")
        if not detail:
            if r.mode == "FAILED":
                lines += [f"{'':<15} note: {note}" for note in r.notes]
            continue
        if r.wavelength_m is not None:
            lines.append(f"{'':<15} wavelength along x {1e3 * r.wavelength_m:.2f} mm")
        if r.fidelity_note:
            lines.append(f"{'':<15} {r.fidelity_note}")
        if r.estimate_method:
            lines.append(f"{'':<15} error estimate: {r.estimate_method}")
        for note in r.notes:
            lines.append(f"{'':<15} note: {note}")
        if r is rows[-1] or rows[rows.index(r) + 1].scene != r.scene:
            for a in r.assumptions:
                lines.append(f"{'':<15} assumption: {a}")
    if not detail:
        lines.append("how each row was resolved, notes and assumptions: modalfe report -v (and --json)")
    return "\n".join(lines)
