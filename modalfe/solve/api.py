"""``solve_modes``: the modes of a scene at the fidelity asked for, with their error estimates."""

from __future__ import annotations

import logging
import math
import numbers
import os
import weakref
from dataclasses import replace

import numpy as np

import modalfe.caches as caches
from modalfe.errors import SceneError, SolverError
from modalfe.models.estimate import machine_memory
from modalfe.results.labels import base_label
from modalfe.results.modes import Mode, Modes
from modalfe.scene.scene import Analysis, Scene
from modalfe.solve import resolved
from modalfe.solve.axisymmetric import solve_axisymmetric
from modalfe.solve.estimates import LINE_SUPPORT_CAVEAT
from modalfe.solve.fidelity import solve_at_fidelity
from modalfe.solve.linalg import single_threaded_blas

log = logging.getLogger(__name__)

FIDELITIES = ("auto", "beam", "plate", "axisymmetric", "solid")
# the relative frequency error every command and ``solve_modes`` answer at unless told otherwise, one default for all
# (issue 34): 0.5 %, a fraction of the 1-32 % by which the seed devices' working modes differ from the seeds'
# measured, analytic and FE targets, so that a deviation is the model's and not the mesh's
DEFAULT_TOL = 0.005
# most modes one near/count solve is asked for, checked before any meshing: ARPACK keeps 2 count + 1 vectors
# of every unknown (10,000 modes of a 100k-unknown model: 16 GB); a band is solved in windows instead
MAX_COUNT = 1000
OWN_MESH = math.inf  # the ``tol`` that refines nothing: the scene's own mesh (the cheapest fidelity) with its estimate
Check = tuple[tuple[str | None, float], ...]
# a shift above this multiple of the frequency the mesh resolves (``Scene.max_frequency``) is refused: there the
# shear wavelength spans under 0.6 of the 6 elements per wavelength the mesh is sized for, so the modes found are the
# mesh's (cube_plate near 1e12 Hz answered 19-23 MHz "in-plane" modes on a mesh resolving 50 kHz), and refinement
# within its few steps cannot reach them; up to it the error estimates say how far a mode is resolved
FAR_ABOVE_MESH = 10.0
# the reduced models whose modes the mode table and the admittance take as the solid's: the axisymmetric model's
# electrodes are equipotential faces as in 3-D, driven through n = 0 only (n >= 1 modes carry no charge), its modal
# masses the whole body's and its open circuit the 3-D one (``modalfe.models.axisymmetric``), so fa, k_eff and the
# modal sum hold alike; auto's axisymmetric answer is then the one ``modes`` gives
REVOLVED = ("axisymmetric",)
NEAREST = None  # the selector of a check entry (selector, near) that means the mode nearest ``near``


