"""The one solve path of every fidelity: build the scene's model (``modalfe.models.build``), constrain it for the
circuit, solve the eigen problem near the target and label each mode from its shape."""

from __future__ import annotations

import time
import weakref
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

import modalfe.caches as caches
from modalfe.models.build import Level, build_model
from modalfe.models.constraints import free_values
from modalfe.progress import step
from modalfe.results.labels import unique_labels
from modalfe.results.modes import Mode, Modes
from modalfe.solve.eigen import EigenSolution, eigenpairs
from modalfe.solve.linalg import single_threaded_blas
from modalfe.solve.open_circuit import bordered_ritz, open_circuit_solve, open_circuit_start

UNLABELLED = "unlabelled"  # the label of every mode of a level solved without labels (``solve_level``)
_KEPT_FACTORS = 3  # short-circuit solves kept for an open-circuit solve of the same model


@dataclass
class _ShortSolve:
    """A short-circuit solve of a driven model kept for its open circuit (``modes_of``) and its forced response: the
    factorization (solve, shift) of A - shift B, and the projected pencil (A, B), whose blocks the open circuit
    borders with its floating potentials, once asked for (``projected``). The model is held weakly: the entry lives
    no longer than the model in ``modalfe.models.build``'s cache."""

    model: weakref.ref
    factor: tuple
    pencil: tuple[sp.csr_matrix, sp.csr_matrix] | None = None

    def projected(self) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """(A, B): T^T K T and T^T M T of the short circuit, projected on the first call and kept from then on. A
        solve does not keep them: a factorization costs seconds to make again, a projection a fraction of one, while
        the pair with its triangle (``modalfe.solve.linalg.Shifted``) holds ~40 % of the model's memory (400 MB of
        the Cu-Be plate's quartic round-feet model), which the estimate levels solved next would sit on."""
        if self.pencil is None:
            self.pencil = _short_projection(self.model())
        return self.pencil


def _short_projection(model) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """(T^T K T, T^T M T) of ``model``'s short circuit."""
    constraints = model.constraints("short")
    return constraints.project(model.K), constraints.project(model.M)


_SHORT_SOLVES: list[_ShortSolve] = []  # newest first
caches.register("short-circuit factorizations", _SHORT_SOLVES.clear)
# (model held weakly, eigen shift [rad^2/s^2]) of answers read back from the resolved answers (``remember_shift``)
_SHIFTS: list[tuple[weakref.ref, float]] = []
caches.register("shifts of answers read back", _SHIFTS.clear)


def remember_shift(model, near: float) -> None:
    """``model``, read back from the resolved answers, was solved in short circuit near ``near`` [Hz]: where a
    factorization of it is asked for (``short_circuit_pencil``), it is made at that shift, once, as the solve would
    have kept it (a ``table`` after ``modes``: 60 s against 6.4 s solved afresh on the Cu-Be plate, each mode's open
    circuit and beside-resonance solve factorizing anew)."""
    _SHIFTS[:] = [(ref, shift) for ref, shift in _SHIFTS if ref() is not None and ref() is not model]
    _SHIFTS.append((weakref.ref(model), (2 * np.pi * near) ** 2))


def solve_level(scene, analysis, *, fidelity: str = "solid", size_factor: float = 1.0, solver: str = "auto",
                frame=None, min_layers: int | None = None, labels: bool = True) -> Modes:
    """Modes of ``scene`` for ``analysis`` (near/count or band, circuit) at ``fidelity`` on one mesh level
    (element sizes x ``size_factor``): mass-normalised full DOF shapes, labelled (``labels=False``: an estimate
    level whose labels nobody reads, ``UNLABELLED``), no error estimate."""
    with step(f"{scene.name}, {fidelity} model, order {scene.mesh.order}, element sizes x{size_factor:g}: mesh and "
              f"assembly"):
        model, timings = build_model(scene, fidelity, size_factor=size_factor, frame=frame, min_layers=min_layers)
    modes = modes_of(model, analysis, fidelity=fidelity, solver=solver, timings=timings, labels=labels)
    return modes if frame is not None else replace(modes, level=Level(fidelity, scene.mesh, size_factor, min_layers))


