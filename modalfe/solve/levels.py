"""The one solve path of every fidelity: build the scene's model (``modalfe.models.build``), constrain it for the
circuit, solve the eigen problem near the target and label each mode from its shape."""

from __future__ import annotations

import numpy as np

from modalfe.models.build import build_model
from modalfe.results.labels import unique_labels
from modalfe.results.modes import Mode, Modes
from modalfe.solve.eigen import eigenpairs


def solve_level(scene, analysis, *, fidelity: str = "solid", size_factor: float = 1.0, solver: str = "auto",
                frame=None, min_layers: int | None = None) -> Modes:
    """Modes of ``scene`` for ``analysis`` (near/count or band, circuit) at ``fidelity`` on one mesh level
    (element sizes x ``size_factor``): mass-normalised full DOF shapes, labelled, no error estimate."""
    model, timings = build_model(scene, fidelity, size_factor=size_factor, frame=frame, min_layers=min_layers)
    return modes_of(model, analysis, fidelity=fidelity, solver=solver, timings=timings)


def modes_of(model, analysis, *, fidelity: str, solver: str = "auto", timings: dict | None = None) -> Modes:
    """Modes of an assembled ``model`` (solid, plate or beam) for ``analysis``."""
    T = model.constraints(analysis.circuit).T
    A = (T.T @ model.K @ T).tocsr()
    B = (T.T @ model.M @ T).tocsr()
    solution = eigenpairs(A, B, analysis, solver)
    shapes = T @ solution.vectors
    frequencies = [float(np.sqrt(max(lam, 0.0)) / (2 * np.pi)) for lam in solution.values]
    names = unique_labels(model, shapes, frequencies)  # unique in the solve; degenerate pairs in their clearest basis
    modes = [Mode(i, f, name, shapes[:, i], model, analysis.circuit, wavelength=w)
             for i, (f, (name, w)) in enumerate(zip(frequencies, names))]
    seconds = {**(timings or {}), "factorization": solution.factorization_seconds,
               "eigensolve": solution.eigensolve_seconds, "solver": solution.solver}
    return Modes(tuple(modes), model, analysis.circuit, fidelity, A.shape[0], seconds,
                 mesh_frequency=model.scene.max_frequency)