def solve_modes(
    scene: Scene | str,
    *,
    near: float | None = None,
    count: int | None = None,
    band: tuple[float, float] | None = None,
    circuit: str | None = None,
    mode: str | None = None,
    error_estimate: bool = True,
    size_factor: float = 1.0,
    solver: str = "auto",
    frame=None,
    fidelity: str = "auto",
    tol: float = DEFAULT_TOL,
    check: Check | None = None,
    harmonics: int | None = None,
) -> Modes:
    """Modes of ``scene`` (a ``Scene``, or a built-in name or TOML file for ``load_scene``): ``count`` nearest
    ``near`` [Hz], or all in ``band`` [Hz], answered on a discretization whose stated error of the modes asked about
    meets ``tol``. Defaults come from ``scene.analysis``; ``count`` < 1 and ``near`` with ``band`` are refused.

    The modes asked about (``asked_modes``) drive the refinement: ``check`` as (selector, near Hz) pairs, else the
    scene's working modes in the question, else ``mode`` (a label), else the mode nearest ``near`` (a band: all its
    modes); the others keep their own stated error. The same scene, question and tolerance give the same answer in
    every command: it is kept (``modalfe.solve.resolved``) and read back instead of solved again.
    ``fidelity``: ``auto`` (the cheapest of beam, plate, axisymmetric and solid that meets ``tol``,
    ``modalfe.solve.fidelity``), ``solid`` (the 3-D solid refined to ``tol``), ``beam`` or ``plate`` (reduced models
    on their own mesh, stated error discretization plus model error). ``error_estimate=False``: the scene's own mesh
    solved once (``auto``: the solid), its error unknown (NaN), for the expert who sets the mesh; ``tol=OWN_MESH``
    (inf): that mesh with its stated error, never refined. ``size_factor`` scales the element sizes.
    ``frame`` (3, 3) rotates the whole device (mesh and materials), for invariance checks.
    ``fidelity="axisymmetric"``: a body of revolution (cylinders and rings on one axis) on its meridian plane,
    circumferential harmonics n = 0..``harmonics`` (default the scene's ``mesh.harmonics``, else as many as the
    answer reaches), refined by the order and the grid to ``tol`` (``modalfe.solve.axisymmetric``); ``auto`` tries it
    on a scene of round parts, its model error checked against the 3-D solid like the plate's.
    The mesh resolves the scene's frequency range (``Scene.max_frequency``: ``mesh.max_frequency`` or the
    scene's own analysis, widened to a ``band`` asked here); ``near`` only places the shift, so modes far
    above that range carry the large error estimates of an under-resolved mesh.
    """
    scene = _scene(scene)
    if fidelity not in FIDELITIES:
        raise SolverError(f"fidelity: must be one of {FIDELITIES}, got '{fidelity}'")
    if harmonics is not None:
        if fidelity != "axisymmetric":
            raise SolverError(f"harmonics: only the axisymmetric fidelity solves harmonics, got fidelity '{fidelity}'")
        scene = replace(scene, mesh=replace(scene.mesh, harmonics=harmonics))
    if not (isinstance(tol, numbers.Real) and tol > 0):  # NaN fails too; inf: the scene's own mesh, estimated
        raise SolverError(f"tol: must be a positive relative error, got {tol}")
    if not (isinstance(size_factor, numbers.Real) and math.isfinite(size_factor) and size_factor > 0):
        raise SolverError(f"size_factor: must be a positive finite factor on the element sizes, got {size_factor!r}")
    if frame is not None:
        _check_rotation(frame)
    if near is not None and band is not None:
        raise SolverError("near: give near (and count) or band, not both")
    if count is not None and (isinstance(count, bool) or not isinstance(count, numbers.Integral) or count < 1):
        raise SolverError(f"count: must be a whole number of modes >= 1, got {count!r}")
    if count is not None and count > MAX_COUNT:
        raise SolverError(f"count: {count} modes asked, at most {MAX_COUNT} per solve; ask for a band instead "
                          f"(solved in windows)")
    a = scene.analysis
    if near is not None or band is not None:
        a = Analysis(near=near, count=a.count if count is None else count, band=band, circuit=circuit or a.circuit)
    else:
        a = Analysis(near=a.near, count=a.count if count is None else count, band=a.band, circuit=circuit or a.circuit)
    if a.band is None and a.near is None:
        raise SolverError("give near (and count) or band")
    if a.near is not None and a.near > FAR_ABOVE_MESH * scene.max_frequency:
        from modalfe.models.mesh import resolved_frequency

        resolves = resolved_frequency(scene)  # mesh.max_size may refine past mesh.max_frequency
        if a.near > FAR_ABOVE_MESH * resolves:
            raise SolverError(f"near: {a.near:.6g} Hz is {a.near / resolves:.3g} times the highest frequency the mesh "
                              f"resolves ({resolves:.6g} Hz; mesh.max_frequency, mesh.max_size): the modes found "
                              f"there would be the mesh's, not the device's; raise mesh.max_frequency to solve there")
    if a.band is not None and a.band[1] > scene.max_frequency:
        # a band is a frequency range the mesh must resolve; ``near`` is only the shift of the eigen solve
        scene = replace(scene, mesh=replace(scene.mesh, max_frequency=a.band[1]))
    if check is None:
        check = asked_modes(scene, a, mode)
    machine_memory()  # a bad $MODALFE_MAX_MEMORY is refused whether or not the answer is kept
    key = None
    if frame is None:
        key = resolved.answer_key(scene, a, fidelity=fidelity, tol=float(tol), check=check,
                                  error_estimate=bool(error_estimate), size_factor=float(size_factor))
        kept = resolved.lookup(key, scene)
        if kept is not None:
            if kept.circuit == "short" and a.band is None and a.near:
                from modalfe.solve.levels import remember_shift

                # the answer's model and its levels' (solved near the same shift, ``coarser``): their open circuits
                # and forced solves factorize there, once, as after a fresh solve
                plan = kept.estimate
                for modes in (kept, *kept.cross_check, *(plan.levels if plan is not None else ()),
                              *((plan.floor,) if plan is not None and plan.floor is not None else ())):
                    if modes.model is not None:
                        remember_shift(modes.model, a.near)
            return kept
    with single_threaded_blas():
        if fidelity == "axisymmetric":
            if frame is not None:
                raise SolverError("frame: rotating the device is supported at solid fidelity only")
            modes = solve_axisymmetric(scene, a, tol=tol, check=check, size_factor=size_factor, solver=solver,
                                       error_estimate=error_estimate)
        else:
            modes = with_support_caveats(scene, solve_at_fidelity(
                scene, a, fidelity=fidelity, tol=tol, check=check, size_factor=size_factor, solver=solver,
                error_estimate=error_estimate, frame=frame))
    if a.circuit == "open" and len(modes) and "drive" in scene.electrodes.values():
        # a mode keeps its label in both circuits (issue 35: a piezo cube's open circuit was labelled anew, its coupled
        # modes lifted past others): each open mode paired by shape with a mode of the short circuit's answer to the
        # same question on the same discretization takes that mode's label (``partner_labels``)
        from modalfe.results.coupling import partner_labels

        short = solve_modes(scene, near=a.near, count=a.count, band=a.band, circuit="short", mode=mode,
                            error_estimate=error_estimate, size_factor=size_factor, solver=solver, frame=frame,
                            fidelity=fidelity, tol=tol, check=check)
        modes = partner_labels(short, modes)
    if key is not None:
        resolved.store(key, modes)
    stages = ", ".join(f"{k} {v:.2f} s" for k, v in modes.timings.items() if isinstance(v, float))
    log.info("%s: %d modes, %d DOFs, %s fidelity (%s)", scene.name, len(modes), modes.dofs, modes.fidelity, stages)
    return modes


