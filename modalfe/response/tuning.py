"""Tuning a mode to a target frequency by changing scene parameters: Gauss-Newton on ln f with the modal
sensitivities (``modalfe.response.sensitivity``), one 3-D solid solve and its sensitivities per iterate."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from modalfe.errors import SceneError, SolverError
from modalfe.response.sensitivity import check_parameters, frequency_sensitivities, with_values
from modalfe.results.modes import select
from modalfe.solve.api import solve_modes

MAX_RELATIVE_STEP = 0.2  # trust region: no parameter moves by more than this fraction of itself in one iterate
TUNE_COUNT = 6  # modes asked of each solve around the tracked one (enough to find it by label when neighbours move)


@dataclass(frozen=True)
class Iterate:
    """One solve: parameter values [their units], the tracked mode's frequency [Hz] and d ln f / d ln p."""

    values: dict[str, float]
    frequency: float
    relative_sensitivity: dict[str, float]
    seconds: float


@dataclass(frozen=True)
class TuningResult:
    """The iterates, whether the last one is within ``tol`` of the target, and the scene at the last values."""

    label: str
    target: float
    tol: float
    iterates: tuple[Iterate, ...]
    converged: bool
    reason: str
    scene: object

    @property
    def final(self) -> Iterate:
        return self.iterates[-1]


def tune_frequency(scene, label: str, target: float, parameters: Sequence[str], *, tol: float = 1e-3,
                   bounds: Mapping[str, tuple[float, float]] | None = None, max_iterations: int = 12,
                   progress: Callable[[int, Iterate], None] | None = None) -> TuningResult:
    """Change ``parameters`` (``Scene.with_overrides`` names, real and non-zero) until the mode ``label`` (selected
    by label nearest the current frequency) lies within ``tol`` (relative) of ``target`` [Hz].

    Each iterate solves the 3-D solid near the tracked frequency (no error estimate), takes d ln f / d ln p of the
    mode (``frequency_sensitivities``) and steps ln p by the minimum-norm Gauss-Newton step for
    ln f(p) = ln target (Nocedal & Wright, Numerical Optimization, 2006, sec. 10.3), each relative change limited
    to ``MAX_RELATIVE_STEP`` and clipped to ``bounds`` (name -> (low, high)). Stops converged, or (not converged,
    with the reason) when the parameters sit on their bounds or the mode does not move, or after
    ``max_iterations`` solves."""
    names = list(dict.fromkeys(parameters))
    if not names or len(names) != len(parameters):
        raise SceneError("vary: give one or more distinct parameters")
    if not (math.isfinite(target) and target > 0):
        raise SceneError(f"target: must be a positive frequency in Hz, got {target}")
    if not (math.isfinite(tol) and 0 < tol < 0.5):
        raise SceneError(f"tol: must lie in (0, 0.5), got {tol}")
    check_parameters(scene, names)
    bounds = dict(bounds or {})
    unknown = sorted(set(bounds) - set(names))
    if unknown:
        raise SceneError(f"bounds: {unknown[0]} is not among the parameters varied {names}")
    iterates: list[Iterate] = []
    near = target
    for _ in range(max_iterations):
        start = time.perf_counter()
        modes = solve_modes(scene, near=near, count=TUNE_COUNT, fidelity="solid", error_estimate=False)
        try:
            mode = select(modes, label, near)
        except SolverError as exc:
            raise SolverError(f"tune: the mode {label} is not found near {near:.6g} Hz ({exc})") from None
        found = frequency_sensitivities(modes, names)
        row = [m.index for m in modes].index(mode.index)
        slope = found.relative[row]
        values = dict(zip(names, found.values.tolist()))
        for name, value in values.items():
            low, high = bounds.get(name, (-math.inf, math.inf))
            if value == 0 or not low <= value <= high:
                raise SceneError(f"{name}: {value:g} cannot be tuned (must be non-zero and within its bounds "
                                 f"{low:g}-{high:g})")
        iterate = Iterate(values, mode.frequency, dict(zip(names, slope.tolist())), time.perf_counter() - start)
        iterates.append(iterate)
        if progress is not None:
            progress(len(iterates), iterate)
        residual = math.log(mode.frequency / target)
        if abs(mode.frequency / target - 1) <= tol:
            return TuningResult(label, target, tol, tuple(iterates), True, "within tol", scene)
        if not np.all(np.isfinite(slope)) or float(slope @ slope) == 0:
            return TuningResult(label, target, tol, tuple(iterates), False,
                                "the mode does not move with these parameters", scene)
        step = -residual * slope / float(slope @ slope)  # min-norm d ln p
        step = np.clip(step, math.log(1 - MAX_RELATIVE_STEP), math.log(1 + MAX_RELATIVE_STEP))
        proposed = {}
        for (name, value), s in zip(values.items(), step):
            low, high = bounds.get(name, (-math.inf, math.inf))
            proposed[name] = float(np.clip(value * math.exp(s), low, high))  # ln |p| moves by s, the sign is kept
        if all(math.isclose(proposed[n], values[n], rel_tol=1e-12) for n in names):
            return TuningResult(label, target, tol, tuple(iterates), False,
                                "the parameters sit on their bounds", scene)
        scene = with_values(scene, proposed)
        near = mode.frequency * math.exp(float(slope @ step))  # where the mode should be now
    return TuningResult(label, target, tol, tuple(iterates), False, f"not within tol after {max_iterations} solves",
                        scene)
