"""Sensitivities of the modal frequencies (and k_eff), and of a mode's amplitude per volt at resonance, of a solved
3-D solid model to scene parameters, from two extra assemblies per parameter (a central difference of the
matrices, ``RELATIVE_STEP``) and no new eigen solve.

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

The amplitude per volt at resonance of an output o (``ReducedModel.amplitude_per_volt``, short circuit, 1 V on the
driven electrodes) is |c| with c = g(zeta) theta phi / lambda + P r, where theta = s^T f_V (f_V = -K x_V the voltage
load), phi = P s (P the output's z-row of ``output_operators``), g = 1 / (2 i zeta) - 1 / kappa, kappa =
1 - omega_d^2 / lambda, and r = T y + x_V the undamped response at omega_d = 0.97 omega_r ((A - omega_d^2 B) y = F)
whose part along the mode, theta phi / (kappa lambda), ``reduce`` takes out (``modalfe.response.forced``). Its
derivative takes, from the same dK, dM: d lambda as above; ds = T dx by Nelson's method (AIAA J. 14 (1976) 1201):
dx = v + c x with (A - lambda B) v = -(dA - lambda dB) x + d lambda B x solved with v_k = 0 at the largest
|x_k| (row and column k of the singular matrix replaced by the identity) and c = -x^T B v - x^T dB x / 2 (from
x^T B x = 1); dtheta = ds^T f_V - s^T dK x_V (the electrodes' charge coupling, the electromechanical block of dK);
dy = (A - omega_d^2 B)^-1 (dF - (dA - omega_d^2 dB) y + d(omega_d^2) B y); dzeta = zeta'(omega) d omega (non-zero for
Rayleigh damping only). Nelson's matrix is singular for a repeated eigenvalue: such a mode is refused. An output
that moves with the mesh (a face group's centre: a foot tip when the length changes) or a fixed point the mesh moves
under has its probe row P differenced like K: dP = (P(p + h) - P(p - h)) / 2h on the two moved meshes, exactly what
a solve at p +- h reads there.
"""

from __future__ import annotations

import fnmatch
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError, SolverError
from modalfe.geometry import builder_parameters
from modalfe.geometry.gmsh_model import grid_breaks
from modalfe.models.constraints import free_values
from modalfe.models.solid import Model, assemble
from modalfe.response.forced import Damping, beside_resonance
from modalfe.response.loads import output_operators
from modalfe.results.coupling import k_eff
from modalfe.results.modes import Mode, Modes
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
# piezoelectric constants a sensitivity can be taken to: the tensor and its (row, column) entries in Voigt notation,
# the 6mm symmetry of a poled ceramic tying d31 = d32 and d15 = d24 (IEEE Std 176-1987, table of 6mm constants)
_PIEZO_CONSTANTS = {f"{t}{k}": (t, entries) for t in "de" for k, entries in
                    (("31", ((2, 0), (2, 1))), ("33", ((2, 2),)), ("15", ((0, 4), (1, 3))))}


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
    (``E``, ``nu``, ``rho``), ``materials.NAME.d31|d33|d15|e31|e33|e15`` of a piezoelectric material a part is
    made of (``_piezo_parameter``), ``springs.GROUP`` (all three components scaled together; the value is the
    largest) or ``springs.GROUP.z`` [N/m], ``masses.GROUP`` [kg]. A dimension moves the mesh's nodes with the
    parts (``moved_nodes``); one that changes the topology (parts merging or crossing) is refused.

    ``open_modes``: open-circuit modes of the same scene and mesh; each mode is paired with the one most alike
    in shape (MAC, ``modalfe.solve.estimates.shape_partners``) and k_eff^2 = (fa^2 - fr^2) / fa^2 is
    differentiated through fr and fa: dk = fr (fr dfa / fa - dfr) / (k fa^2). The bracket is a difference of
    nearly equal terms: an error e in d ln f / d ln p becomes ~ e / k^2 in d ln k / d ln p, so a weakly coupled
    mode's dk_eff is only as good as that allows (NaN where k_eff = 0).
    """
    model = _solid(modes.model)
    specs, steps = _steps(model, parameters, relative_step)
    return _pass(modes, specs, steps, open_modes)


def _steps(model: Model, parameters: Sequence[str], relative_step: float) -> tuple[list[_Parameter], np.ndarray]:
    """The parameters of ``model``'s scene (every name checked before anything is assembled) and their steps h."""
    if not (np.isfinite(relative_step) and 0 < relative_step < 0.1):
        raise SceneError(f"relative_step: must lie in (0, 0.1), got {relative_step}")
    specs = [_parameter(model.scene, name) for name in parameters]
    steps = np.array([relative_step * (abs(s.value) or s.scale) for s in specs])
    for spec, h in zip(specs, steps):
        if not h > 0:
            raise SceneError(f"{spec.name}: is 0 with nothing to scale a step by; give another parameter")
    return specs, steps