def with_support_caveats(scene: Scene, modes: Modes) -> Modes:
    """``modes`` whose fidelity note ends with what the scene's line supports mean on the 3-D solid that answered
    (``modalfe.solve.estimates.LINE_SUPPORT_CAVEAT``): the reduced models refuse them, so only the solid meets one."""
    if not scene.edges or modes.fidelity != "solid":
        return modes
    caveat = f"{LINE_SUPPORT_CAVEAT} ({', '.join(scene.edges)})"
    return replace(modes, fidelity_note="; ".join(n for n in (modes.fidelity_note, caveat) if n))


def asked_modes(scene: Scene, analysis: Analysis, mode: str | None = None) -> Check | None:
    """The modes a question asks about, as (selector, near Hz) pairs (None: every mode of a band): the scene's
    working modes sought at its frequency, or ``own_working_modes`` when it is the scene's own question (its
    analysis), so that every command asking the same question resolves the same modes; else ``mode`` near the
    question's frequency; else the mode nearest ``near`` (``NEAREST``), or every mode of a band."""
    own = analysis.near == scene.analysis.near and analysis.band == scene.analysis.band
    members = tuple((wm.selector, wm.near) for wm in scene.working_modes
                    if analysis.near is not None and math.isclose(wm.near, analysis.near, rel_tol=1e-9))
    if own:
        members = members or own_working_modes(scene)
    if members and (mode is None or any(mode == selector for selector, _ in members)):
        return members
    if analysis.band is not None:
        return None if mode is None else ((mode, 0.5 * (analysis.band[0] + analysis.band[1])),)
    return ((NEAREST if mode is None else mode), analysis.near),


# a scene's own window (its analysis.near) is about its working mode nearest that frequency when within this relative
# distance (the ciliary beam's analysis near 24 kHz, its bending-z 6 sought near 24.2 kHz); farther, about none
OWN_WINDOW = 0.1


def own_working_modes(scene: Scene) -> Check:
    """The working modes the scene's own question (its ``analysis``) asks about, as (selector, near Hz): those in
    its band, else those sought nearest its ``near`` (within ``OWN_WINDOW``)."""
    a = scene.analysis
    if a.band is not None:
        return tuple((wm.selector, wm.near) for wm in scene.working_modes if a.band[0] <= wm.near <= a.band[1])
    if a.near is None or not scene.working_modes:
        return ()
    nearest = min(abs(wm.near - a.near) for wm in scene.working_modes)
    return tuple((wm.selector, wm.near) for wm in scene.working_modes
                 if abs(wm.near - a.near) == nearest and nearest <= OWN_WINDOW * a.near)


def working_question(scene: Scene, selector: str | None = None, near: float | None = None) -> dict:
    """``solve_modes`` keywords that ask about the mode ``selector`` (default: the scene's first working mode)
    sought near ``near`` [Hz] (default: ``sought_near``): the scene's own question (its analysis) where that asks
    about the mode (``own_working_modes``), so that the answer is the one ``modes`` gives; else the window of
    ``analysis.count`` modes around the frequency; with ``mode`` set."""
    target = sought_near(scene, selector, near)
    selector = selector or scene.working_modes[0].selector
    a = scene.analysis
    if near is None and any(selector == s for s, _ in own_working_modes(scene)):
        return {"band": a.band, "mode": selector} if a.band is not None else \
            {"near": a.near, "count": a.count, "mode": selector}
    return {"near": target, "count": a.count, "mode": selector}


