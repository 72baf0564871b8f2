"""Results: frozen Mode objects in a Modes container, with units in the field docstrings."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from modalfe.errors import SolverError


@dataclass(frozen=True, eq=False)
class Mode:
    """One eigenmode.

    frequency : [Hz]
    label : shape label, e.g. ``(0,6)``, ``bending-z 6``, ``heave``
    shape : full DOF vector (u then phi), mass-normalised (u^T M u = 1 [kg])
    error_estimate : estimated relative discretization error of ``frequency`` (NaN if not estimated)
    wavelength : bending wavelength along the long axis [m] for plate modes, else NaN
    """

    index: int
    frequency: float
    label: str
    shape: np.ndarray
    error_estimate: float = float("nan")
    wavelength: float = float("nan")

    @property
    def omega(self) -> float:
        """Angular frequency [rad/s]."""
        return 2 * np.pi * self.frequency


@dataclass(frozen=True, eq=False)
class Modes:
    """Modes of one scene, sorted by frequency, with the model that produced them.

    circuit : ``short`` or ``open``; fidelity : ``solid``; dofs : free unknowns solved for;
    timings : seconds per stage (mesh, assembly, factorization, eigensolve, error_estimate)
    """

    modes: tuple[Mode, ...]
    model: object
    circuit: str
    fidelity: str
    dofs: int
    timings: dict[str, float] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.modes)

    def __iter__(self):
        return iter(self.modes)

    def __getitem__(self, i: int) -> Mode:
        return self.modes[i]

    @property
    def frequencies(self) -> np.ndarray:
        return np.array([m.frequency for m in self.modes])

    def labelled(self, label: str, near: float | None = None) -> Mode:
        """The mode with this label (nearest ``near`` [Hz] if several); SolverError if none."""
        found = [m for m in self.modes if m.label == label]
        if not found:
            raise SolverError(
                f"no mode labelled '{label}' among {[m.label for m in self.modes]}; widen the search"
            )
        if near is None:
            return found[0]
        return min(found, key=lambda m: abs(m.frequency - near))

    def nearest(self, frequency: float) -> Mode:
        return min(self.modes, key=lambda m: abs(m.frequency - frequency))

    def with_error_estimates(self, estimates: dict[int, float]) -> Modes:
        modes = tuple(replace(m, error_estimate=estimates.get(m.index, m.error_estimate)) for m in self.modes)
        return replace(self, modes=modes)
