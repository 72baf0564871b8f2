"""Scenes: the validated parameters of one device, from a built-in name or a TOML file.

A scene names its geometry builder and that builder's keyword parameters, the role of each face
group (driven or grounded electrode, clamp, spring, attached mass), the analysis asked for, the
mesh resolution, the working mode and the seed's targets with their sources.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

from modalfe.errors import SceneError
from modalfe.scene.frozen import FrozenMap, freeze


@dataclass(frozen=True)
class Target:
    """A number from a seed to compare with: ``kind`` is measured, reference (a peer's model) or analytic."""

    name: str
    value: float
    unit: str
    kind: str
    source: str


@dataclass(frozen=True)
class WorkingMode:
    """A mode the device is designed around, found by its shape near ``near`` [Hz].

    ``selector``: a plate label ``(0,6)``, a family ``(0,n)`` (nodal lines across the length only,
    the one nearest ``near``), a beam label ``bending-z 6``, or ``heave`` for a suspension mode.
    """

    selector: str
    near: float
    targets: tuple[Target, ...] = ()


@dataclass(frozen=True)
class Drive:
    """Forced-response defaults: ``damping`` (``Q=150``, ``zeta=0.025`` or ``rayleigh=a,b``, with its
    source in ``damping_source``), ``outputs`` (face groups or (name, (x, y, z))), the working mode
    to drive, and amplitude or time targets from the seeds."""

    damping: str = "Q=150"
    damping_source: str = "assumption (docs/assumptions.md, Damping: default Q ~ 150)"
    outputs: tuple = ()
    targets: tuple[Target, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "outputs", freeze(tuple(self.outputs)))
        object.__setattr__(self, "targets", tuple(self.targets))


@dataclass(frozen=True)
class MeshSettings:
    """Element size from elements per wavelength at ``max_frequency`` [Hz]; ``element`` hex or tet;
    ``clamp_grading`` geometric element layers toward faces clamped in x, y and z (hex only, 0: none)."""

    elements_per_wavelength: float = 6.0
    max_frequency: float = 0.0
    element: str = "hex"
    order: int = 2
    min_size: float = 0.0
    max_size: float = math.inf
    min_layers: int = 3
    clamp_grading: int = 0


@dataclass(frozen=True)
class Analysis:
    """Which modes to find: ``count`` modes nearest ``near`` [Hz], or all in ``band`` [Hz]."""

    near: float | None = None
    count: int = 8
    band: tuple[float, float] | None = None
    circuit: str = "short"

    def __post_init__(self) -> None:
        if self.band is not None:
            object.__setattr__(self, "band", freeze(tuple(self.band)))


@dataclass(frozen=True)
class Scene:
    """One device's validated parameters. Build variants with ``with_overrides``.

    Immutable and hashable: the tables (``params``, ``electrodes``, ``clamps``, ``springs``,
    ``masses``, ``materials``) are read-only ``FrozenMap``s, lists in them tuples.
    """

    name: str
    device: str
    params: Mapping[str, Any]
    electrodes: Mapping[str, str] = field(default_factory=dict)
    clamps: Mapping[str, str] = field(default_factory=dict)
    springs: Mapping[str, tuple[float, float, float]] = field(default_factory=dict)
    masses: Mapping[str, float] = field(default_factory=dict)
    materials: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    analysis: Analysis = Analysis()
    mesh: MeshSettings = MeshSettings()
    working_modes: tuple[WorkingMode, ...] = ()
    assumptions: tuple[str, ...] = ()
    kind: str = "plate"
    symmetry: tuple[str, ...] = ()
    drive: Drive = Drive()
    # a seed's spectrum to print beside the computed one, by family: "suspension" (rigid-body modes on the
    # supports) or "plate" (elastic modes), e.g. {"suspension": "seed 002 FEM: 28, 45, 51, 77 Hz"}
    reference_spectra: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in _TABLES:
            object.__setattr__(self, name, FrozenMap(getattr(self, name)))
        for name in ("working_modes", "assumptions", "symmetry"):
            object.__setattr__(self, name, tuple(getattr(self, name)))

    def assembly(self):
        """The box assembly that is meshed: the whole device, or the half (quarter) kept by
        ``symmetry`` (axes whose mid-plane the device is mirror-symmetric about; the solve then
        returns only the modes symmetric about those planes)."""
        assembly = self.full_assembly()
        for axis in self.symmetry:
            assembly = assembly.halved("xyz".index(axis))
        return assembly

    @property
    def symmetry_clamps(self) -> dict[str, str]:
        """Mirror conditions: no displacement normal to each symmetry plane."""
        return {f"symmetry_{axis}": axis for axis in self.symmetry}

    def full_assembly(self):
        """The device's whole box assembly (validated by its builder)."""
        from modalfe.geometry import BUILDERS

        try:
            builder = BUILDERS[self.device]
        except KeyError:
            raise SceneError(f"device: unknown builder '{self.device}'; known: {sorted(BUILDERS)}") from None
        try:
            return builder(**self.params)
        except TypeError as exc:
            raise SceneError(f"{self.device}: {exc}") from None

    def material(self, name: str):
        """A material by name: the scene's own definitions first, then the library."""
        from modalfe.scene.materials import material

        if name in self.materials:
            return material({"name": name, **self.materials[name]})
        return material(name)

    def with_overrides(self, **overrides: Any) -> Scene:
        """A copy with parameters changed. Keys: builder parameters (``ceramic_thickness``), or
        dotted ``mesh.*``, ``analysis.*``, ``springs.GROUP``, ``masses.GROUP``, ``electrodes.GROUP``,
        ``materials.NAME.KEY``."""
        scene = self
        params = dict(self.params)
        for key, value in overrides.items():
            head, _, rest = key.partition(".")
            if head in ("mesh", "analysis", "drive") and rest:
                sub = getattr(scene, head)
                names = {f.name for f in fields(sub)}
                if rest not in names:
                    raise SceneError(f"{key}: unknown setting; known: {sorted(names)}")
                if rest == "band" and value is not None:
                    value = tuple(float(v) for v in value)
                scene = replace(scene, **{head: replace(sub, **{rest: value})})
            elif head in ("springs", "masses", "electrodes", "clamps") and rest:
                table = dict(getattr(scene, head))
                table[rest] = value
                scene = replace(scene, **{head: table})
            elif key in ("springs", "masses", "electrodes", "clamps"):
                if not isinstance(value, Mapping):
                    raise SceneError(f"{key}: must be a table group = value")
                scene = replace(scene, **{key: dict(value)})
            elif key == "symmetry":
                scene = replace(scene, symmetry=tuple(value))
            elif head == "materials" and rest:
                name, _, prop = rest.partition(".")
                table = dict(scene.materials)
                table[name] = {**table.get(name, {}), prop: value}
                scene = replace(scene, materials=table)
            else:
                params[key] = value
        scene = replace(scene, params=params)
        scene.validate()
        return scene

    def validate(self) -> None:
        """Raise SceneError naming the first field at fault."""
        from modalfe.geometry import BUILDERS, check_parameters

        if self.device in BUILDERS:
            check_parameters(self.device, self.params)  # types and constraints from the builder's signature
        for axis in self.symmetry:
            if axis not in ("x", "y", "z"):
                raise SceneError(f"symmetry: axes must be 'x', 'y' or 'z', got '{axis}'")
        assembly = self.assembly()
        for part in assembly.parts:
            try:
                mat = self.material(part.material)
            except SceneError as exc:
                raise SceneError(f"part '{part.name}': {exc}") from None
            if part.poling and not mat.is_piezoelectric:
                raise SceneError(f"part '{part.name}': poled but material '{part.material}' is not piezoelectric")
        groups = set(self.full_assembly().faces) | set(assembly.faces)
        for role, table in (("electrodes", self.electrodes), ("springs", self.springs), ("masses", self.masses)):
            for group in table:
                if group not in groups:
                    raise SceneError(f"{role}.{group}: no such face group; known: {sorted(groups)}")
        for group, components in self.clamps.items():
            if group not in groups:
                raise SceneError(f"clamps.{group}: no such face group; known: {sorted(groups)}")
            if not components or set(components) - set("xyz"):
                raise SceneError(f"clamps.{group}: components must be letters of 'xyz', got '{components}'")
        for group, role in self.electrodes.items():
            if role not in ("drive", "ground"):
                raise SceneError(f"electrodes.{group}: must be 'drive' or 'ground', got '{role}'")
        for group, k in self.springs.items():
            if len(k) != 3 or any(not (math.isfinite(v) and v >= 0) for v in k):
                raise SceneError(f"springs.{group}: needs three stiffnesses >= 0 [N/m], got {k}")
        for group, m in self.masses.items():
            if not (math.isfinite(m) and m > 0):
                raise SceneError(f"masses.{group}: must be a positive mass [kg], got {m}")
        a = self.analysis
        if a.circuit not in ("short", "open"):
            raise SceneError(f"analysis.circuit: must be 'short' or 'open', got '{a.circuit}'")
        if a.band is not None and not (0 <= a.band[0] < a.band[1]):
            raise SceneError(f"analysis.band: needs 0 <= F1 < F2 [Hz], got {a.band}")
        if a.near is not None and not a.near > 0:
            raise SceneError(f"analysis.near: must be a positive frequency [Hz], got {a.near}")
        if a.near is None and a.band is None:
            raise SceneError("analysis: give near (with count) or band")
        if not (isinstance(a.count, int) and a.count >= 1):
            raise SceneError(f"analysis.count: must be a positive integer, got {a.count}")
        m = self.mesh
        if m.element not in ("hex", "tet"):
            raise SceneError(f"mesh.element: must be 'hex' or 'tet', got '{m.element}'")
        if m.order not in (1, 2):
            raise SceneError(f"mesh.order: must be 1 or 2, got {m.order}")
        if not m.elements_per_wavelength > 0:
            raise SceneError(f"mesh.elements_per_wavelength: must be positive, got {m.elements_per_wavelength}")
        if isinstance(m.clamp_grading, bool) or not (isinstance(m.clamp_grading, int) and 0 <= m.clamp_grading <= 12):
            raise SceneError(f"mesh.clamp_grading: must be an integer from 0 to 12, got {m.clamp_grading!r}")

    @property
    def max_frequency(self) -> float:
        """Highest frequency the mesh must resolve [Hz]: mesh.max_frequency, or the analysis's top
        (band end, or the target frequency) when higher."""
        a = self.analysis
        top = a.band[1] if a.band is not None else a.near
        return max(self.mesh.max_frequency, top)


_TABLES = ("params", "electrodes", "clamps", "springs", "masses", "materials", "reference_spectra")