def seek(scene: Scene, selector: str | None = None, near: float | None = None) -> tuple[str | None, float | None]:
    """(selector, near [Hz]) of the mode a command looks for: ``selector``, default the first working mode's;
    ``near``, default the ``near`` of the working mode of that selector (its pattern: ``(1,1)#2`` is ``(1,1)``),
    else the first working mode's, else the analysis's (None when the scene has neither)."""
    first = scene.working_modes[0] if scene.working_modes else None
    selector = selector or (first.selector if first else None)
    if near is None:
        named = [wm for wm in scene.working_modes if selector and base_label(wm.selector) == base_label(selector)]
        near = (named[0] if named else first).near if (named or first) else scene.analysis.near
    return selector, near


def sought_near(scene: Scene, selector: str | None = None, near: float | None = None) -> float:
    """The frequency [Hz] the mode ``selector`` is sought near (``seek``); SolverError where the scene names no
    working mode and none is given."""
    _, target = seek(scene, selector, near)
    if target is None or (near is None and not scene.working_modes):
        raise SolverError("mode: the scene names no working mode; give the mode and the frequency it is sought near")
    return target


def solid_modes(scene: Scene, *, needs: str, fidelity: str = "auto", takes: tuple[str, ...] = (),
                **question) -> Modes:
    """``solve_modes(scene, fidelity=fidelity, **question)`` for ``needs`` (a phrase: what asks), which works on
    the 3-D solid and the reduced models ``takes``: where ``auto`` answered with another reduced model, the solid
    refined to the same tolerance answers instead (said in its note); another reduced ``fidelity`` asked is refused
    before any solve."""
    if fidelity not in ("auto", "solid", *takes):
        raise SolverError(f"fidelity: {needs} needs the 3-D solid model (fidelity 'solid'"
                          + "".join(f" or '{t}'" for t in takes) + f"), got '{fidelity}'")
    modes = solve_modes(scene, fidelity=fidelity, **question)
    if modes.fidelity in ("solid", *takes):
        return modes
    solid = solve_modes(scene, fidelity="solid", **question)
    return replace(solid, fidelity_note=f"{solid.fidelity_note}; {needs} needs the 3-D solid: auto's {modes.fidelity} "
                                        f"answer (within tol too) not used")