def _pass(modes: Modes, specs: list[_Parameter], steps: np.ndarray, open_modes: Modes | None,
          also: Callable[[int, Model, Model, object, object], None] | None = None) -> Sensitivities:
    """One pass over the parameters: the models at p +- h, dK/dp and dM/dp, every mode's df/dp (and dk_eff/dp),
    and ``also(column, above, below, dK, dM)`` for any other derivative taken from the same matrices."""
    model = modes.model
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
        if also is not None:
            also(column, above, below, dK, dM)
    return Sensitivities(tuple(s.name for s in specs), np.array([s.value for s in specs]), steps,
                         tuple(mode.label for mode in modes), fr, dfr, coupling, dk)


@dataclass(frozen=True)
class AmplitudeSensitivities:
    """Derivatives of one mode's amplitude per volt at resonance at its outputs (``ReducedModel.amplitude_per_volt``)
    with respect to scene parameters, and of every mode's frequency from the same matrices.

    label, frequency [Hz] : the mode; damping : its description; outputs : output names; amplitude : (outputs,)
    0-peak normal amplitude per volt at resonance [m/V]; damplitude : (outputs, parameters) dA/dp [m/V per unit of
    p]; dfrequency : (parameters,) df/dp of the mode [Hz per unit]; modal : every mode's ``Sensitivities``
    (parameters, values, steps there).
    """

    label: str
    frequency: float
    damping: str
    outputs: tuple[str, ...]
    amplitude: np.ndarray
    damplitude: np.ndarray
    dfrequency: np.ndarray
    modal: Sensitivities

    @property
    def relative(self) -> np.ndarray:
        """(outputs, parameters) d ln A / d ln p = (p / A) dA/dp [-]."""
        return self.damplitude * self.modal.values[None, :] / self.amplitude[:, None]


def amplitude_sensitivities(modes: Modes, parameters: Sequence[str], *, mode: Mode, outputs, damping: Damping,
                            open_modes: Modes | None = None, relative_step: float = RELATIVE_STEP,
                            material_points: bool = False) -> AmplitudeSensitivities:
    """dA/dp [m/V per unit] of the amplitude per volt at resonance of ``mode`` (one of ``modes``, short circuit) at
    ``outputs`` (names as for ``reduce``) with ``damping``, for each of ``parameters`` (as for
    ``frequency_sensitivities``, whose derivatives of every mode, and k_eff's with ``open_modes``, come from the same
    two assemblies per parameter): the module docstring's derivative; two factorizations (Nelson's matrix and the
    one beside resonance), no eigen solve. SolverError for a mode whose eigenvalue is repeated (within
    ``DEGENERATE`` of another of ``modes``): its eigenvector has no derivative of its own. A fixed output point
    (name, (x, y, z)) on an element boundary of a moving mesh reads a field with a kink there: its derivative is the
    mean of the one-sided ones. ``material_points``: every output is read where it sits in the mesh, moving with its
    nodes (no probe row differenced): a point of a grid that scales with its face, as the touch surface's."""
    model = _solid(modes.model)
    if not any(m is mode for m in modes):
        raise SceneError("mode: not one of the modes given; pick it from them (modes.labelled(...))")
    lam = mode.omega**2
    for other in modes:
        if other is not mode and abs(other.omega**2 - lam) <= DEGENERATE * lam:
            raise SolverError(f"mode {mode.label}: its eigenvalue is repeated (mode {other.label} within "
                              f"{DEGENERATE:g}); Nelson's eigenvector derivative needs a distinct one")
    specs, steps = _steps(model, parameters, relative_step)
    derivative = _AmplitudeDerivative(mode, outputs, damping)
    damplitude, dlam = np.zeros((len(derivative.probes), len(specs))), np.zeros(len(specs))

    def amplitude(column: int, above: Model, below: Model, dK, dM) -> None:
        dP = None
        if specs[column].geometric and not material_points:
            P_above, P_below = (output_operators(m, outputs) for m in (above, below))
            dP = {name: (P_above[name][2] - P_below[name][2]) / (2 * steps[column]) for name in derivative.probes}
        damplitude[:, column], dlam[column] = derivative(dK, dM, dP)

    modal = _pass(modes, specs, steps, open_modes, amplitude)
    return AmplitudeSensitivities(mode.label, mode.frequency, damping.describe(), tuple(derivative.probes),
                                  np.abs(derivative.c), damplitude, dlam / (8 * np.pi**2 * mode.frequency), modal)