def modes_of(model, analysis, *, fidelity: str, solver: str = "auto", timings: dict | None = None,
             labels: bool = True, known: Modes | tuple[Mode, ...] | None = None, partners: bool = False) -> Modes:
    """Modes of an assembled ``model`` (solid, plate or beam) for ``analysis``. An open-circuit solve of a model solved
    in short circuit borders that solve's matrices (``Constraints.project``) and, at its shift, reuses its
    factorization (``open_circuit_solve``). ``known``: short-circuit modes of ``model`` solved near a frequency (an
    answer), whose factorization was kept: a short-circuit band keeps those in it and seeks only the others at their
    shift (``modalfe.solve.eigen.band_eigenpairs``); the open circuit at their shift starts Lanczos from them, or
    (``partners``: only the open modes that can be the partners of ``known`` are wanted, those the floating
    electrodes couple and ``known`` themselves) is projected on them and a few solves
    (``modalfe.solve.open_circuit.bordered_ritz``)."""
    _SHORT_SOLVES[:] = [kept for kept in _SHORT_SOLVES if kept.model() is not None]
    constraints = model.constraints(analysis.circuit)
    short = [kept for kept in _SHORT_SOLVES if kept.model() is model]  # this model's kept short-circuit solves
    # a kept factorization at this shift: bordered for the open circuit, as is for the short
    kept = next((k for k in short if k.factor[1] == (2 * np.pi * analysis.near) ** 2), None) \
        if analysis.band is None else None
    border = constraints.border(model.K) if analysis.circuit == "open" and kept is not None else None
    solution = None
    if partners and known is not None and border is not None and border[0].shape[1]:
        solution = _partners_from_short(model, constraints, border, kept, known, analysis.count)
    if solution is None:
        solution = _solved(model, analysis, constraints, short, kept, border, known, fidelity, solver)
    n_free = constraints.T.shape[1]
    driven = "drive" in model.scene.electrodes.values()  # else the open circuit is the short one: nothing to reuse
    if analysis.circuit == "short" and driven and solution.factor is not None:
        _SHORT_SOLVES.insert(0, _ShortSolve(weakref.ref(model), solution.factor))
        del _SHORT_SOLVES[_KEPT_FACTORS:]
    T = constraints.T
    shapes = T @ solution.vectors
    frequencies = [float(np.sqrt(max(lam, 0.0)) / (2 * np.pi)) for lam in solution.values]
    # unique in the solve; degenerate pairs in their clearest basis; modes carried by attached masses yield
    names = (unique_labels(model, shapes, frequencies, model.attached_share(shapes)) if labels
             else [(UNLABELLED, float("nan"))] * len(frequencies))
    modes = [Mode(i, f, name, shapes[:, i], model, analysis.circuit, wavelength=w)
             for i, (f, (name, w)) in enumerate(zip(frequencies, names))]
    seconds = {**(timings or {}), "factorization": solution.factorization_seconds,
               "eigensolve": solution.eigensolve_seconds, "solver": solution.solver}
    return Modes(tuple(modes), model, analysis.circuit, fidelity, n_free, seconds,
                 mesh_frequency=model.scene.max_frequency)


def _partners_from_short(model, constraints, border: tuple, kept: _ShortSolve, known,
                         count: int) -> EigenSolution | None:
    """The ``count`` open-circuit modes (unknowns ``constraints``, the short circuit's first) nearest the kept short
    solve's shift that can be partners of the short modes ``known`` (``modalfe.solve.open_circuit.bordered_ritz``:
    projected on them and a few solves with the kept factorization), None where that does not settle."""
    started = time.perf_counter()
    A, B = kept.projected()
    short_modes = free_values(constraints.T, np.column_stack([m.shape for m in known]))[: A.shape[0]]
    with step(f"{model.scene.name}: open circuit from the short one, {A.shape[0]} unknowns"), \
            single_threaded_blas():
        ritz = bordered_ritz(*border, A, B, kept.factor, short_modes, count)
    return None if ritz is None else EigenSolution(*ritz, 0.0, time.perf_counter() - started, "reused")


