"""Scenes: the validated parameters of one device, from a built-in name or a TOML file.

A scene names its geometry builder and that builder's keyword parameters, the role of each face
group (driven or grounded electrode, clamp, spring, attached mass), the analysis asked for, the
mesh resolution, the working mode and the seed's targets with their sources.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

import modalfe.scene.values as v
from modalfe.errors import SceneError
from modalfe.scene.frozen import FrozenMap, freeze
from modalfe.scene.loads import Load, check_load

DEFAULT_DAMPING_SOURCE = "assumption (docs/assumptions.md, Damping: default Q ~ 150)"
MATERIAL_DAMPING_SOURCE = "default: each material's Qm from the material table (modalfe.scene.materials)"
USER_DAMPING_SOURCE = "set by the user"
KINDS = ("plate", "beam", "solid")  # solid: no reduced model (a device with cylinders, rings or outlines)
MAX_HARMONIC = 64  # highest circumferential harmonic ``mesh.harmonics`` takes (64 nodal diameters)
_DAMPING = re.compile(r"^(zeta|Q)=([^,]+)$|^rayleigh=([^,]+),([^,]+)$")


def check_damping(field: str, text: Any, *, material: bool = False) -> str:
    """``zeta=Z``, ``Q=Q`` or ``rayleigh=ALPHA,BETA``: finite numbers >= 0 (Q > 0), light (``check_underdamped``);
    with ``material`` also ``material`` (each material's Qm, ``modalfe.response.losses``)."""
    if material and text == "material":
        return text
    match = _DAMPING.match(text) if isinstance(text, str) else None
    if match is None:
        raise SceneError(f"{field}: expected 'zeta=Z', 'Q=Q' or 'rayleigh=ALPHA,BETA', got {text!r}")
    try:
        numbers = [float(x) for x in match.groups() if x is not None and x not in ("zeta", "Q")]
    except ValueError:
        raise SceneError(f"{field}: expected numbers in 'zeta=Z', 'Q=Q' or 'rayleigh=ALPHA,BETA', got {text!r}") \
            from None
    if any(not (math.isfinite(x) and x >= 0) for x in numbers) or (match.group(1) == "Q" and numbers[0] == 0):
        raise SceneError(f"{field}: damping values must be finite and >= 0 (Q > 0), got {text!r}")
    if match.group(1) in ("zeta", "Q"):
        check_underdamped(field, numbers[0] if match.group(1) == "zeta" else 1 / (2 * numbers[0]))
    return text


def check_underdamped(field: str, zeta: float, where: str = "") -> None:
    """Refuse a modal damping ratio ``zeta`` >= 1 (Q <= 0.5, eta >= 2): an overdamped mode has no resonance, so a
    resonator model (one-mode reduction, modal admittance) would show none; ``where`` says at which mode."""
    if zeta >= 1:
        raise SceneError(f"{field}: modal damping ratio {zeta:.3g}{where} is overdamped (zeta >= 1, Q <= 0.5, "
                         f"eta >= 2): the mode has no resonance for a resonator model; give light damping (zeta < 1)")


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
    ``symmetric`` / ``antisymmetric``: mid-planes the mode's shape is mirror-symmetric / antisymmetric about (the
    Cu-Be plate's (0,6) about x; the tile's twisting (1,1) antisymmetric about x and y): the report solves it on
    that half (quarter) of the device where the geometry is mirror-symmetric (``family_scene``).
    """

    selector: str
    near: float
    targets: tuple[Target, ...] = ()
    symmetric: tuple[str, ...] = ()
    antisymmetric: tuple[str, ...] = ()

    def family_scene(self, scene: Scene) -> tuple[Scene, str]:
        """(``scene`` solving only this mode's family: its ``symmetric`` planes added to the scene's symmetry, its
        ``antisymmetric`` ones as the antisymmetry; a phrase for the report), or (``scene``, why not) where the
        device is not mirror-symmetric about those planes (a dimension changed by the user) or the family cannot be
        solved (antisymmetry with piezoelectric parts)."""
        symmetry = tuple(a for a in dict.fromkeys((*scene.symmetry, *self.symmetric)) if a not in self.antisymmetric)
        family = replace(scene, symmetry=symmetry, antisymmetry=tuple(self.antisymmetric))
        if family == scene:
            return scene, ""
        try:
            family.validate()
            family.assembly()
        except SceneError as exc:
            return scene, f"{self.selector} not solved on its mirror family alone ({exc})"
        return family, ""


@dataclass(frozen=True)
class Drive:
    """Forced-response defaults: ``damping`` (``material``: each material's Qm weighted by the mode's strain
    energy, ``damping_fallback`` for the materials without one; or ``Q=150``, ``zeta=0.025``, ``rayleigh=a,b`` for
    every mode), each with its source; ``outputs`` (face groups, ``mean:GROUP`` or (name, (x, y, z)) [m]),
    the ``load`` (``modalfe.response.loads.Load``, a text such as ``force actuator=0,0,1`` or a table;
    default: the driven electrodes' voltage) with its source, and amplitude or time targets from the seeds."""

    damping: str = "material"
    damping_source: str = MATERIAL_DAMPING_SOURCE
    damping_fallback: str = "Q=150"
    damping_fallback_source: str = DEFAULT_DAMPING_SOURCE
    outputs: tuple = ()
    targets: tuple[Target, ...] = ()
    load: Any = "voltage"
    load_source: str = "default: the driven electrodes' voltage"

    def __post_init__(self) -> None:
        check_damping("drive.damping", self.damping, material=True)
        v.string("drive.damping_source", self.damping_source)
        check_damping("drive.damping_fallback", self.damping_fallback)
        v.string("drive.damping_fallback_source", self.damping_fallback_source)
        for i, item in enumerate(v.array("drive.outputs", self.outputs)):
            if isinstance(item, str):
                v.string(f"drive.outputs[{i}]", item)
                continue
            pair = v.array(f"drive.outputs[{i}]", item, length=2)
            v.string(f"drive.outputs[{i}][0]", pair[0])
            v.numbers3(f"drive.outputs[{i}][1]", pair[1], unit="m")
        object.__setattr__(self, "load", Load.from_value(self.load, "drive.load"))
        v.string("drive.load_source", self.load_source)
        object.__setattr__(self, "outputs", freeze(tuple(self.outputs)))
        object.__setattr__(self, "targets", tuple(self.targets))


@dataclass(frozen=True)
class MeshSettings:
    """Element size from elements per wavelength at ``max_frequency`` [Hz]; ``element`` hex or tet;
    ``family`` of the hexahedra: serendipity (nodes on vertices and edges only, orders 1-3) or Lagrange
    (tensor-product, orders 1-4), ``auto`` serendipity at order 2 and Lagrange above;
    ``clamp_grading`` geometric element layers toward faces clamped in x, y and z (hex only, 0: none);
    ``harmonics`` the highest circumferential harmonic n the axisymmetric model solves (n = 0..harmonics; None: as
    many as the modes asked for reach, ``modalfe.solve.axisymmetric``)."""

    elements_per_wavelength: float = 6.0
    max_frequency: float = 0.0
    element: str = "hex"
    order: int = 2
    family: str = "auto"
    min_size: float = 0.0
    max_size: float = math.inf
    min_layers: int = 3
    clamp_grading: int = 0
    harmonics: int | None = None

    def __post_init__(self) -> None:
        v.number("mesh.elements_per_wavelength", self.elements_per_wavelength, positive=True)
        v.number("mesh.max_frequency", self.max_frequency, unit="Hz", minimum=0.0)
        v.string("mesh.element", self.element, choices=("hex", "tet"))
        top = 4 if self.element == "hex" else 2  # Gauss-Lobatto Lagrange hexahedra to 4; tetrahedra P1, P2
        if v.integer("mesh.order", self.order) not in range(1, top + 1):
            raise SceneError(f"mesh.order: must be 1 to {top} for {self.element} elements, got {self.order}")
        v.string("mesh.family", self.family, choices=("auto", "lagrange", "serendipity"))
        if self.family == "serendipity" and (self.element != "hex" or self.order > 3):
            raise SceneError(f"mesh.family: serendipity elements are hexahedra of order 1 to 3, got {self.element} "
                             f"of order {self.order}")
        v.number("mesh.min_size", self.min_size, unit="m", minimum=0.0)
        v.number("mesh.max_size", self.max_size, unit="m", positive=True, allow_inf=True)
        if self.min_size > self.max_size:
            raise SceneError(f"mesh.min_size: {self.min_size:g} m exceeds mesh.max_size {self.max_size:g} m")
        v.integer("mesh.min_layers", self.min_layers, minimum=1, maximum=1000)
        v.integer("mesh.clamp_grading", self.clamp_grading, minimum=0, maximum=12)
        if self.harmonics is not None:
            v.integer("mesh.harmonics", self.harmonics, minimum=0, maximum=MAX_HARMONIC)

    @property
    def serendipity(self) -> bool:
        """Whether the hexahedra carry nodes on their vertices and edges only (``auto``: at order 2)."""
        return self.element == "hex" and (self.family == "serendipity" or (self.family == "auto" and self.order == 2))


@dataclass(frozen=True)
class Analysis:
    """Which modes to find: ``count`` modes nearest ``near`` [Hz], or all in ``band`` [Hz]."""

    near: float | None = None
    count: int = 8
    band: tuple[float, float] | None = None
    circuit: str = "short"

    def __post_init__(self) -> None:
        if self.near is not None:
            v.number("analysis.near", self.near, unit="Hz", minimum=0.0)
        v.integer("analysis.count", self.count, minimum=1)
        if self.band is not None:
            band = v.array("analysis.band", self.band, length=2)
            f1, f2 = (v.number(f"analysis.band[{i}]", f, unit="Hz", minimum=0.0) for i, f in enumerate(band))
            if not f1 < f2:
                raise SceneError(f"analysis.band: needs 0 <= F1 < F2 [Hz], got ({f1:g}, {f2:g})")
            object.__setattr__(self, "band", freeze(tuple(band)))
        v.string("analysis.circuit", self.circuit, choices=("short", "open"))


@dataclass(frozen=True)
class Scene:
    """One device's validated parameters. Build variants with ``with_overrides``.

    Immutable and hashable: the tables (``params``, ``electrodes``, ``clamps``, ``edges``, ``guides``, ``springs``,
    ``masses``, ``materials``) are read-only ``FrozenMap``s, lists in them tuples.
    """

    name: str
    device: str
    params: Mapping[str, Any]
    electrodes: Mapping[str, str] = field(default_factory=dict)
    clamps: Mapping[str, str] = field(default_factory=dict)
    # line supports: name -> {faces = (GROUP_A, GROUP_B), fix = COMPONENTS}, the components held at zero on the lines
    # where the two face groups meet (docs/supports.md)
    edges: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    # guided faces: GROUP -> COMPONENTS each held uniform over the face (one shared unknown per component: the face
    # translates along them without tilting or twisting; docs/supports.md)
    guides: Mapping[str, str] = field(default_factory=dict)
    springs: Mapping[str, tuple[float, float, float]] = field(default_factory=dict)
    masses: Mapping[str, float] = field(default_factory=dict)
    materials: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    analysis: Analysis = Analysis()
    mesh: MeshSettings = MeshSettings()
    working_modes: tuple[WorkingMode, ...] = ()
    assumptions: tuple[str, ...] = ()
    kind: str = "plate"
    symmetry: tuple[str, ...] = ()
    # axes whose mid-plane the device is mirror-symmetric about and the modes kept are ANTIsymmetric about (the
    # tile's twisting mode (1,1) about both): the same half (quarter) solved, the tangential displacement fixed on
    # the cut instead of the normal one
    antisymmetry: tuple[str, ...] = ()
    drive: Drive = Drive()
    # a seed's spectrum to print beside the computed one, by family: "suspension" (rigid-body modes on the
    # supports) or "plate" (elastic modes), e.g. {"suspension": "seed 002 FEM: 28, 45, 51, 77 Hz"}
    reference_spectra: Mapping[str, str] = field(default_factory=dict)
    # writes ``assumptions`` from the scene's parameters again after ``with_overrides`` (built-in scenes), so the
    # lines never describe dimensions the user changed
    assumption_writer: Callable[[Scene], tuple[str, ...]] | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in _TABLES:
            object.__setattr__(self, name, FrozenMap(getattr(self, name)))
        for name in ("working_modes", "assumptions", "symmetry", "antisymmetry"):
            object.__setattr__(self, name, tuple(getattr(self, name)))

    def assembly(self):
        """The box assembly that is meshed: the whole device, or the half (quarter) kept by
        ``symmetry`` and ``antisymmetry`` (axes whose mid-plane the device is mirror-symmetric about; the solve
        then returns only the modes symmetric, or antisymmetric, about those planes). Built once per scene (a
        frozen value): the report's solves asked for it ~900 times, 1.6 s of 28 s rebuilding it."""
        return self._kept("_assembly", self._cut_assembly)

    def _kept(self, name: str, build: Callable[[], object]):
        """``build()``, kept on the instance under ``name`` after the first call (not kept when it raises)."""
        if name not in self.__dict__:
            object.__setattr__(self, name, build())
        return self.__dict__[name]

    def _cut_assembly(self):
        assembly = self.full_assembly()
        if self.antisymmetry and any(p.poling for p in assembly.parts):
            raise SceneError("antisymmetry: not available with piezoelectric parts (their potential would have to "
                             "vanish on the cut); use symmetry or solve the whole device")
        for axis in (*self.symmetry, *self.antisymmetry):
            half = assembly.halved("xyz".index(axis))  # the parts' mirror images first
            _check_mirrored_roles(self, assembly, axis)
            assembly = half
        return assembly

    @property
    def mirror_axes(self) -> tuple[str, ...]:
        """Every mid-plane the model is cut at: ``symmetry`` then ``antisymmetry``."""
        return (*self.symmetry, *self.antisymmetry)

    @property
    def mirror_family(self) -> str:
        """The modes the model keeps, in words ("symmetric about y and antisymmetric about x"), "" for all."""
        return " and ".join(f"{kind} about {'/'.join(axes)}" for kind, axes in
                            (("symmetric", self.symmetry), ("antisymmetric", self.antisymmetry)) if axes)

    @property
    def symmetry_clamps(self) -> dict[str, str]:
        """Mirror conditions: no displacement normal to each symmetry plane, none along an antisymmetry plane."""
        return {**{f"symmetry_{axis}": axis for axis in self.symmetry},
                **{f"symmetry_{axis}": "xyz".replace(axis, "") for axis in self.antisymmetry}}

    def full_assembly(self):
        """The device's whole assembly (validated by its builder; a geometry file's for device ``imported``), built
        once per scene."""
        return self._kept("_full_assembly", self._built_assembly)

    def _built_assembly(self):
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
        dotted ``mesh.*``, ``analysis.*``, ``drive.*``, ``springs.GROUP``, ``masses.GROUP``,
        ``electrodes.GROUP``, ``clamps.GROUP``, ``guides.GROUP``, ``edges.NAME``, ``materials.NAME.KEY``.
        Setting ``drive.damping`` makes its source "set by the user"; a built-in scene's assumption lines are
        rewritten from the new parameters."""
        if not overrides:
            return self
        scene = self
        params = dict(self.params)
        for key, value in overrides.items():
            if not isinstance(key, str) or not key:
                raise SceneError(f"--set: a key must be a non-empty name, got {key!r}")
            head, _, rest = key.partition(".")
            if head in ("mesh", "analysis", "drive") and rest:
                sub = getattr(scene, head)
                names = {f.name for f in fields(sub)}
                if rest not in names:
                    raise SceneError(f"{key}: unknown setting; known: {sorted(names)}")
                change = {rest: value}
                for what in ("damping", "damping_fallback", "load"):
                    if key == f"drive.{what}" and f"drive.{what}_source" not in overrides:
                        change[f"{what}_source"] = f"{USER_DAMPING_SOURCE} (drive.{what})"
                scene = replace(scene, **{head: replace(sub, **change)})
            elif head in _SUPPORT_TABLES and rest:
                table = dict(getattr(scene, head))
                table[rest] = value
                scene = replace(scene, **{head: table})
            elif key in _SUPPORT_TABLES:
                if not isinstance(value, Mapping):
                    raise SceneError(f"{key}: must be a table group = value")
                scene = replace(scene, **{key: dict(value)})
            elif key in ("symmetry", "antisymmetry"):
                axes = v.array(key, value)
                scene = replace(scene, **{key: tuple(v.string(f"{key}[{i}]", a, choices=("x", "y", "z"))
                                                     for i, a in enumerate(axes))})
            elif key == "kind":
                scene = replace(scene, kind=v.string("kind", value, choices=KINDS))
            elif head == "materials" and rest:
                name, _, prop = rest.partition(".")
                if not prop:
                    if not isinstance(value, Mapping):
                        raise SceneError(f"{key}: must be a table of material constants, or set materials.NAME.KEY")
                    table = dict(scene.materials)
                    table[name] = dict(value)
                else:
                    table = dict(scene.materials)
                    table[name] = {**table.get(name, {}), prop: value}
                scene = replace(scene, materials=table)
            elif head in ("mesh", "analysis", "drive", "materials"):
                raise SceneError(f"{key}: give a setting, e.g. {head}.NAME=VALUE")
            else:
                params[key] = value
        scene = replace(scene, params=params)
        if scene.params != self.params and _has_shapes(scene):
            # a built-in given round parts: no reduced model describes them; swept hexahedra mesh them when they
            # all stand on one axis, else tetrahedra (unless mesh.element = "hex" is asked here: the mesher refuses)
            scene = replace(scene, kind="solid")
            if scene.mesh.element == "hex" and "mesh.element" not in overrides and scene.assembly().sweep_axis is None:
                scene = replace(scene, mesh=replace(scene.mesh, element="tet"))
        scene.validate()
        if self.assumption_writer is not None and (scene.params != self.params or scene.materials != self.materials):
            scene = replace(scene, assumptions=self.assumption_writer(scene))  # from the validated parameters
        return scene

    def validate(self) -> None:
        """Raise SceneError naming the first field at fault."""
        from modalfe.geometry import BUILDERS, check_parameters

        v.string("name", self.name)
        v.string("kind", self.kind, choices=KINDS)
        for name in ("analysis", "mesh", "drive"):
            expected = {"analysis": Analysis, "mesh": MeshSettings, "drive": Drive}[name]
            if not isinstance(getattr(self, name), expected):
                raise SceneError(f"{name}: must be a {expected.__name__}")
        if self.device == "imported":
            from modalfe.scene.part_tables import imported_parts

            v.known_keys("", self.params, ("file", "digest", "parts"))
            imported_parts(self.params.get("parts", ()))
            if self.mirror_axes:
                which = "symmetry" if self.symmetry else "antisymmetry"
                raise SceneError(f"{which}: not available for a geometry file (its mirror halves are not known)")
            if self.mesh.element != "tet":
                raise SceneError(f"mesh.element: a geometry file is meshed with tetrahedra; set 'tet', got "
                                 f"'{self.mesh.element}'")
        elif self.device in ("boxes", "shaped"):
            v.known_keys("", self.params, ("parts", "faces"))
            if self.device == "boxes":
                v.box_parts(self.params.get("parts", ()))
            else:
                from modalfe.scene.part_tables import shaped_parts

                shaped_parts(self.params.get("parts", ()))
            v.face_groups(self.params.get("faces", {}))
        elif self.device in BUILDERS:
            check_parameters(self.device, self.params)  # types and constraints from the builder's signature
        for key in ("symmetry", "antisymmetry"):
            for i, axis in enumerate(getattr(self, key)):
                v.string(f"{key}[{i}]", axis, choices=("x", "y", "z"))
        for axis in self.antisymmetry:
            if axis in self.symmetry or self.antisymmetry.count(axis) > 1:
                raise SceneError(f"antisymmetry: the {axis} mid-plane is listed twice (symmetry or antisymmetry)")
        for name, spec in self.materials.items():
            v.table(f"materials.{name}", spec)
            self.material(name)
        assembly = self.assembly()
        if assembly.shaped and self.kind != "solid":
            raise SceneError(f"kind: part '{assembly.shaped[0]}' is not a box, which only the solid model meshes: "
                             f"kind must be 'solid', got '{self.kind}'")
        for part in assembly.parts:
            try:
                mat = self.material(part.material)
            except SceneError as exc:
                raise SceneError(f"part '{part.name}': {exc}") from None
            if part.poling and not mat.is_piezoelectric:
                raise SceneError(f"part '{part.name}': poled but material '{part.material}' is not piezoelectric")
        groups = set(self.full_assembly().faces) | set(assembly.faces)
        for role, table in (("electrodes", self.electrodes), ("springs", self.springs), ("masses", self.masses),
                            ("clamps", self.clamps), ("guides", self.guides)):
            for group in table:
                if group not in groups:
                    raise SceneError(f"{role}.{group}: no such face group; known: {sorted(groups)}")
        for role, table in (("clamps", self.clamps), ("guides", self.guides)):
            for group, components in table.items():
                _components(f"{role}.{group}", components)
        for name, edge in self.edges.items():
            _check_edge(self, name, edge, groups)
        for group, role in self.electrodes.items():
            v.string(f"electrodes.{group}", role, choices=("drive", "ground"))
        for group, k in self.springs.items():
            v.numbers3(f"springs.{group}", k, unit="N/m", minimum=0.0)
        for group, m in self.masses.items():
            v.number(f"masses.{group}", m, unit="kg", positive=True)
        if self.drive.load.kind != "voltage":
            check_load(self, self.drive.load)  # the face group exists, the load is symmetric like the model
        a = self.analysis
        if a.near is not None and not a.near > 0:
            raise SceneError(f"analysis.near: must be a positive frequency [Hz], got {a.near}")
        if a.near is None and a.band is None:
            raise SceneError("analysis: give near (with count) or band")
        for i, wm in enumerate(self.working_modes):
            v.string(f"working_modes[{i}].selector", wm.selector)
            v.number(f"working_modes[{i}].near", wm.near, unit="Hz", positive=True)
        from modalfe.scene.checks import check_device

        check_device(self)  # one bonded body, consistent electrodes (modalfe/scene/checks.py)

    @property
    def max_frequency(self) -> float:
        """Highest frequency the mesh must resolve [Hz]: mesh.max_frequency, or the analysis's top
        (band end, or the target frequency) when higher."""
        a = self.analysis
        top = a.band[1] if a.band is not None else a.near
        return max(self.mesh.max_frequency, top)


def _has_shapes(scene: Scene) -> bool:
    """Whether the scene's device has parts other than boxes (False when its parameters do not build: ``validate``
    then names the parameter at fault)."""
    try:
        return bool(scene.full_assembly().shaped)
    except SceneError:
        return False


_TABLES = ("params", "electrodes", "clamps", "edges", "guides", "springs", "masses", "materials", "reference_spectra")
_SUPPORT_TABLES = ("springs", "masses", "electrodes", "clamps", "edges", "guides")  # --set TABLE.GROUP or TABLE


def _components(field: str, components: Any) -> str:
    """Displacement components ``components`` of a support: distinct letters of 'xyz'."""
    v.string(field, components)
    if set(components) - set("xyz") or len(set(components)) != len(components):
        raise SceneError(f"{field}: components must be distinct letters of 'xyz', got '{components}'")
    return components


def _check_edge(scene: Scene, name: str, edge: Any, groups: set[str]) -> None:
    """SceneError naming the field unless ``edges.NAME`` is {faces = [A, B], fix = COMPONENTS} with A and B two face
    groups of the device that meet along a line (``Assembly.meeting_length``; curved faces: the mesh checks)."""
    where = f"edges.{name}"
    v.table(where, edge)
    v.known_keys(where, edge, ("faces", "fix"))
    if "faces" not in edge or "fix" not in edge:
        raise SceneError(f"{where}: needs faces = [GROUP_A, GROUP_B] (the line where they meet) and fix = COMPONENTS")
    pair = [v.string(f"{where}.faces[{i}]", g) for i, g in enumerate(v.array(f"{where}.faces", edge["faces"],
                                                                             length=2))]
    for i, group in enumerate(pair):
        if group not in groups:
            raise SceneError(f"{where}.faces[{i}]: no such face group '{group}'; known: {sorted(groups)}")
    if pair[0] == pair[1]:
        raise SceneError(f"{where}.faces: two different face groups meet on an edge, got '{pair[0]}' twice")
    _components(f"{where}.fix", edge["fix"])
    if scene.mirror_axes:
        which = "symmetry" if scene.symmetry else "antisymmetry"
        raise SceneError(f"{which}: not available with edge supports ({where}); solve the whole device")
    if scene.device == "imported":
        return  # physical surfaces have no rectangles: the mesh finds the shared nodes
    length = scene.full_assembly().meeting_length(*pair)
    if length == 0.0:
        raise SceneError(f"{where}.faces: '{pair[0]}' and '{pair[1]}' do not meet along a line")


def _check_mirrored_roles(scene: Scene, assembly, axis: str) -> None:
    """SceneError unless every face group with a role (spring, mass, clamp, electrode) has its mirror image about
    the ``axis`` mid-plane of ``assembly`` in itself or in a group of the same role and value: a half model solves
    one side and stands for the other by its image, so a support on one side only would be lost or doubled."""
    k = "xyz".index(axis)
    lo, hi = assembly.bounds
    twice, scale = lo[k] + hi[k], max(b - a for a, b in zip(lo, hi))

    def rectangles(group: str, mirror: bool = False):
        out = set()
        for face in assembly.faces[group]:
            rect = assembly.face_rect(face)
            if rect is None:  # a curved wall: the parts' own mirror check covers it
                return None
            normal, at, a, b = rect
            a, b = list(a), list(b)
            if mirror and normal == k:
                at = twice - at
            elif mirror:
                a[k], b[k] = twice - b[k], twice - a[k]
            out.add((normal, round(at / scale, 9), *(round(x / scale, 9) for i in range(3) if i != normal
                                                     for x in (a[i], b[i]))))
        return frozenset(out)

    for table in ("springs", "masses", "clamps", "guides", "electrodes"):
        roles = {g: v for g, v in getattr(scene, table).items() if g in assembly.faces}
        for group, value in roles.items():
            image = rectangles(group, mirror=True)
            if image is None or any(rectangles(other) == image for other, v in roles.items() if v == value):
                continue
            which = "symmetry" if axis in scene.symmetry else "antisymmetry"
            raise SceneError(f"{which}: {table}.{group} has no mirror image of the same value about the {axis} "
                             f"mid-plane (the half model stands for the other side by its image)")