def amplitude_derivatives(mode: Mode, dK, dM, *, outputs, damping: Damping) -> np.ndarray:
    """(outputs,) dA [m/V per unit] of ``mode``'s amplitude per volt at resonance at ``outputs`` (fixed in the
    mesh) for given derivatives ``dK``, ``dM`` of its model's full matrices (module docstring; the mode must be
    distinct: ``amplitude_sensitivities`` checks that against its neighbours)."""
    _solid(mode.model)
    return _AmplitudeDerivative(mode, outputs, damping)(dK, dM, None)[0]


class _AmplitudeDerivative:
    """The amplitude per volt c (complex, per output) of a mode at resonance and what its derivative needs, factored
    once: Nelson's matrix and the one beside resonance (module docstring); called with dK, dM (and the outputs'
    probe derivatives dP, None for fixed ones) it gives (dA per output, d lambda)."""

    def __init__(self, mode: Mode, outputs, damping: Damping) -> None:
        from modalfe.solve.linalg import Shifted, factorize

        if mode.circuit != "short":
            raise SolverError(f"mode: the amplitude per volt needs a short-circuit mode, got {mode.circuit}")
        if not isinstance(damping, Damping):
            raise SceneError(f"damping: must be a Damping (Damping.parse('Q=150')), got {damping!r}")
        model = mode.model
        T, F, _, x_v, y, omega_d = beside_resonance(mode)
        A, B = (T.T @ model.K @ T).tocsr(), (T.T @ model.M @ T).tocsr()
        x = free_values(T, mode.shape)
        x = x / np.sqrt(x @ (B @ x))
        self.mode, self.damping, self.T, self.B, self.F, self.x_v, self.y, self.x = mode, damping, T, B, F, x_v, y, x
        self.lam, self.wd2 = mode.omega**2, omega_d**2
        self.s, self.r = T @ x, T @ y + x_v
        self.probes = {name: P[2] for name, P in output_operators(model, outputs).items()}  # the normal (z) rows
        self.theta = float(x @ F)
        self.zeta = damping.ratio(mode.omega)
        self.g = 1 / (2j * self.zeta) - self.lam / (self.lam - self.wd2)
        self.phi = np.array([float((P @ self.s)[0]) for P in self.probes.values()])
        self.c = self.g * self.theta * self.phi / self.lam + np.array([float((P @ self.r)[0])
                                                                         for P in self.probes.values()])
        self.k = int(np.argmax(np.abs(x)))  # Nelson: v_k = 0 where the mode is largest
        pick = np.arange(len(x)) == self.k
        keep = sp.diags((~pick).astype(float))
        self.nelson, _ = factorize(keep @ (A - self.lam * B) @ keep + sp.diags(pick.astype(float)))
        self.beside, _ = factorize(Shifted(A, B, self.wd2))

    def __call__(self, dK, dM, dP: dict | None) -> tuple[np.ndarray, float]:
        T, B, x, y, lam, wd2 = self.T, self.B, self.x, self.y, self.lam, self.wd2
        dA, dB = T.T @ dK @ T, T.T @ dM @ T
        dlam = float(x @ (dA @ x) - lam * (x @ (dB @ x)))
        rhs = dlam * (B @ x) - (dA @ x - lam * (dB @ x))
        rhs[self.k] = 0.0
        v = self.nelson(rhs)
        dx = v - (x @ (B @ v) + 0.5 * (x @ (dB @ x))) * x
        dF = -(T.T @ (dK @ self.x_v))  # the electrodes' charge coupling: dK's electromechanical block
        dtheta = float(dx @ self.F + x @ dF)
        dy = self.beside(dF - (dA @ y - wd2 * (dB @ y)) + (wd2 / lam) * dlam * (B @ y))
        ds, dr = T @ dx, T @ dy
        omega = self.mode.omega
        dg = -_ratio_slope(self.damping, omega) * dlam / (2 * omega) / (2j * self.zeta**2)
        theta, phi, g = self.theta, self.phi, self.g
        dc = np.empty(len(phi), dtype=complex)
        for i, (name, P) in enumerate(self.probes.items()):
            dphi, dPr = float((P @ ds)[0]), float((P @ dr)[0])
            if dP is not None:
                dphi, dPr = dphi + float((dP[name] @ self.s)[0]), dPr + float((dP[name] @ self.r)[0])
            resonant = dg * theta * phi[i] + g * (dtheta * phi[i] + theta * dphi - theta * phi[i] * dlam / lam)
            dc[i] = resonant / lam + dPr
        return np.real(np.conj(self.c) * dc) / np.abs(self.c), dlam


