"""Results: frozen Mode objects in a Modes container, with units in the field docstrings."""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

import numpy as np

from modalfe.errors import SolverError
from modalfe.results.labels import base_label

RIGID_BELOW = 1e-6  # of a solve's highest frequency: a rigid-body mode's, round-off (``Modes.rigid_indices``)

_FAMILY = re.compile(r"^\((\d+|n),(\d+|n)\)$")


@dataclass(frozen=True, eq=False)
class Mode:
    """One eigenmode, bound to the assembled model (and so the scene and mesh) that produced it.

    frequency : [Hz]
    label : shape label, e.g. ``(0,6)``, ``bending-z 6``, ``heave``
    shape : full DOF vector of ``model`` (u then phi), mass-normalised (u^T M u = 1 [kg])
    model : the assembled solid, plate or beam model; circuit : ``short`` or ``open``
    error_estimate : estimated relative error of ``frequency`` (NaN if not estimated): discretization,
        plus the model error for a beam or plate model
    wavelength : bending wavelength along the long axis [m] for plate modes, else NaN
    model_error : estimated relative error of a beam or plate model against the 3-D solid (NaN for the
        solid itself, or when not cross-checked)
    """

    index: int
    frequency: float
    label: str
    shape: np.ndarray = field(repr=False)
    model: object = field(repr=False)
    circuit: str = "short"
    error_estimate: float = float("nan")
    wavelength: float = float("nan")
    model_error: float = float("nan")

    @property
    def omega(self) -> float:
        """Angular frequency [rad/s]."""
        return 2 * np.pi * self.frequency

    @property
    def scene(self):
        """The scene the mode was solved for."""
        return self.model.scene

    @property
    def modal_mass(self) -> float:
        """Generalised mass x^T M x [kg] of ``shape`` (1 for the mass-normalised shapes a solve returns)."""
        return float(self.shape @ (self.model.M @ self.shape))

    def displacement(self, points) -> np.ndarray:
        """Displacement (n, 3) [m per unit modal coordinate] at ``points`` (n, 3) [m] of the whole device."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        return np.asarray(self.model.displacement_probes(p) @ self.shape).reshape(3, -1).T

    def potential(self, points) -> np.ndarray:
        """Electric potential (n,) [V per unit modal coordinate] at ``points`` (n, 3) [m] (solid models)."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        return np.asarray(self.model.potential_probes(p) @ self.shape)


@dataclass(frozen=True, eq=False)
class Modes:
    """Modes of one scene, sorted by frequency, with the model that produced them.

    circuit : ``short`` or ``open``; fidelity : ``beam``, ``plate`` or ``solid``; dofs : free unknowns
    solved for; timings : seconds per stage (mesh, assembly, factorization, eigensolve, error_estimate,
    cross_check); fidelity_note : which fidelity answered and why (``auto``); cross_check : the 3-D solid
    levels (finer coarse level first) that a reduced model's model error was measured against, else empty;
    mesh_frequency : the highest frequency [Hz] the mesh resolves at the scene's elements per wavelength;
    estimate_method : how the error estimates were made (p- or h-refinement), empty when not estimated
    level : the discretization solved (``modalfe.models.build.Level``), None for a model built elsewhere
    estimate : how the solid's errors were estimated (``modalfe.solve.estimates.EstimatePlan``: its levels and rule,
        which numbers derived from a mode are estimated by too), None where no level estimates them
    """

    modes: tuple[Mode, ...]
    model: object
    circuit: str
    fidelity: str
    dofs: int
    timings: dict[str, float] = field(default_factory=dict)
    fidelity_note: str = ""
    cross_check: tuple[Modes, ...] = ()
    mesh_frequency: float = float("nan")
    estimate_method: str = ""
    level: object = None
    estimate: object = None

    def __len__(self) -> int:
        return len(self.modes)

    def __iter__(self):
        return iter(self.modes)

    def __getitem__(self, i: int) -> Mode:
        return self.modes[i]

    @property
    def frequencies(self) -> np.ndarray:
        return np.array([m.frequency for m in self.modes])

    @property
    def resolution(self) -> str:
        """One line on how these modes were resolved: DOFs, model, which fidelity answered and how the errors were
        estimated."""
        parts = [f"{self.dofs} DOFs, {self.fidelity} model", self.fidelity_note, self.estimate_method]
        return "; ".join(p for p in parts if p)

    def labelled(self, label: str, near: float | None = None) -> Mode:
        """The mode with this label (nearest ``near`` [Hz] if several); if none carries it exactly, a mode of its
        pattern with another ambiguity suffix (``(1,1)#2`` for ``(1,1)``: suffixes only tell modes of one solve
        apart, another solve may number them differently). SolverError if none."""
        found = [m for m in self.modes if m.label == label] or [
            m for m in self.modes if base_label(m.label) == base_label(label)]
        if not found:
            raise SolverError(
                f"no mode labelled '{label}' among {[m.label for m in self.modes]}; widen the search"
            )
        if near is None:
            return found[0]
        return min(found, key=lambda m: abs(m.frequency - near))

    def nearest(self, frequency: float) -> Mode:
        return min(self.modes, key=lambda m: abs(m.frequency - frequency))

    def rigid_indices(self) -> set[int]:
        """Indices of the rigid-body modes: below ``RIGID_BELOW`` of the highest frequency (a free body's, at
        round-off), which state no relative error."""
        top = max((m.frequency for m in self.modes), default=0.0)
        return {m.index for m in self.modes if m.frequency < RIGID_BELOW * top}

    def with_error_estimates(self, estimates: dict[int, float]) -> Modes:
        modes = tuple(replace(m, error_estimate=estimates.get(m.index, m.error_estimate)) for m in self.modes)
        return replace(self, modes=modes)


def select(modes, selector: str, near: float):
    """The mode matching ``selector`` nearest ``near`` [Hz]: an exact label, or a plate family
    where ``n`` stands for any count, e.g. ``(0,n)``: the family's plain labels first, then ambiguity-suffixed
    ones (``(0,3)#2``)."""
    m = _FAMILY.match(selector)
    if m and "n" in selector:
        a, b = m.groups()

        def fits(label: str) -> bool:
            g = _FAMILY.match(base_label(label))
            return bool(g) and all(want == "n" or want == got for want, got in zip((a, b), g.groups()))

        found = [mode for mode in modes if fits(mode.label) and mode.label == base_label(mode.label)]
        found = found or [mode for mode in modes if fits(mode.label)]  # only suffixed ones: take those
        if not found:
            raise SolverError(f"no mode of the family {selector} among {[x.label for x in modes]}")
        return min(found, key=lambda mode: abs(mode.frequency - near))
    return modes.labelled(selector, near=near)