def _solved(model, analysis, constraints, short: list, kept, border, known, fidelity: str,
            solver: str) -> EigenSolution:
    """The eigen solve of ``model`` for ``analysis`` (``modalfe.solve.eigen.eigenpairs``) on its projected pencil
    (the short circuit's projection, bordered for the open circuit: ``Constraints.project``) with the
    factorization ``kept`` at its shift (bordered by ``border`` for the open circuit, ``open_circuit_solve``), a
    short band seeded and an open circuit started from the short modes ``known``."""
    if analysis.circuit == "short" and short:  # the same projection again, whose shifts share one pencil (``Shifted``)
        A, B = short[0].projected()
    else:  # an open circuit borders the short one's projection where it is held (else projecting it would be a
        # second projection of the model's size)
        picked = short[0].pencil if short else None
        A = constraints.project(model.K, picked=None if picked is None else picked[0])
        B = constraints.project(model.M, picked=None if picked is None else picked[1])
    factor, start, seed = None, None, None
    if kept is not None:
        factor = kept.factor if border is None else open_circuit_solve(*border, kept.factor)
    if factor is not None and known is not None and analysis.circuit == "open":
        start = open_circuit_start(constraints.T, known, factor[0], border[0].shape[1])
    if known is not None and analysis.band is not None and analysis.circuit == "short" and short:
        seed = (short[0].factor, np.array([m.omega**2 for m in known]),
                free_values(constraints.T, np.column_stack([m.shape for m in known])))
    asked = f"{analysis.band[0]:g}-{analysis.band[1]:g} Hz" if analysis.band is not None else \
        f"{analysis.count} modes near {analysis.near or 0:g} Hz"
    # ARPACK's dense products under one BLAS thread, whoever calls (``single_threaded_blas``: the admittance's band
    # completion ran beside PARDISO's threads at 3x the time a Lanczos step)
    with step(f"{model.scene.name}, {fidelity} model, order {model.scene.mesh.order}: eigen solve, {asked}, "
              f"{analysis.circuit} circuit, {A.shape[0]} unknowns"), single_threaded_blas():
        return eigenpairs(A, B, analysis, solver, factor, seed, start)


def short_circuit_pencil(model, *, factorized: bool = False) -> tuple[sp.csr_matrix, sp.csr_matrix, tuple | None]:
    """(A, B, factor): the short-circuit pencil T^T K T, T^T M T of ``model`` and the factorization (solve, shift)
    of A - shift B its eigen solve kept (``_ShortSolve``); projected afresh, factor None, where none is kept (a
    model read back from the resolved answers, or one without a driven electrode). ``factorized``: a model read back
    gets its factorization at the shift it was solved at (``remember_shift``), kept as its solve's would be."""
    kept = next((k for k in _SHORT_SOLVES if k.model() is model), None)
    if kept is not None:
        return (*kept.projected(), kept.factor)
    A, B = _short_projection(model)
    shift = next((shift for ref, shift in _SHIFTS if ref() is model), None) if factorized else None
    if shift is None:
        return A, B, None
    from modalfe.errors import SolverError
    from modalfe.solve.linalg import Shifted, factorize

    try:
        factor = (factorize(Shifted(A, B, shift))[0], shift)
    except SolverError:  # the shift on an eigenvalue: the callers factorize where they solve
        return A, B, None
    _SHORT_SOLVES.insert(0, _ShortSolve(weakref.ref(model), factor, (A, B)))
    del _SHORT_SOLVES[_KEPT_FACTORS:]
    return A, B, factor
