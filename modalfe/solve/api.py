"""``solve_modes``: the modes of a scene at the fidelity asked for, with their error estimates."""

from __future__ import annotations

import logging
import math
import numbers
from dataclasses import replace

from modalfe.errors import SolverError
from modalfe.results.modes import Modes
from modalfe.scene.scene import Analysis, Scene
from modalfe.solve.fidelity import solve_at_fidelity

log = logging.getLogger(__name__)

FIDELITIES = ("auto", "beam", "plate", "solid")
# relative frequency error asked of ``fidelity="auto"``: below the seeds' 2-7 % model-to-measurement gaps
DEFAULT_TOL = 0.02
# most modes one near/count solve is asked for, checked before any meshing: ARPACK keeps 2 count + 1 vectors
# of every unknown (10,000 modes of a 100k-unknown model: 16 GB); a band is solved in windows instead
MAX_COUNT = 1000


def solve_modes(
    scene: Scene,
    *,
    near: float | None = None,
    count: int | None = None,
    band: tuple[float, float] | None = None,
    circuit: str | None = None,
    error_estimate: bool = True,
    size_factor: float = 1.0,
    solver: str = "auto",
    frame=None,
    fidelity: str = "solid",
    tol: float = DEFAULT_TOL,
    check: tuple[tuple[str, float], ...] | None = None,
) -> Modes:
    """Modes of ``scene``: ``count`` nearest ``near`` [Hz], or all in ``band`` [Hz].

    Defaults come from ``scene.analysis``; ``count`` < 1 and ``near`` with ``band`` are refused. With
    ``error_estimate`` the scene is solved again on meshes 1.5x and 2.25x coarser (thickness layers too:
    3 -> 2 -> 1 by default) and each frequency gets a Richardson estimate of its relative error
    (``modalfe.solve.estimates.richardson``).
    ``fidelity``: ``solid`` (3-D), ``beam`` or ``plate`` (reduced models), or ``auto``: the cheapest
    whose estimated error meets ``tol`` on the modes ``check`` names as (selector, near Hz) pairs
    (all modes when None); see ``modalfe.solve.fidelity``.
    ``frame`` (3, 3) rotates the whole device (mesh and materials), for invariance checks.
    The mesh resolves the scene's frequency range (``Scene.max_frequency``: ``mesh.max_frequency`` or the
    scene's own analysis, widened to a ``band`` asked here); ``near`` only places the shift, so modes far
    above that range carry the large error estimates of an under-resolved mesh.
    """
    if fidelity not in FIDELITIES:
        raise SolverError(f"fidelity: must be one of {FIDELITIES}, got '{fidelity}'")
    if not (math.isfinite(tol) and tol > 0):
        raise SolverError(f"tol: must be a positive relative error, got {tol}")
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
    if a.band is not None and a.band[1] > scene.max_frequency:
        # a band is a frequency range the mesh must resolve; ``near`` is only the shift of the eigen solve
        scene = replace(scene, mesh=replace(scene.mesh, max_frequency=a.band[1]))
    with single_threaded_blas():
        modes = solve_at_fidelity(scene, a, fidelity=fidelity, tol=tol, check=check, size_factor=size_factor,
                                  solver=solver, error_estimate=error_estimate, frame=frame)
    stages = ", ".join(f"{k} {v:.2f} s" for k, v in modes.timings.items() if isinstance(v, float))
    log.info("%s: %d modes, %d DOFs, %s fidelity (%s)", scene.name, len(modes), modes.dofs, modes.fidelity, stages)
    return modes


def open_circuit_modes(short: Modes, *, near: float, count: int, solver: str = "auto") -> Modes:
    """The open-circuit modes, ``count`` nearest ``near`` [Hz], of the very model that solved ``short`` (its mesh,
    even where ``fidelity="auto"`` refined it past the scene's; at ``short``'s shift the factorization is reused,
    ``modalfe.solve.levels.open_circuit_solve``)."""
    from modalfe.solve.levels import modes_of

    with single_threaded_blas():
        return modes_of(short.model, Analysis(near=near, count=count, circuit="open"), fidelity=short.fidelity,
                        solver=solver)


def open_circuit_partner(short: Modes, mode, *, near: float, solver: str = "auto"):
    """The open-circuit mode of ``mode`` of ``short`` (its antiresonance, ``modalfe.results.coupling.antiresonance``),
    solved near ``near`` [Hz] with as few modes as hold it: the open circuit raises each mode by its coupling, rarely
    past another mode, so the partner is among the open modes nearest the shift as many as the short modes at
    least as near as ``mode``, plus two; where it is not, twice the modes, up to ``short``'s count."""
    from modalfe.results.coupling import antiresonance

    sigma = near**2
    rank = sum(abs(m.frequency**2 - sigma) <= abs(mode.frequency**2 - sigma) for m in short)
    count = min(rank + 2, max(len(short), 1))
    while True:
        try:
            return antiresonance(mode, open_circuit_modes(short, near=near, count=count, solver=solver))
        except SolverError:
            if count >= len(short):
                raise
            count = min(2 * count, len(short))


def single_threaded_blas():
    """Context with one BLAS thread. numpy's OpenBLAS threads spin while they wait; on a small machine shared
    with MKL PARDISO's threads and other processes, the small dense operations of a solve (the labels'
    interpolation) then ran up to 100x slower (measured: the Cu-Be plate's report row 6 s with one BLAS thread,
    30-40 s with two under load). The heavy work is sparse (PARDISO has its own threads), so this costs nothing."""
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")
