"""The axisymmetric rung: the modes of a body of revolution from its meridian section (``modalfe.models.axisymmetric``),
harmonics n = 0..``mesh.harmonics`` in one solve, refined until the stated error of the modes asked about meets ``tol``.

Error estimate by the order (p-refinement on one grid): the answer is solved on elements of order p = max(mesh.order,
3) and again at p - 1; a mode's stated error is |f_p - f_(p-1)| / f_p, its partner the mode of the same harmonic and
label at p - 1 (else the nearest of that harmonic). That bounds the error of f_p wherever the order converges at
least halving the error per order (e_p <= e_(p-1) / 2, so e_p <= e_(p-1) - e_p = |f_p - f_(p-1)| when both lie on one
side): so on one part (a disc, a ring: no singular point), where tests/models/test_axisymmetric.py and
studies/axisymmetric_verification.py measure it covering by 40x or more. Bonded parts (a stack: ``singular_field``) have
singular edges where parts end on one another, and there neither the order nor the grid converges asymptotically on
the grids used: measured on the disc stack (tests/oracles/cases.py ``stack_scene``, order 3, grids x1 to x1/7.6,
against order 4 on x1/17), the order step alone stated 7.0e-5 against 8.6e-5 on its n = 2 mode, the grid step at the
least order of a singular field (``MIN_ORDER``: 2 |f_h - f_1.5h|) 6.6e-5. There the stated error is their sum (the
grid's partner the previous refinement step, or one 1.5x coarser), which covered every mode of the stack on every
grid (by 1.3-5x, the reference's own uncertainty added: studies/axisymmetric_verification.py --stack). Where the
checked modes' stated error exceeds ``tol``, elements 1.5x smaller, at most ``MAX_STEPS`` times. No model error: the
model is exact for a body of revolution up to the harmonics solved (a mode of a harmonic above ``mesh.harmonics`` is
missing, not wrong).

Harmonics: ``mesh.harmonics`` where the scene sets it; else (None) as many as the answer reaches: from
``FIRST_HARMONICS``, doubled (up to ``MAX_HARMONIC``) while the top harmonic holds a mode of the question's window on
the scene's own mesh (one unrefined solve each), so that the harmonics above it hold none there. This takes the
lowest mode of each harmonic to rise with n, as a disc's flexural (n, 0) and in-plane families do (the 20 x 1 mm
PZT-5A disc's window round R1 holds (8,0) at 102 kHz: 4 -> 8 -> 16); a window high in the spectrum can hold a
harmonic past one that holds no mode there, which this rule does not see: where the top harmonic has a mode below
the window's top (``modes_below``, a Sturm count of its block alone), the note says the answer may miss modes of
higher harmonics (a 40 x 1 mm PZT-5A disc round R1: n = 0..8 solved, (10,0) at 42.4 kHz and an n = 11 mode at 50.4
kHz, 0.7 kHz from R1, missing). A harmonic costs about its share of the
DOFs (the disc at n = 0..16: 6,436 DOFs, 0.9 s; the disc stack of tests/oracles/cases.py near 192 kHz at tol 2e-4,
whose window holds (4,0): n = 0..8, 87,097 DOFs, 48 s against 16 s at n = 0..4)."""

from __future__ import annotations

import math
import time
from dataclasses import replace

from modalfe.errors import SceneError
from modalfe.models.axisymmetric import FIRST_HARMONICS
from modalfe.results.modes import Modes
from modalfe.scene.scene import MAX_HARMONIC
from modalfe.solve.checked import NOT_ESTIMATED, percent, worst_checked
from modalfe.solve.eigen import sturm_count
from modalfe.solve.estimates import MIN_ORDER, singular_field
from modalfe.solve.levels import solve_level

MAX_STEPS = 6  # at most 1.5^6 = 11x smaller elements than the scene's (the meridian mesh: ~130x the DOFs)
REFINE = 1.5  # element size ratio of one refinement step, as the solid's levels (``modalfe.solve.estimates``)
TOP_ORDER = 4  # highest element order the model offers (``modalfe.models.axisymmetric.ORDERS``)


def solve_axisymmetric(scene, analysis, *, tol: float, check, size_factor: float = 1.0, solver: str = "auto",
                       error_estimate: bool = True) -> Modes:
    """Modes of ``scene`` (a body of revolution: ``modalfe.models.axisymmetric.meridian_section``) for ``analysis``,
    each n >= 1 mode standing for a degenerate pair of the 3-D body, stated errors by the order (module docstring),
    refined until the ``check``ed modes meet ``tol``, over the scene's ``mesh.harmonics`` or as many as the answer
    reaches (module docstring). Without ``error_estimate``: the scene's own mesh at its order, errors NaN."""
    if scene.mesh.harmonics is not None:
        return _solve_harmonics(scene, analysis, tol=tol, check=check, size_factor=size_factor, solver=solver,
                                error_estimate=error_estimate)
    top = FIRST_HARMONICS
    while top < MAX_HARMONIC:  # probed on the scene's own mesh and order, unlabelled: the refined solve once
        probe = solve_level(replace(scene, mesh=replace(scene.mesh, harmonics=top, order=max(scene.mesh.order, 2))),
                            analysis, fidelity="axisymmetric", size_factor=size_factor, solver=solver, labels=False)
        if all(probe.model.harmonic_of(m.shape) < top for m in probe):
            break
        top = min(2 * top, MAX_HARMONIC)
    modes = _solve_harmonics(replace(scene, mesh=replace(scene.mesh, harmonics=top)), analysis, tol=tol,
                             check=check, size_factor=size_factor, solver=solver, error_estimate=error_estimate)
    window_top = analysis.band[1] if analysis.band is not None else max(m.frequency for m in modes)
    below = modes_below(scene, top, window_top, circuit=analysis.circuit, size_factor=size_factor, solver=solver)
    if not below:
        return modes
    return replace(modes, fidelity_note=(
        f"{modes.fidelity_note}; harmonics above n = {top} (not solved) may hold modes of the window: n = {top} "
        f"has {below} mode(s) below the window's top ({window_top:.6g} Hz) although none in it, so higher "
        f"harmonics' lowest modes may lie in it (missing here): set mesh.harmonics higher to solve them"))


