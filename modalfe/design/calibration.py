"""Model updating from measured modes: the scene parameters (in ln p) that best explain measured frequencies and
bending wavelengths, with their posterior uncertainty, correlation and what the data cannot identify.

Weighted nonlinear least squares, chi^2(x) = sum_i ((y_i(x) - d_i) / sigma_i)^2 over x = ln |p|, minimised by
Levenberg-Marquardt in its trust-region form (Nocedal & Wright, Numerical Optimization, 2nd ed. 2006, sec. 10.3,
algorithm 4.1 for the radius; Friswell & Mottershead, Finite Element Model Updating in Structural Dynamics, 1995,
ch. 7 for sensitivity-based updating), one 3-D solid solve per trial point. The Jacobian of a frequency is
df/dp of ``modalfe.response.sensitivity`` (no new eigen solve); that of a wavelength is a central difference of
the labeller's wavelength (``Mode.wavelength``: twice the mean spacing of the nodal lines crossed along the
plate's centre line, ``modalfe.results.labels``) between eigen solves of the model assembled at p +- h on the
same mesh with its nodes moved (``perturbed_model``): the extraction is piecewise linear in the nodal values, so
no closed-form derivative exists short of the eigenvector derivative (Nelson 1976), which costs a linear solve
per parameter anyway; the moved mesh keeps the extraction smooth in p (the same triangles, the same samples).

At the optimum the posterior covariance of ln p is the Gauss-Newton one, (J^T W J)^-1 (Friswell & Mottershead
eq. 7.27; Bard, Nonlinear Parameter Estimation, 1974, sec. 7-5), scaled by chi^2 / (m - n) when that exceeds 1
(the stated sigmas do not explain the residuals: the Birge ratio) and left unscaled otherwise; the result says
which. Identifiability is read from the SVD of the weighted Jacobian J_w = W^(1/2) J: a direction v_k with
singular value s_k below ``RELATIVE_THRESHOLD`` s_max, or whose posterior sd 1 / s_k (ln units) exceeds 1 (the
combination uncertain by more than itself), is not identified; the parameters along it are named, with the
combination the data do fix (``E^0.5*thickness``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from modalfe.design.measurements import Measurement
from modalfe.design.tune_checks import check_variables
from modalfe.errors import SceneError, SolverError
from modalfe.response.sensitivity import (
    frequency_sensitivities,
    parameter_value,
    perturbed_model,
    with_values,
)
from modalfe.results.modes import select
from modalfe.solve.api import solid_modes, solve_modes
from modalfe.solve.estimates import partner
from modalfe.solve.levels import modes_of

CALIBRATE_COUNT = 6  # modes asked of each solve around a measured one (enough to find it by label as it moves)
INITIAL_RADIUS = math.log(1.2)  # first trust radius in ln p: parameters move by at most ~20 % in the first step
MAX_RADIUS = 1.0  # the trust region never exceeds a factor e in the parameters
RELATIVE_THRESHOLD = 1e-3  # s_k / s_max below this: the direction is not identified (numerical rank of J_w)
WAVELENGTH_STEP = 1e-3  # relative step of the wavelength's central difference (module docstring): truncation
# ~ h^2 (1e-6 relative), eigen-solver noise on the shapes ~ 1e-10 / h = 1e-7
_SHIFT = 0.995  # solves are shifted this far below the expected frequency: never onto an eigenvalue
_ACCEPT = 0.1  # actual / predicted chi^2 reduction above which a trial point is accepted
_MESH_MARGIN = 1.1  # the mesh resolves the highest measured frequency with this margin


@dataclass(frozen=True)
class Iterate:
    """One trial point: parameter values [their units], chi^2 there, whether it was accepted, the trust radius
    it was taken in [ln p] and the seconds its solve (and, if accepted, its Jacobian) took."""

    values: dict[str, float]
    chi2: float
    accepted: bool
    radius: float
    seconds: float


@dataclass(frozen=True)
class Calibration:
    """The fit: ``values`` [their units] of ``parameters`` with posterior ``sd`` (same units, first order:
    |p| x sd of ln p), ``correlation`` (of ln p); per measured quantity (``quantities``: ``"(0,6) frequency"``,
    ``"(0,6) wavelength"``) its ``measured``, ``sigma`` and ``predicted`` value [Hz or m]; ``chi2`` and its
    ``dof`` (m - n); ``scale``: the factor the covariance was multiplied by and ``covariance_basis`` saying why;
    ``singular_values`` and ``directions`` (columns, in ln p) of the weighted Jacobian; ``jacobian``: d y / d ln p
    (quantities, parameters) at the estimates [Hz or m], unweighted (``posterior`` with other sigmas);
    ``unidentified``: plain statements of what the data cannot identify (empty when all can); the ``iterates``;
    whether it ``converged`` and why it stopped; the ``scene`` at the estimates."""

    parameters: tuple[str, ...]
    values: np.ndarray
    sd: np.ndarray
    correlation: np.ndarray
    quantities: tuple[str, ...]
    measured: np.ndarray
    sigma: np.ndarray
    predicted: np.ndarray
    chi2: float
    dof: int
    scale: float
    covariance_basis: str
    singular_values: np.ndarray
    directions: np.ndarray
    jacobian: np.ndarray
    unidentified: tuple[str, ...]
    iterates: tuple[Iterate, ...]
    converged: bool
    reason: str
    scene: object

    @property
    def residuals(self) -> np.ndarray:
        """(predicted - measured) / sigma of each quantity [-]."""
        return (self.predicted - self.measured) / self.sigma

    @property
    def solves(self) -> int:
        return len(self.iterates)


@dataclass(frozen=True)
class _Parameter:
    """A varied parameter (a pattern such as ``springs.foot_*.z`` sets all it matches to one value,
    ``modalfe.response.sensitivity.tied_members``), its sign and the bounds of ln |p|."""

    name: str
    sign: float
    low: float
    high: float


@dataclass(frozen=True)
class _Point:
    """The model at one parameter point: predicted quantities, the selected modes, and the Jacobian d y / d ln p
    (unweighted) once asked for."""

    x: np.ndarray
    scene: object
    predicted: np.ndarray
    modes: tuple
    solve: object
    jacobian: np.ndarray | None = None


def calibrate(scene, measurements: Sequence[Measurement], parameters: Sequence[str], *,
              bounds: Mapping[str, tuple[float, float]] | None = None, max_iterations: int = 20,
              tol: float = 1e-5, start: Mapping[str, float] | None = None,
              progress: Callable[[int, Iterate], None] | None = None,
              resolution: Mapping | None = None) -> Calibration:
    """Fit ``parameters`` of ``scene`` to ``measurements`` (module docstring: Levenberg-Marquardt in ln |p|, one
    3-D solid solve per trial point, at most ``max_iterations`` a stage), within ``bounds`` (name -> (low, high),
    same sign as the value). Names as for ``frequency_sensitivities``; a ``*`` in the group of ``springs.GROUP...``,
    ``masses.GROUP`` or ``materials.NAME.KEY`` ties every matching group to one value (``springs.foot_*.z``: all
    feet alike), which they must share at the start. Each measured mode is found by label nearest its current
    predicted frequency (the measured one at the start). Converged when the Gauss-Newton step moves no ln p by more
    than ``tol``. ``start``: values to start from (name -> value, a pattern's value set on all it matches) instead
    of the scene's. The mesh resolves the highest measured frequency (``mesh.max_frequency`` raised if below it).

    Two stages: the fit on the scene's own mesh, then from its estimates on the resolved model (the answer
    ``modes`` gives for the measured modes at ``resolution``: ``solve_modes``' tol, fidelity, error_estimate); the
    posterior takes each predicted frequency's stated error as a model uncertainty beside the measurement's,
    sigma^2 = sigma_measured^2 + (error x f)^2 (Kennedy & O'Hagan, J. R. Stat. Soc. B 63 (2001) 425: the model's
    own inadequacy as a further variance)."""
    measurements = tuple(measurements)
    if not measurements or not all(isinstance(m, Measurement) for m in measurements):
        raise SceneError("measured: give one or more measurements")
    if not (math.isfinite(tol) and 0 < tol < 0.1):
        raise SceneError(f"tol: must lie in (0, 0.1), got {tol}")
    top = _MESH_MARGIN * max(m.frequency for m in measurements)
    if scene.max_frequency < top:
        scene = scene.with_overrides(**{"mesh.max_frequency": top})
    specs = _parameters(scene, parameters, dict(bounds or {}))
    if start:
        unknown = sorted(set(start) - {s.name for s in specs})
        if unknown:
            raise SceneError(f"start: {unknown[0]} is not among the parameters varied {[s.name for s in specs]}")
        scene = with_values(scene, {s.name: float(start[s.name]) for s in specs if s.name in start})
        specs = _parameters(scene, parameters, dict(bounds or {}))
    quantities, measured, sigma = _data(measurements)
    x = np.log(np.abs(_values(scene, specs)))
    iterates: list[Iterate] = []
    fit = _Fit(scene, specs, measurements, measured, sigma, max_iterations, tol, progress, iterates)
    point, chi2, converged, reason = fit.run(x, [m.frequency for m in measurements], resolved=None)
    if not converged:
        return _result(specs, point, quantities, measured, sigma, chi2, tuple(iterates), converged,
                       f"{reason} (on the scene's own mesh, before the resolved model)")
    point, chi2, converged, reason = fit.run(point.x, list(point.predicted[:len(measurements)]),
                                             resolved=dict(resolution or {}), previous=point.modes)
    errors = np.array([mode.error_estimate for mode in point.modes] + [math.nan] * (len(measured) - len(point.modes)))
    model_sigma = np.where(np.isfinite(errors), np.nan_to_num(errors, posinf=0.0) * point.predicted, 0.0)
    total = np.sqrt(sigma**2 + model_sigma**2)
    unstated = [m.label for m, e in zip(measurements, errors) if not np.isfinite(e)]
    reason += "; on the resolved model, its stated discretization error added to each frequency's sigma"
    if unstated:
        reason += f" (not estimated for {', '.join(unstated)}: measured sigma only)"
    return _result(specs, point, quantities, measured, total, _chi2(point.predicted, measured, total),
                   tuple(iterates), converged, reason)


@dataclass
class _Fit:
    """The Levenberg-Marquardt loop of ``calibrate`` (module docstring), run on the scene's own mesh or on the
    resolved model; ``iterates`` collects every trial point of both."""

    scene: object
    specs: list
    measurements: tuple
    measured: np.ndarray
    sigma: np.ndarray
    max_iterations: int
    tol: float
    progress: Callable | None
    iterates: list

    def run(self, x: np.ndarray, near: list[float], *, resolved: Mapping | None,
            previous: tuple = ()) -> tuple[_Point, float, bool, str]:
        """(point, chi2, converged, reason) of the fit from ln |p| = ``x``, each measured mode sought near ``near``."""
        scene, specs, measurements, measured, sigma, tol = (self.scene, self.specs, self.measurements, self.measured,
                                                            self.sigma, self.tol)
        started = len(self.iterates)
        clock = time.perf_counter()
        point = _evaluate(scene, specs, measurements, x, near, jacobian=True, previous=previous, resolved=resolved)
        radius = INITIAL_RADIUS
        low, high = np.array([s.low for s in specs]), np.array([s.high for s in specs])
        converged, reason = False, f"not converged after {self.max_iterations} solves"

        def record(p: _Point, chi2: float, accepted: bool) -> None:
            nonlocal clock
            iterate = Iterate(dict(zip([s.name for s in specs], _values(p.scene, specs).tolist())), chi2, accepted,
                              radius, time.perf_counter() - clock)
            self.iterates.append(iterate)
            clock = time.perf_counter()
            if self.progress is not None:
                self.progress(len(self.iterates), iterate)

        chi2 = _chi2(point.predicted, measured, sigma)
        record(point, chi2, True)
        while True:
            r = (point.predicted - measured) / sigma
            J = point.jacobian / sigma[:, None]
            step, held = _bounded_step(J, r, math.inf, point.x, low, high)
            if chi2 == 0 or np.max(np.abs(step), initial=0.0) <= tol:
                names = [s.name for s, h in zip(specs, held) if h]
                converged, reason = True, "the Gauss-Newton step is below tol" + (
                    f"; held on their bounds (the data pull them beyond): {', '.join(names)}" if names else "")
                break
            if len(self.iterates) - started >= self.max_iterations:
                break
            step, _ = _bounded_step(J, r, radius, point.x, low, high)
            x = point.x + step
            predicted_chi2 = float(np.sum((r + J @ step) ** 2))
            near = _near(point, measurements, step)
            trial = _evaluate(scene, specs, measurements, x, near, jacobian=False, previous=point.modes,
                              resolved=resolved)
            trial_chi2 = _chi2(trial.predicted, measured, sigma)
            ratio = (chi2 - trial_chi2) / max(chi2 - predicted_chi2, 1e-300)
            accepted = ratio > _ACCEPT
            if accepted:
                point, chi2 = _evaluate(scene, specs, measurements, x, near, jacobian=True, found=trial), trial_chi2
            norm = float(np.linalg.norm(step))
            record(trial, trial_chi2, accepted)
            if ratio < 0.25:
                radius = 0.25 * norm
            elif ratio > 0.75 and norm >= 0.99 * radius:
                radius = min(2 * radius, MAX_RADIUS)
            if radius <= tol:
                reason = "the trust region shrank below tol (the model does not follow its linearisation)"
                break
        return point, chi2, converged, reason


def _data(measurements: Sequence[Measurement]) -> tuple[tuple[str, ...], np.ndarray, np.ndarray]:
    """Quantities (frequencies first, in measurement order, then wavelengths), measured values and sigmas."""
    waved = [m for m in measurements if not math.isnan(m.wavelength)]
    names = [f"{m.label} frequency" for m in measurements] + [f"{m.label} wavelength" for m in waved]
    measured = [m.frequency for m in measurements] + [m.wavelength for m in waved]
    sigma = [m.sigma for m in measurements] + [m.wavelength_sigma for m in waved]
    return tuple(names), np.array(measured), np.array(sigma)


def _parameters(scene, names: Sequence[str], bounds: dict) -> list[_Parameter]:
    """The varied parameters checked against the scene (a pattern as one), and their bounds in ln |p|."""
    names = list(names)
    if not names or len(set(names)) != len(names) or not all(isinstance(n, str) and n for n in names):
        raise SceneError(f"vary: give one or more distinct parameter names, got {names}")
    unknown = sorted(set(bounds) - set(names))
    if unknown:
        raise SceneError(f"bounds: {unknown[0]} is not among the parameters varied {names}")
    specs = []
    for name in names:
        check_variables(scene, [name])  # a pattern's members changed together, as the fit changes them
        value = parameter_value(scene, name)
        if value == 0:
            raise SceneError(f"{name}: is 0; a calibration works in ln |p|, start it from a non-zero value")
        lo, hi = bounds.get(name, (-math.inf, math.inf) if value < 0 else (0.0, math.inf))
        if not (lo < hi) or lo * value < 0 or hi * value < 0:
            raise SceneError(f"bounds {name}: needs LOW < HIGH of the value's sign, got {lo:g}:{hi:g}")
        if not lo <= value <= hi:
            raise SceneError(f"{name}: {value:g} lies outside its bounds {lo:g}:{hi:g}")
        ln = sorted(math.log(abs(b)) if b != 0 else -math.inf for b in (lo, hi))
        specs.append(_Parameter(name, math.copysign(1.0, value), ln[0], ln[1]))
    return specs


def _values(scene, specs: Sequence[_Parameter]) -> np.ndarray:
    """The value of each parameter (a pattern's common value) [its unit]."""
    return np.array([parameter_value(scene, spec.name) for spec in specs])


def _at(scene, specs: Sequence[_Parameter], x: np.ndarray):
    """``scene`` with every member of each parameter set to sign exp(x)."""
    return with_values(scene, {s.name: float(s.sign * math.exp(v)) for s, v in zip(specs, x)})


def _chi2(predicted: np.ndarray, measured: np.ndarray, sigma: np.ndarray) -> float:
    return float(np.sum(((predicted - measured) / sigma) ** 2))


def _near(point: _Point, measurements: Sequence[Measurement], step: np.ndarray) -> list[float]:
    """Where each measured mode should be after ``step`` (first order), to find it by label there."""
    n = len(measurements)
    return (point.predicted[:n] + point.jacobian[:n] @ step).tolist()


def _evaluate(scene, specs, measurements, x, near, *, jacobian: bool, found: _Point | None = None,
              previous: tuple = (), resolved: Mapping | None = None) -> _Point:
    """The model at ln |p| = ``x``: predicted frequencies (and wavelengths) of the measured modes, each selected by
    label nearest ``near`` [Hz] (or by shape to ``previous``, ``_solve``), from one solve plus one eigen solve of
    the same model per measured frequency outside the first solve's span; with ``jacobian``, d y / d ln p too
    (reusing ``found``'s solve); ``resolved``: on the resolved model (``_solve``)."""
    point = found if found is not None else _solve(_at(scene, specs, x), measurements, near, x, previous, resolved)
    if not jacobian:
        return point
    names = [spec.name for spec in specs]
    model = point.modes[0].model
    unique = sorted({id(mode): mode for mode in point.modes}.values(), key=lambda mode: mode.frequency)
    modes = replace(point.solve, modes=tuple(unique))
    found_df = frequency_sensitivities(modes, names)  # a pattern's members moved together: the tie's derivative
    row = {id(mode): i for i, mode in enumerate(unique)}
    rows = [found_df.dfrequency[row[id(mode)]] * found_df.values for mode in point.modes]
    waved = [(m, mode) for m, mode in zip(measurements, point.modes) if not math.isnan(m.wavelength)]
    if waved:
        dw = np.empty((len(waved), len(names)))
        for j, (name, value) in enumerate(zip(names, found_df.values)):
            h = WAVELENGTH_STEP * abs(value)
            above, below = (_wavelengths(perturbed_model(model, name, value + sign * h), waved)
                            for sign in (1, -1))
            dw[:, j] = (above - below) / (2 * h) * value
        rows += list(dw)
    return replace(point, jacobian=np.array(rows))


def _solve(scene, measurements, near, x, previous: tuple = (), resolved: Mapping | None = None) -> _Point:
    """One solve near the first measured mode, more eigen solves of its model for measured modes outside its span;
    with ``resolved`` (``solve_modes`` keywords) the first on the model resolved for it, the others of its window
    with their stated errors (those of further solves of that model: none). Each measured mode by label nearest
    ``near``; where no
    mode carries the label (a mode mixed with a neighbour in a veering takes another pattern), the one most alike
    in shape (MAC) to its match at the last accepted point (``previous``)."""
    if resolved is None:
        first = solve_modes(scene, near=_SHIFT * near[0], count=CALIBRATE_COUNT, fidelity="solid",
                            error_estimate=False)
    else:
        first = solid_modes(scene, needs="calibrate", near=_SHIFT * near[0], count=CALIBRATE_COUNT,
                            mode=measurements[0].label, **resolved)
    solves = [first]
    chosen = []
    for m, f in zip(measurements, near):
        try:  # on the resolved model, the resolved solve's own mode (with its stated error) where it holds one
            mode = select(first if resolved is not None and _holds(first, m.label) else
                          _covering(solves, first.model, f), m.label, f)
        except SolverError:  # crowded by other modes: once more with four times as many around it
            analysis = replace(scene.analysis, near=_SHIFT * f, count=4 * CALIBRATE_COUNT, band=None, circuit="short")
            solves.append(modes_of(first.model, analysis, fidelity="solid"))
            try:
                mode = select(solves[-1], m.label, f)
            except SolverError as exc:  # relabelled (mixed with a neighbour): the last point's mode by shape
                mode = partner(previous[len(chosen)], solves[-1]) if previous else None
                if mode is None:
                    raise SolverError(f"calibrate: the measured mode {m.label} is not found near {f:.6g} Hz "
                                      f"({exc})") from None
        if not math.isnan(m.wavelength) and not math.isfinite(mode.wavelength):
            raise SolverError(f"calibrate: {m.label} has a measured wavelength but its computed shape has none "
                              f"(not a plate mode with two or more nodal lines across the length)")
        chosen.append(mode)
    waved = [mode.wavelength for m, mode in zip(measurements, chosen) if not math.isnan(m.wavelength)]
    return _Point(np.asarray(x, dtype=float), scene, np.array([mode.frequency for mode in chosen] + waved),
                  tuple(chosen), first)


def _holds(modes, label: str) -> bool:
    """Whether ``modes`` hold a mode of ``label`` (``select`` finds it)."""
    try:
        select(modes, label, modes[0].frequency if len(modes) else 0.0)
    except SolverError:
        return False
    return True


def _covering(solves: list, model, frequency: float):
    """The solve of ``solves`` whose modes span ``frequency`` [Hz], else a new eigen solve of ``model`` near it
    (appended to ``solves``): one factorization serves every measured mode within one solve's span."""
    for modes in solves:
        if modes.frequencies.min() <= frequency <= modes.frequencies.max():
            return modes
    analysis = replace(model.scene.analysis, near=_SHIFT * frequency, count=CALIBRATE_COUNT, band=None,
                       circuit="short")
    solves.append(modes_of(model, analysis, fidelity="solid"))
    return solves[-1]


def _wavelengths(model, waved) -> np.ndarray:
    """Wavelength [m] of each (measurement, mode) of ``waved`` in ``model`` (the same unknowns, nodes moved): the
    mode most alike in shape (``partner``) among eigen solves near the modes' frequencies."""
    out, solves = [], []
    for _, mode in waved:
        found = partner(mode, _covering(solves, model, mode.frequency))
        if found is None or not math.isfinite(found.wavelength):
            raise SolverError(f"calibrate: {mode.label} loses its shape (or wavelength) when a parameter moves by "
                              f"{WAVELENGTH_STEP:g} of itself; its wavelength has no derivative")
        out.append(found.wavelength)
    return np.array(out)


def _bounded_step(J: np.ndarray, r: np.ndarray, radius: float, x: np.ndarray, low: np.ndarray,
                  high: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The step of ``_step`` within the bounds and which parameters it holds on them (module docstring): a
    parameter on a bound that the descent direction -J^T r or the step pushes outward is held and the step of the
    others recomputed (an active set: Nocedal & Wright 2006, sec. 16.5), then the step clipped to the bounds."""
    gradient = J.T @ r
    on_low, on_high = x <= low + 1e-12, x >= high - 1e-12
    held = (on_low & (gradient > 0)) | (on_high & (gradient < 0))
    while True:
        step = _step(J, r, radius, ~held)
        outward = ~held & ((on_low & (step < 0)) | (on_high & (step > 0)))
        if not outward.any():
            return np.clip(x + step, low, high) - x, held
        held = held | outward


def _step(J: np.ndarray, r: np.ndarray, radius: float, free: np.ndarray) -> np.ndarray:
    """Levenberg-Marquardt step in ln p of the free parameters: the minimum-norm Gauss-Newton step (singular values
    below ``RELATIVE_THRESHOLD`` s_max dropped) if it lies within ``radius`` (2-norm), else (J^T J + mu I)^-1
    (-J^T r) with mu > 0 such that its norm is ``radius`` (Nocedal & Wright 2006, sec. 10.3, eq. 10.34)."""
    step = np.zeros(J.shape[1])
    if not free.any():
        return step
    U, s, Vt = np.linalg.svd(J[:, free], full_matrices=False)
    g = U.T @ r
    kept = s > RELATIVE_THRESHOLD * s.max() if s.size and s.max() > 0 else np.zeros(s.shape, bool)

    def at(mu: float) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.where(kept, -s * g / (s**2 + mu), 0.0)
        return Vt.T @ c

    delta = at(0.0)
    if np.linalg.norm(delta) > radius:
        lo, hi = 0.0, max(float(s.max() ** 2), 1e-300)
        while np.linalg.norm(at(hi)) > radius:
            hi *= 10
        for _ in range(100):  # ||delta(mu)|| decreases with mu: bisect (geometrically once lo > 0)
            mu = 0.5 * (lo + hi) if lo == 0 else math.sqrt(lo * hi)
            if np.linalg.norm(at(mu)) > radius:
                lo = mu
            else:
                hi = mu
            if hi - lo <= 1e-6 * hi:
                break
        delta = at(hi)
    step[free] = delta
    return step


def _result(specs, point: _Point, quantities, measured, sigma, chi2, iterates, converged, reason) -> Calibration:
    """Estimates, Gauss-Newton covariance (module docstring) and identifiability at ``point``."""
    names = tuple(s.name for s in specs)
    values = _values(point.scene, specs)
    found = posterior(point.jacobian, sigma, chi2)
    sd_ln = np.sqrt(np.diag(found.covariance))
    correlation = found.covariance / np.outer(sd_ln, sd_ln)
    s = found.singular_values
    weak = (s < RELATIVE_THRESHOLD * max(float(s.max()), 1e-300)) | (
        math.sqrt(found.scale) / np.maximum(s, 1e-300) > 1)
    statements = _identifiability(names, found.directions, weak, sd_ln)
    return Calibration(names, values, np.abs(values) * sd_ln, correlation, quantities, measured, sigma,
                       point.predicted, chi2, found.dof, found.scale, found.basis, s, found.directions,
                       point.jacobian, tuple(statements), iterates, converged, reason, point.scene)


@dataclass(frozen=True)
class Posterior:
    """Gauss-Newton posterior of ln p: ``covariance`` (n, n), the ``scale`` it carries and why (``basis``),
    residual ``dof`` = m - n, and the weighted Jacobian's ``singular_values`` (n, zeros where m < n) and right
    singular vectors ``directions`` (columns)."""

    covariance: np.ndarray
    scale: float
    basis: str
    dof: int
    singular_values: np.ndarray
    directions: np.ndarray


def posterior(jacobian: np.ndarray, sigma: np.ndarray, chi2: float) -> Posterior:
    """(J_w^T J_w)^-1 with J_w = ``jacobian`` / ``sigma`` (d y / d ln p over the 1-sigma of each quantity), times
    chi2 / (m - n) when that exceeds 1 (module docstring); a direction with no information (singular value 0)
    gets the variance of a singular value 1e-12 of the largest (a huge, finite sd)."""
    J = np.asarray(jacobian, dtype=float) / np.asarray(sigma, dtype=float)[:, None]
    m, n = J.shape
    _, s, Vt = np.linalg.svd(J, full_matrices=True)
    s = np.concatenate([s, np.zeros(n - len(s))])
    dof = m - n
    scale, basis = 1.0, "stated sigmas (chi2 / dof <= 1)" if dof > 0 else "stated sigmas (no residual dof)"
    if dof > 0 and chi2 / dof > 1:
        scale, basis = chi2 / dof, f"residual variance (chi2 / dof = {chi2 / dof:.3g} > 1 scales it)"
    floor = max(float(s.max()), 1e-300) * 1e-12
    covariance = scale * (Vt.T / np.maximum(s, floor) ** 2) @ Vt
    return Posterior(covariance, scale, basis, dof, s, Vt.T)


def _identifiability(names: Sequence[str], V: np.ndarray, weak: np.ndarray, sd_ln: np.ndarray) -> list[str]:
    """Plain statements for the weak directions (columns of ``V`` where ``weak``) and the parameters whose posterior
    sd of ln p exceeds 1 (``sd_ln``): those are not (separately) identifiable; the combination the strong
    directions fix among them, as a product of powers."""
    involved = (np.sum(V[:, weak] ** 2, axis=1) > 0.01) | (sd_ln > 1)  # > 10 % of a weak direction, or sd > value
    if not involved.any():
        return []
    group = [i for i in range(len(names)) if involved[i]]
    strong = V[np.ix_(group, np.flatnonzero(~weak))]
    quoted = [names[i] for i in group]
    if len(group) == 1:
        return [f"{quoted[0]} is not identified: the data hardly depend on it (posterior sd above its value)"]
    together = ", ".join(quoted[:-1]) + f" and {quoted[-1]}"
    if strong.size == 0 or np.linalg.norm(strong) < 1e-6:
        return [f"{together} are not identified: the data depend on none of them"]
    u, sv, _ = np.linalg.svd(strong, full_matrices=False)
    if len(sv) > 1 and sv[1] > 0.1 * sv[0]:
        return [f"{together} are not separately identifiable: only {int(np.sum(sv > 0.1 * sv[0]))} combinations "
                f"of them are"]
    lead = int(np.flatnonzero(np.abs(u[:, 0]) >= 0.99 * np.abs(u[:, 0]).max())[0])  # the first of the largest
    exponents = u[:, 0] / u[lead, 0]
    product = "*".join(f"{q}^{e:.3g}" if abs(e - 1) > 5e-4 else q for q, e in zip(quoted, exponents)
                       if abs(e) > 1e-4)
    return [f"{together} are not separately identifiable: only {product} is"]