def _ratio_slope(damping: Damping, omega: float) -> float:
    """d zeta / d omega [s] of ``damping.ratio``: 0 for a modal ratio or Q; -alpha / (2 omega^2) + beta / 2 for
    Rayleigh damping, zeta = alpha / (2 omega) + beta omega / 2 (Chopra, Dynamics of Structures, sec. 11.4)."""
    if damping.zeta is not None or damping.Q is not None:
        return 0.0
    return -damping.alpha / (2 * omega**2) + damping.beta / 2


def check_parameters(scene, parameters: Sequence[str]) -> None:
    """SceneError naming the first of ``parameters`` that ``frequency_sensitivities`` cannot take for ``scene``
    (before any solve)."""
    for name in parameters:
        _parameter(scene, name)


def parameter_value(scene, name: str) -> float:
    """The value [its unit] of the parameter ``name`` (as for ``frequency_sensitivities``) in ``scene``."""
    return _parameter(scene, name).value


def with_values(scene, values: Mapping[str, float]):
    """``scene`` with each parameter of ``values`` (names as for ``frequency_sensitivities``) set [its unit], all
    together: a half model's mirror checks apply to the result, not to each step (the feet's springs of
    ``springs.foot_*.z`` keep their mirror images only once every one is set)."""
    mirrors = {"symmetry": list(scene.symmetry), "antisymmetry": list(scene.antisymmetry)}
    stepwise = len(values) > 1 and any(mirrors.values())
    changed = scene.with_overrides(symmetry=[], antisymmetry=[]) if stepwise else scene
    for name, value in values.items():
        changed = _parameter(changed, name).at(value)
    return changed.with_overrides(**mirrors) if stepwise else changed


def tied_members(scene, name: str) -> tuple[str, ...]:
    """The scene parameters a name stands for: itself, or for a pattern in the group of ``springs.GROUP...``,
    ``masses.GROUP`` or ``materials.NAME.KEY`` (``springs.foot_*.z``) every group it matches, set to one value
    together; SceneError if a pattern matches nothing or stands elsewhere."""
    if "*" not in name and "?" not in name:
        return (name,)
    head, _, rest = name.partition(".")
    group, _, tail = rest.partition(".")
    table = {"springs": scene.springs, "masses": scene.masses, "materials": scene.materials}.get(head)
    if table is None or "*" in tail or "?" in tail:
        raise SceneError(f"{name}: a pattern may stand only for the group of springs.GROUP, masses.GROUP or "
                         f"materials.NAME.KEY")
    found = sorted(g for g in table if fnmatch.fnmatchcase(g, group))
    if not found:
        raise SceneError(f"{name}: matches no {head} group; known: {sorted(table)}")
    return tuple(f"{head}.{g}" + (f".{tail}" if tail else "") for g in found)