def _scene(scene) -> Scene:
    """``scene`` itself, or the scene a built-in name or a TOML file path names; SceneError otherwise."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        from modalfe.scene import load_scene

        return load_scene(scene)
    raise SceneError(f"scene: expected a Scene, a built-in scene name or a .toml file, got {type(scene).__name__}")


def _check_rotation(frame) -> None:
    """SolverError unless ``frame`` is a (3, 3) rotation (orthonormal, determinant +1)."""
    try:
        R = np.asarray(frame, dtype=float)
    except (TypeError, ValueError):
        R = np.full((1,), np.nan)
    if R.shape != (3, 3) or not np.all(np.isfinite(R)) or not np.allclose(R @ R.T, np.eye(3), atol=1e-9) \
            or not np.isclose(np.linalg.det(R), 1.0, atol=1e-9):
        raise SolverError("frame: must be a 3 x 3 rotation matrix (orthonormal, determinant +1)")


def open_circuit_modes(short: Modes | Mode, *, near: float | None = None, count: int | None = None,
                       band: tuple[float, float] | None = None, solver: str = "auto") -> Modes:
    """The open-circuit modes, ``count`` nearest ``near`` [Hz] or all in ``band``, of the very model that solved
    ``short`` (short-circuit modes, or one mode of the 3-D solid: its mesh, even where ``fidelity="auto"`` refined
    it past the scene's; at ``short``'s shift the factorization is reused,
    ``modalfe.solve.levels.open_circuit_solve``); an open mode paired by shape with one of ``short`` (Modes) takes its
    label (``modalfe.results.coupling.partner_labels``)."""
    from modalfe.results.coupling import partner_labels
    from modalfe.solve.levels import modes_of

    analysis = Analysis(band=band, circuit="open") if band is not None else \
        Analysis(near=near, count=count, circuit="open")
    with single_threaded_blas():
        opens = modes_of(short.model, analysis, fidelity=short.fidelity if isinstance(short, Modes) else "solid",
                         solver=solver, known=short if isinstance(short, Modes) else (short,))
    return partner_labels(short, opens) if isinstance(short, Modes) else opens


# (model held weakly, near, Modes unbound from it: ``_bound``): the partner search's last open solves, newest first
_OPEN_SOLVES: list[tuple] = []
_KEPT_OPEN = 4
caches.register("open-circuit partner solves", _OPEN_SOLVES.clear)


def _open_solve(model, near: float, count: int, solver: str, known) -> Modes:
    """The open-circuit modes of ``model``, at least ``count`` nearest ``near`` [Hz]: a kept solve at that shift with
    as many (the partners of a table's modes, sought one by one, from one solve) or a new one, kept: the open modes
    that can be partners of the short-circuit modes ``known`` of the same model, from them and a few solves
    (``modalfe.solve.levels.modes_of``'s ``partners``; an open mode the floating electrodes do not couple is a short
    mode unchanged, its own partner, and the others are not sought)."""
    from modalfe.solve.levels import modes_of

    _OPEN_SOLVES[:] = [kept for kept in _OPEN_SOLVES if kept[0]() is not None]
    for ref, at, opens in _OPEN_SOLVES:
        if ref() is model and at == near and len(opens) >= count:
            return _bound(opens, model)
    analysis = Analysis(near=near, count=count, circuit="open")
    with single_threaded_blas():
        # partners only, which keep the short modes' labels (``OpenCircuit``): their own are not needed
        opens = modes_of(model, analysis, fidelity="solid", solver=solver, known=known, partners=True, labels=False)
    _OPEN_SOLVES.insert(0, (weakref.ref(model), near, _bound(opens, None)))
    del _OPEN_SOLVES[_KEPT_OPEN:]
    return opens


def _bound(modes: Modes, model) -> Modes:
    """``modes`` bound to ``model``: kept unbound (None), so that a kept solve does not keep its model alive."""
    return replace(modes, model=model, modes=tuple(replace(m, model=model) for m in modes))


# most open-circuit modes sought for one partner where no short-circuit modes size the solve (``open_circuit_partner``)
PARTNER_COUNT = 16


def open_circuit_partner(mode, *, near: float, among: Modes | None = None, solver: str = "auto"):
    """The open-circuit mode of the short-circuit ``mode`` (its antiresonance, by shape:
    ``modalfe.results.coupling.antiresonance``), solved on its model near ``near`` [Hz] with as few modes as hold it:
    the open circuit raises each mode by its coupling, rarely past another mode, so the partner is among the open
    modes nearest the shift as many as the short modes of ``among`` at least as near as ``mode``, plus two (two
    without ``among``); where it is not, twice the modes, up to ``among``'s count (``PARTNER_COUNT`` without)."""
    from modalfe.results.coupling import antiresonance

    sigma = near**2
    most = max(len(among), 1) if among is not None else PARTNER_COUNT
    rank = sum(abs(m.frequency**2 - sigma) <= abs(mode.frequency**2 - sigma) for m in among) if among is not None \
        else 0
    count = min(rank + 2, most)
    while True:
        try:
            return antiresonance(mode, _open_solve(mode.model, near, count, solver,
                                                   among if among is not None else (mode,)))
        except SolverError:
            if count >= most:
                raise
            count = min(2 * count, most)


def derived_errors(modes: Modes, mode, values, fine: dict[str, float] | None = None,
                   eigenvalues: tuple[str, ...] = ()) -> dict[str, tuple[float, str]]:
    """{name: (stated relative error, "" or why not estimated)} of the numbers ``values(mode)`` derives from ``mode``
    of the answer ``modes`` (``fine``: those numbers when already computed): from the same levels and rule as the
    frequency's estimate (``modalfe.solve.estimates.EstimatePlan.derived_errors``; ``eigenvalues``: the names that are
    eigenvalues, estimated at the frequency's orders), NaN with the reason where the
    answer states no estimate (``--no-error-estimate``, a reduced model's answer)."""
    fine = values(mode) if fine is None else fine
    if modes.estimate is None:
        reason = f"not estimated ({modes.estimate_method or 'no estimate levels kept'})"
        if modes.fidelity == "axisymmetric":
            reason = ("not estimated (the axisymmetric answer keeps no estimate level for the numbers derived from a "
                      f"mode; its frequencies': {modes.estimate_method})")
        return {name: (math.nan, reason) for name in fine}
    with single_threaded_blas():
        return modes.estimate.derived_errors(mode, values, fine, eigenvalues)