def modes_below(scene, harmonic: int, frequency: float, *, circuit: str, size_factor: float = 1.0,
                solver: str = "auto") -> int:
    """How many modes harmonic ``harmonic`` alone has below ``frequency`` [Hz], on ``scene``'s own mesh (order 2 at
    least): the Sturm count of its block (``modalfe.solve.eigen.sturm_count``), one harmonic's DOFs. A free 40 x 1
    mm PZT-5A disc's window round R1 (43-54 kHz) holds none of n = 8, yet n = 8 to 11 each have a mode below 54 kHz,
    and (10,0) lies at 42.4 kHz, n = 11's at 50.4 kHz: missing from n = 0..8."""
    from modalfe.models.axisymmetric import assemble_axisymmetric

    model = assemble_axisymmetric(replace(scene, mesh=replace(scene.mesh, order=max(scene.mesh.order, 2))),
                                  harmonics=(harmonic,), size_factor=size_factor)
    constraints = model.constraints(circuit)
    return sturm_count(constraints.project(model.K), constraints.project(model.M), (2 * math.pi * frequency) ** 2,
                       solver=solver)


def _solve_harmonics(scene, analysis, *, tol: float, check, size_factor: float, solver: str,
                     error_estimate: bool) -> Modes:
    """``solve_axisymmetric`` over the scene's own ``mesh.harmonics``."""
    if not error_estimate:
        if scene.mesh.order == 1:
            raise SceneError("mesh.order: the axisymmetric model takes orders 2 to 4, got 1")
        return replace(solve_level(scene, analysis, fidelity="axisymmetric", size_factor=size_factor, solver=solver),
                       estimate_method=NOT_ESTIMATED)
    p = min(max(scene.mesh.order, 3), TOP_ORDER)
    fine_scene = replace(scene, mesh=replace(scene.mesh, order=p))
    coarse_scene = replace(scene, mesh=replace(scene.mesh, order=p - 1))
    singular = singular_field(scene)
    start = time.perf_counter()
    grid = solve_level(fine_scene, analysis, fidelity="axisymmetric", size_factor=size_factor * REFINE,
                       solver=solver) if singular else None
    for step in range(MAX_STEPS + 1):
        factor = size_factor / REFINE**step
        fine = solve_level(fine_scene, analysis, fidelity="axisymmetric", size_factor=factor, solver=solver)
        t = time.perf_counter()
        coarse = solve_level(coarse_scene, analysis, fidelity="axisymmetric", size_factor=factor, solver=solver)
        errors = partner_steps(fine, coarse)
        if singular:  # plus the grid's step at the least order of a singular field (module docstring)
            steps = partner_steps(fine, grid)
            errors = {i: e + steps[i] / (REFINE**MIN_ORDER - 1) for i, e in errors.items()}
            grid = fine
        modes = fine.with_error_estimates(errors)
        worst, why = worst_checked(modes, check)
        if worst <= tol or step == MAX_STEPS:
            break
    met = f"{why} <= tol {percent(tol)}" if worst <= tol else f"{why} > tol {percent(tol)} after {MAX_STEPS} steps"
    note = (f"axisymmetric model, harmonics n = 0..{scene.mesh.harmonics} (each n >= 1 mode one of a degenerate "
            f"pair), element size x{factor:.3g}: {met}")
    method = f"p-refinement: order {p} against order {p - 1} on the same grid"
    if singular:
        method += f", plus the grid's step (x{REFINE:g}) at order {MIN_ORDER:g} ({singular}: a singular field)"
    timings = dict(fine.timings, error_estimate=time.perf_counter() - t, total=time.perf_counter() - start)
    return replace(modes, fidelity_note=note, estimate_method=method, timings=timings)


def partner_steps(fine: Modes, other: Modes) -> dict[int, float]:
    """Mode index of ``fine`` -> |f - f_partner| / f against its partner in ``other`` (the same model at another order
    or grid): the mode of the same harmonic and label, else the nearest in frequency of that harmonic (inf where
    ``other`` has none of that harmonic); none for a rigid-body mode (below 1e-6 of the highest frequency: its
    relative step is round-off over round-off, 1.5e6 on the buzzer disc's yaw), as the solid's Richardson."""
    harmonic_of = fine.model.harmonic_of
    other_of = other.model.harmonic_of
    rigid = fine.rigid_indices()
    steps = {}
    for mode in fine:
        if mode.index in rigid:
            continue
        n = harmonic_of(mode.shape)
        same = [m for m in other if other_of(m.shape) == n]
        pool = [m for m in same if m.label == mode.label] or same
        if not pool or mode.frequency <= 0:
            steps[mode.index] = math.inf
            continue
        partner = min(pool, key=lambda m: abs(m.frequency - mode.frequency))
        steps[mode.index] = abs(mode.frequency - partner.frequency) / mode.frequency
    return steps