def _tied_parameter(scene, name: str) -> _Parameter:
    """A pattern's members (``tied_members``) as one parameter: their common value, all set together."""
    members = [_parameter(scene, member) for member in tied_members(scene, name)]
    values = [m.value for m in members]
    if not all(math.isclose(v, values[0], rel_tol=1e-9) for v in values):
        raise SceneError(f"{name}: the tied parameters {[m.name for m in members]} must start equal, got {values}")
    return _Parameter(name, values[0], max(m.scale for m in members), any(m.geometric for m in members),
                      lambda x: with_values(scene, {m.name: x for m in members}))


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
    if "*" in name or "?" in name:
        return _tied_parameter(scene, name)
    head, _, rest = name.partition(".")
    lo, hi = scene.full_assembly().bounds
    extent = max(b - a for a, b in zip(lo, hi))
    if head == "materials" and rest:
        material, _, key = rest.partition(".")
        if key in _PIEZO_CONSTANTS and key not in scene.materials.get(material, {}):
            return _piezo_parameter(scene, name, material, key)
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
    accepted = builder_parameters(scene.device) if scene.device not in ("boxes", "shaped") else {}  # parts tables
    if name not in accepted:
        raise SceneError(f"{name}: not a parameter a sensitivity can be taken to; give a builder parameter "
                         f"{sorted(accepted)}, materials.NAME.KEY, materials.NAME.d31|d33|d15|e31|e33|e15, "
                         f"springs.GROUP, masses.GROUP"
                         + (" or parts.NAME.origin|size.x|y|z" if scene.device == "boxes" else ""))
    if accepted[name].kind is not float:
        raise SceneError(f"{name}: a {accepted[name].type_name} parameter; a sensitivity needs a real number "
                         f"(a count or a name changes the mesh topology)")
    value = _number(name, scene.params.get(name, accepted[name].default))
    return _Parameter(name, value, extent, True, lambda x: scene.with_overrides(**{name: x}))


def _piezo_parameter(scene, name: str, material: str, key: str) -> _Parameter:
    """``materials.NAME.d31|d33|d15`` [C/N] at fixed s^E and eps^T (a datasheet's constants) or ``e31|e33|e15``
    [C/m^2] at fixed c^E and eps^S of a piezoelectric material that a part is made of (the scene's or the
    library's), poled along its 3-axis; d31 = d32 and d15 = d24 (likewise e) change together, as in a poled ceramic
    (6mm symmetry). The scene gets the material as an e-form table (IEEE Std 176-1987 conversions,
    ``piezo_stiffness_form``)."""
    from modalfe.scene.materials import piezo_compliance_form, piezo_stiffness_form

    used = sorted({q.material for q in scene.full_assembly().parts})
    if material not in used:
        raise SceneError(f"{name}: no part is made of '{material}'; parts' materials: {used}")
    m = scene.material(material)
    if not m.is_piezoelectric:
        raise SceneError(f"{name}: '{material}' is not piezoelectric")
    tensor_name, entries = _PIEZO_CONSTANTS[key]
    s_E, d, eps_T = piezo_compliance_form(m.C, m.e, m.eps_S)
    tensor = d if tensor_name == "d" else m.e

    def at(x: float):
        changed = tensor.copy()
        for i, j in entries:
            changed[i, j] = x
        C, e, eps_S = piezo_stiffness_form(s_E, changed, eps_T) if tensor_name == "d" else (m.C, changed, m.eps_S)
        table = {"C": C.tolist(), "e": e.tolist(), "eps_S": (0.5 * (eps_S + eps_S.T)).tolist(), "rho": m.rho,
                 "source": m.source}
        return scene.with_overrides(**{f"materials.{material}": table})

    row, column = entries[0]
    return _Parameter(name, float(tensor[row, column]), float(np.abs(tensor).max()), False, at)


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
