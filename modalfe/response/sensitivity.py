"""Sensitivities of the modal frequencies (and k_eff) of a solved 3-D solid model to scene parameters, from two
extra assemblies per parameter (a central difference of the matrices, ``RELATIVE_STEP``) and no new eigen solve.

For the symmetric pencil (A, B) = (T^T K T, T^T M T) that the solve used (``modalfe.solve.levels.modes_of``) and a
mode x with x^T B x = 1, differentiating (A - lambda B) x = 0 and multiplying by x^T gives

    d lambda / dp = x^T (dA/dp - lambda dB/dp) x = s^T (dK/dp - lambda dM/dp) s,   s = T x = ``Mode.shape``,

(Fox & Kapoor, AIAA J. 6 (1968) 2426), since T does not depend on p (its potential scale only rescales unknowns,
which leaves the eigenvalues alone). It holds for the coupled piezoelectric system too (A symmetric indefinite,
B singular on the potentials), in short and open circuit alike. For modes of one eigenvalue (a symmetric device's
degenerate pair) x is any basis of the eigenspace: the one-sided derivatives for an increasing p are then the
eigenvalues of X^T (dK - lambda dM) X, ascending (Seyranian, Lund & Olhoff, Struct. Optim. 8 (1994) 207).

dK/dp and dM/dp are central differences (K(p + h) - K(p - h)) / 2h of the matrices assembled for the perturbed
scene on the same mesh, its nodes moved with the parts for a dimension (``moved_nodes``): the same topology, so
the same unknowns; two assemblies per parameter and no eigen solve (``RELATIVE_STEP`` says why not one). With
f = sqrt(lambda) / (2 pi), df/dp = (d lambda/dp) / (8 pi^2 f).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from modalfe.errors import SceneError
from modalfe.geometry import builder_parameters
from modalfe.geometry.gmsh_model import grid_breaks
from modalfe.models.solid import Model, assemble
from modalfe.results.coupling import k_eff
from modalfe.results.modes import Modes
from modalfe.solve.eigen import RIGID_FRACTION
from modalfe.solve.estimates import shape_partners

# relative step h / |p| of the central differences of the matrices. Central, not forward: a shape x held fixed while
# the nodes move strains the moved mesh, so x^T K(p + h) x gains energy ~ h^2 that is large against a low mode's
# own (a suspension mode, a rigid body on soft springs, most): on the honeycomb tile's yaw mode a forward difference
# is 36 % off at h/|p| = 1e-4 and still 0.1 % at 1e-6 (round-off). The central difference's error is truncation
# c (h/|p|)^2 plus round-off r |p|/h, r growing with lambda_max / lambda (the mesh's highest eigenvalue over the
# mode's): measured on d ln f / d ln p, c ~ 200 (a free 2 mm plate's thickness), 2300 (the ciliary beam's first
# mode and the sheets' position x0), 2000 (the tile's yaw and its length) and r ~ 4e-12 (the plate), 3.5e-11 (the
# beam's first mode), 1.5e-9 (the tile's yaw): 3e-5 keeps every one of them below 1e-4 (the tile's yaw 5e-5, the
# beam's first mode 5e-6, the others below 1e-6).
RELATIVE_STEP = 3e-5
# eigenvalues closer than this (relative) form one cluster: a symmetric device's pairs, split by the mesh's
# asymmetry only (2e-5 to 4e-4 on the honeycomb tile's sway and rocking pairs); physically distinct modes are
# farther apart, and those closer are resolved by the cluster's matrix (``frequency_derivatives``)
DEGENERATE = 1e-3
_COMPONENTS = "xyz"


@dataclass(frozen=True)
class Sensitivities:
    """Derivatives of every mode's frequency (and k_eff) with respect to scene parameters.

    parameters : names in the scene's override syntax; values : their values at the solve [their units];
    steps : the central-difference steps h of the matrices [their units]; labels, frequencies : the modes [Hz];
    dfrequency : (modes, parameters) df/dp [Hz per unit of p] (NaN for a rigid-body mode);
    k_eff : effective coupling of each mode from its open-circuit partner (NaN when no open-circuit modes were
    given or none is alike in shape); dk_eff : (modes, parameters) dk_eff/dp [per unit of p]
    """

    parameters: tuple[str, ...]
    values: np.ndarray
    steps: np.ndarray
    labels: tuple[str, ...]
    frequencies: np.ndarray
    dfrequency: np.ndarray
    k_eff: np.ndarray
    dk_eff: np.ndarray

    @property
    def relative(self) -> np.ndarray:
        """(modes, parameters) d ln f / d ln p = (p / f) df/dp [-]."""
        return self.dfrequency * self.values[None, :] / self.frequencies[:, None]


@dataclass(frozen=True)
class _Parameter:
    """One scalar scene parameter: its value, the size a step is relative to when the value is 0, whether it
    moves part faces, and the scene with it set to a new value."""

    name: str
    value: float
    scale: float
    geometric: bool
    at: Callable[[float], object]


def frequency_sensitivities(modes: Modes, parameters: Sequence[str], *, open_modes: Modes | None = None,
                            relative_step: float = RELATIVE_STEP) -> Sensitivities:
    """df/dp [Hz per unit] of every mode of a 3-D solid solve for each of ``parameters`` (module docstring: the
    eigenvalue derivative of Fox & Kapoor 1968 with dK/dp, dM/dp from assemblies at p +- h, h = ``relative_step``
    x |p|; for p = 0, x the device's largest extent (a position), the group's largest stiffness (a spring
    component) or 1 (a material constant)).

    Parameters (``Scene.with_overrides`` syntax): a real builder parameter (``length``, ``x0``), for a box scene
    ``parts.NAME.origin.x`` or ``parts.NAME.size.z`` [m], ``materials.NAME.KEY`` of a material the scene defines
    (``E``, ``nu``, ``rho``), ``springs.GROUP`` (all three components scaled together; the value is the
    largest) or ``springs.GROUP.z`` [N/m], ``masses.GROUP`` [kg]. A dimension moves the mesh's nodes with the
    parts (``moved_nodes``); one that changes the topology (parts merging or crossing) is refused.

    ``open_modes``: open-circuit modes of the same scene and mesh; each mode is paired with the one most alike
    in shape (MAC, ``modalfe.solve.estimates.shape_partners``) and k_eff^2 = (fa^2 - fr^2) / fa^2 is
    differentiated through fr and fa: dk = fr (fr dfa / fa - dfr) / (k fa^2). The bracket is a difference of
    nearly equal terms: an error e in d ln f / d ln p becomes ~ e / k^2 in d ln k / d ln p, so a weakly coupled
    mode's dk_eff is only as good as that allows (NaN where k_eff = 0).
    """
    model = _solid(modes.model)
    if not (np.isfinite(relative_step) and 0 < relative_step < 0.1):
        raise SceneError(f"relative_step: must lie in (0, 0.1), got {relative_step}")
    specs = [_parameter(model.scene, name) for name in parameters]  # every name checked before assembling
    steps = np.array([relative_step * (abs(s.value) or s.scale) for s in specs])
    for spec, h in zip(specs, steps):
        if not h > 0:
            raise SceneError(f"{spec.name}: is 0 with nothing to scale a step by; give another parameter")
    fr = modes.frequencies
    n, m = len(modes), len(specs)
    dfr, dk = np.full((n, m), np.nan), np.full((n, m), np.nan)
    coupling = np.full(n, np.nan)
    partners = {}
    if open_modes is not None:
        if _solid(open_modes.model).K.shape != model.K.shape or open_modes.model.scene != model.scene:
            raise SceneError("open_modes: not solved for the same scene and mesh as the modes")
        short_at = {mode.index: i for i, mode in enumerate(modes)}
        open_at = {mode.index: j for j, mode in enumerate(open_modes)}
        partners = {short_at[i]: open_at[found[0].index] for i, found in shape_partners(modes, open_modes).items()}
        fa = open_modes.frequencies
        for i, j in partners.items():
            coupling[i] = k_eff(fr[i], fa[j])
    for column, (spec, h) in enumerate(zip(specs, steps)):
        above, below = (perturbed_model(model, spec.name, spec.value + sign * h) for sign in (1, -1))
        dK, dM = (above.K - below.K) / (2 * h), (above.M - below.M) / (2 * h)
        dfr[:, column] = frequency_derivatives(modes, dK, dM)
        if partners:
            dfa = frequency_derivatives(open_modes, dK, dM)
            for i, j in partners.items():
                if coupling[i] > 0:
                    dk[i, column] = fr[i] * (fr[i] * dfa[j] / fa[j] - dfr[i, column]) / (coupling[i] * fa[j] ** 2)
    return Sensitivities(tuple(s.name for s in specs), np.array([s.value for s in specs]), steps,
                         tuple(mode.label for mode in modes), fr, dfr, coupling, dk)


def check_parameters(scene, parameters: Sequence[str]) -> None:
    """SceneError naming the first of ``parameters`` that ``frequency_sensitivities`` cannot take for ``scene``
    (before any solve)."""
    for name in parameters:
        _parameter(scene, name)


def with_values(scene, values: Mapping[str, float]):
    """``scene`` with each parameter of ``values`` (names as for ``frequency_sensitivities``) set [its unit]."""
    for name, value in values.items():
        scene = _parameter(scene, name).at(value)
    return scene


def frequency_derivatives(modes: Modes, dK, dM) -> np.ndarray:
    """df/dp [Hz per unit] of each of ``modes`` from the derivatives ``dK``, ``dM`` of its model's full matrices:
    d lambda = x^T (dK - lambda dM) x (Fox & Kapoor 1968) for M-normalised shapes x; for a cluster of one
    eigenvalue (within ``DEGENERATE``), the ascending eigenvalues of X^T (dK - lambda dM) X (Seyranian, Lund &
    Olhoff 1994; ``modes`` sorted by frequency, as a solve returns them); then df = d lambda / (8 pi^2 f), NaN for
    a rigid-body mode (eigenvalue below ``RIGID_FRACTION`` of the highest, frequency below 1e-3 of it: a free body's
    rigid modes come out at round-off frequencies ~ sqrt(eps lambda_max) / 2 pi, 0.01-0.05 Hz on a steel strip)."""
    X = np.column_stack([mode.shape for mode in modes])
    X = X / np.sqrt(np.einsum("ij,ij->j", X, modes.model.M @ X))
    f = modes.frequencies
    lam = (2 * np.pi * f) ** 2
    dlam = np.empty(len(f))
    start = 0
    while start < len(f):
        stop = start + 1
        while stop < len(f) and lam[stop] - lam[start] <= DEGENERATE * lam[stop]:
            stop += 1
        Y, mean = X[:, start:stop], lam[start:stop].mean()
        D = Y.T @ (dK @ Y - mean * (dM @ Y))
        dlam[start:stop] = np.linalg.eigvalsh(0.5 * (D + D.T))
        start = stop
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(lam > RIGID_FRACTION * lam.max(), dlam / (8 * np.pi**2 * f), np.nan)


def perturbed_model(model: Model, parameter: str, value: float) -> Model:
    """The model of ``model.scene`` with ``parameter`` set to ``value`` [its unit], assembled on ``model``'s mesh
    with its nodes moved with the parts (``moved_nodes``): the same unknowns, so the matrices compare entry by
    entry with ``model``'s and its modes with ``model``'s by shape."""
    model = _solid(model)
    spec = _parameter(model.scene, parameter)
    scene = spec.at(value)
    dm = model.mesh
    p = dm.mesh.p if model.frame is None else model.frame.T @ dm.mesh.p  # ``assemble`` rotates it again
    if spec.geometric:
        p = moved_nodes(p, model.scene.assembly(), scene.assembly(), parameter)
    moved = assemble(scene, replace(dm, mesh=type(dm.mesh)(p, dm.mesh.t)), frame=model.frame)
    if moved.K.shape != model.K.shape or not np.array_equal(moved.clamped, model.clamped):
        raise SceneError(f"{parameter}: at {value:g} the model has other unknowns (a support or electrode "
                         f"changed); a sensitivity needs the same ones")
    return moved


def moved_nodes(points: np.ndarray, before, after, parameter: str) -> np.ndarray:
    """Node coordinates (3, n) [m] of a mesh of assembly ``before`` moved to fit ``after``: along each axis the
    piecewise-linear map of ``before``'s grid breakpoints (part faces and face-window edges, sorted) onto
    ``after``'s, so each part's nodes move with its faces. SceneError naming ``parameter`` unless the two have
    the same parts and every face sits on the breakpoint of the same rank in both (no parts merging or crossing:
    the same mesh topology)."""
    if [q.name for q in before.parts] != [q.name for q in after.parts] or set(before.faces) != set(after.faces):
        raise SceneError(f"{parameter}: changes the device's parts or face groups; a sensitivity needs the same "
                         f"mesh topology")
    old, new = grid_breaks(before), grid_breaks(after)
    out = np.empty_like(points)
    for axis in range(3):
        if len(old[axis]) != len(new[axis]) or not np.array_equal(_ranks(before, axis, old[axis]),
                                                                    _ranks(after, axis, new[axis])):
            raise SceneError(f"{parameter}: changes the order of the part faces along {_COMPONENTS[axis]} (parts "
                             f"merge or cross); a sensitivity needs the same mesh topology")
        out[axis] = np.interp(points[axis], old[axis], new[axis])
    return out


def _ranks(assembly, axis: int, breaks: np.ndarray) -> np.ndarray:
    """Index in ``breaks`` of every part face and face-window edge normal to ``axis``, in a fixed order."""
    anchors = [c for q in assembly.parts for c in (q.lo[axis], q.hi[axis])]
    for group in sorted(assembly.faces):
        for face in assembly.faces[group]:
            if face.window is not None:
                _, _, lo, hi = assembly.part(face.part).face_bounds(face.side, face.window)
                anchors += [lo[axis], hi[axis]]
    return np.argmin(np.abs(np.asarray(anchors)[:, None] - breaks[None, :]), axis=1)


def _solid(model) -> Model:
    if not isinstance(model, Model):
        raise SceneError(f"sensitivities: need modes of the 3-D solid model (fidelity 'solid'), got a "
                         f"{type(model).__name__}")
    return model


def _number(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise SceneError(f"{name}: a sensitivity needs a real number, got {value!r}")
    return float(value)


def _parameter(scene, name: str) -> _Parameter:
    """The scalar parameter ``name`` of ``scene`` (see ``frequency_sensitivities``); SceneError naming it if it is
    unknown or not a real number."""
    head, _, rest = name.partition(".")
    lo, hi = scene.full_assembly().bounds
    extent = max(b - a for a, b in zip(lo, hi))
    if head == "materials" and rest:
        material, _, key = rest.partition(".")
        if material not in scene.materials or key not in scene.materials[material]:
            raise SceneError(f"{name}: the scene defines no such constant (materials.{material} must be a table "
                             f"of the scene holding {key or 'KEY'})")
        return _Parameter(name, _number(name, scene.materials[material][key]), 1.0, False,
                          lambda x: scene.with_overrides(**{name: x}))
    if head == "springs" and rest:
        group, _, component = rest.partition(".")
        if group not in scene.springs or component not in ("", *_COMPONENTS):
            raise SceneError(f"{name}: no such spring; give springs.GROUP or springs.GROUP.x|y|z with GROUP in "
                             f"{sorted(scene.springs)}")
        k = np.array([_number(name, c) for c in scene.springs[group]])
        if component:
            axis = _COMPONENTS.index(component)

            def spring(x: float):
                return scene.with_overrides(**{f"springs.{group}": tuple(np.where(np.arange(3) == axis, x, k))})

            return _Parameter(name, k[axis], float(k.max()), False, spring)
        if not k.max() > 0:
            raise SceneError(f"{name}: all three stiffnesses are 0; give one component, springs.{group}.x|y|z")
        return _Parameter(name, float(k.max()), 0.0, False,
                          lambda x: scene.with_overrides(**{f"springs.{group}": tuple(k * (x / k.max()))}))
    if head == "masses" and rest:
        if rest not in scene.masses:
            raise SceneError(f"{name}: no such attached mass; known: {sorted(scene.masses)}")
        return _Parameter(name, _number(name, scene.masses[rest]), 0.0, False,
                          lambda x: scene.with_overrides(**{name: x}))
    if head == "parts" and rest and scene.device == "boxes":
        return _box_parameter(scene, name, rest, extent)
    accepted = builder_parameters(scene.device) if scene.device != "boxes" else {}
    if name not in accepted:
        raise SceneError(f"{name}: not a parameter a sensitivity can be taken to; give a builder parameter "
                         f"{sorted(accepted)}, materials.NAME.KEY, springs.GROUP, masses.GROUP"
                         + (" or parts.NAME.origin|size.x|y|z" if scene.device == "boxes" else ""))
    if accepted[name].kind is not float:
        raise SceneError(f"{name}: a {accepted[name].type_name} parameter; a sensitivity needs a real number "
                         f"(a count or a name changes the mesh topology)")
    value = _number(name, scene.params.get(name, accepted[name].default))
    return _Parameter(name, value, extent, True, lambda x: scene.with_overrides(**{name: x}))


def _box_parameter(scene, name: str, rest: str, extent: float) -> _Parameter:
    """``parts.PART.origin|size.x|y|z`` [m] of a box scene."""
    part, _, tail = rest.partition(".")
    key, _, component = tail.partition(".")
    parts = [dict(spec) for spec in scene.params["parts"]]
    index = next((i for i, spec in enumerate(parts) if spec["name"] == part), None)
    if index is None or key not in ("origin", "size") or component not in _COMPONENTS or not component:
        raise SceneError(f"{name}: give parts.PART.origin|size.x|y|z with PART in {[q['name'] for q in parts]}")
    axis = _COMPONENTS.index(component)

    def at(x: float):
        changed = [dict(spec) for spec in parts]
        changed[index][key] = [x if k == axis else c for k, c in enumerate(parts[index][key])]
        return scene.with_overrides(parts=changed)

    return _Parameter(name, _number(name, parts[index][key][axis]), extent, True, at)
