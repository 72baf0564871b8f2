"""Tuning modes to target frequencies by changing scene parameters, with the modal sensitivities
(``modalfe.response.sensitivity``): 3-D solid solves and their sensitivities at each iterate, no finite differences.

Unknowns are x = ln |p| (a relative change of each parameter; signs are kept). At each iterate:

* targets: the residuals r_i = ln (f_i / target_i) and their Jacobian J_ij = d ln f_i / d ln p_j; the step is the
  minimum-norm least-squares (Gauss-Newton) step s = -J^+ r (Nocedal & Wright, Numerical Optimization, 2nd ed.
  2006, sec. 10.3). With fewer targets than parameters (one frequency, two dimensions) it is the least change in
  ln p that meets the linearised targets: the step lies in the row space of J, each ln p moving in proportion to its
  sensitivity, so a parameter the mode hardly feels hardly moves. With more targets than independent parameters it
  is the least-squares compromise; when that stops moving with a target still outside ``tol`` the run ends saying
  the targets cannot all be met.
* the resolved stage (``tune``): J is the last cheap iterate's, corrected after each resolved iterate by Broyden's
  rank-one update from the step taken and the residuals it changed (Broyden, Math. Comp. 19 (1965) 577; Nocedal &
  Wright sec. 11.1): the resolved model's slopes differ from the scene's own mesh's by a few per cent (Cu-Be plate
  (0,6): -1.35 against -1.38 for the length), which Newton's step tolerates, while its sensitivities cost most of
  a resolved iterate (17 of 23 s on the Cu-Be plate's 31k quartic DOFs). With ``separation`` the neighbours' rows
  are the resolved model's own sensitivities, as every row of the first stage.
* separation (``separation``): the first target's mode keeps |f_n - f_0| / f_0 >= separation from every other
  mode of its solve (the modes the model solves; the gap logged is the nearest's). Linearised in x,
  sigma (d_n + a_n s - ln(1 + sigma sep)) >= 0 with d_n = ln (f_n / f_0), a_n = J_n - J_0, sigma = +1 above,
  -1 below; active set, rebuilt at every iterate: a neighbour whose linearised separation the step would break
  joins the equality rows at its limit and the step is recomputed (Nocedal & Wright sec. 16.5).
* ``maximize="k_eff"``: the effective coupling of the first target's mode (open-circuit partner, Sensitivities.
  k_eff). The targets (and active separations) stay equality constraints: from a design that meets them, the
  gradient g = d ln k / d ln p projected onto the null space of the constraint rows, P g with P = I - A^+ A, is
  added to the restoring step over the trust radius (Rosen's gradient projection, J. SIAM 8 (1960) 181),
  parameters on a bound that g pushes outward held; from a design off them, the restoring step alone
  (restoration, Rosen, J. SIAM 9 (1961) 514). A design back on the targets with a lower k_eff than the best so
  far is rejected and the trust radius halved; the run ends when the predicted gain over the trust radius is
  below ``K_GAIN_TOL`` or the radius below ``MIN_RADIUS``.
* ``maximize=LeastVoltage(reduction, contact)``: the least drive voltage V = W_R(f) / A at which the contact
  model's friction reduction reaches ``reduction`` at the output that moves most (``reduce``'s reference), with A
  the amplitude per volt at resonance there and W_R(f) the amplitude the contact model needs at the mode's frequency
  f (``modalfe.contact.chain.amplitude_for``, the contact model's steady state). The same gradient projection
  maximizes -ln V, whose gradient is d ln A / d ln p (``amplitude_sensitivities``, the same two assemblies per
  parameter as the frequencies') less (d ln W_R / d ln f) (d ln f / d ln p). The first target is the objective's
  own mode, so its row d ln f / d ln p is a constraint row that the projection P removes: on the targets the
  contact model's frequency slope drops out and the ascent is P d ln A / d ln p exactly; W_R is evaluated at each
  design's own frequency for V. Off the targets, restoration alone (as for k_eff).
* ``maximize=ReductionAt(voltage, contact)``: the largest friction reduction R(W = V A, f) at the drive voltage V,
  same output and A; the gradient is (dR / d ln W)(d ln A / d ln p) (dR / d ln W by a central difference of the
  contact model's steady state, ``modalfe.design.outcome``), its frequency term removed by the same projection.
* mode bounds (``mode_bounds``, ``FrequencyBound``): a mode's frequency kept above (or below) a limit L, e.g. above
  the audible range, its stated error e included on the resolved model: f (1 - e) >= L (f (1 + e) <= L below), i.e.
  sigma (ln f - ln L + ln(1 - sigma e)) >= 0 (e taken as 0 where not estimated: the own mesh). The same linearised
  inequality rows and active set as the separation's (a row d + a s >= limit, here d = ln f, a = d ln f / d ln p);
  an active bound row is aimed ``BOUND_MARGIN`` inside its limit, so that a step's linearisation error leaves it
  met. On the resolved stage the bound's row is steered by Broyden's update with the targets' rows, and its mode is
  resolved only to ``BOUND_ROOM`` of the room its limit leaves where that is looser than the targets' tol.
* ``maximize=LargestArea(required, voltage, contact)``: the largest share of the touch surface reaching the
  reduction at the voltage, through its logistic smoothing and the amplitude sensitivities at the surface's points
  (``modalfe.design.outcome``), the same gradient projection; each iterate reports the true share.
* trust region: no parameter moves by more than ``tune_step.MAX_RELATIVE_STEP`` of itself (radius ln 1.2),
  then ``bounds``.
* the device holds together: a step whose scene the builder or the scene checks refuse (a ceramic or foot off
  the plate, parts apart) is halved until it is accepted, up to ``MAX_HALVINGS`` times, and the reason is logged.
* feet (``replace_feet``): after each solve the feet are moved to the in-phase antinodes nearest to them of the
  first target's mode of the device without feet (``modalfe.response.placement.feet_on_antinodes``, as
  ``place_feet`` does: across a (0,n) mode's ridges only), kept inside the plate; the run converges only once no
  foot moves by more than ``FOOT_TOL``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from modalfe.design.feet import feet_on_mode_antinodes, feet_text, has_feet, scene_feet
from modalfe.design.outcome import OUTCOME_OBJECTIVES, LargestArea, LeastVoltage, ReductionAt, outcome_at, touch_points
from modalfe.design.tune_checks import check_tune_inputs, check_variables
from modalfe.design.tune_step import Limit, Point, broyden, is_met, moved_frequencies, trust_step
from modalfe.errors import SceneError, SolverError
from modalfe.response.sensitivity import frequency_sensitivities, parameter_value, with_values
from modalfe.results.modes import select
from modalfe.solve.api import DEFAULT_TOL, solve_modes

TUNE_COUNT = 6  # modes asked of each solve around a target (enough to find it by label when neighbours move)
MAX_HALVINGS = 6  # a step the scene refuses is halved at most this often (down to 1/64)
# maximising k_eff: stop when the projected gradient promises less than 0.1 % of k_eff over the trust radius, or
# the radius has shrunk below 0.5 % of each parameter (the modal sensitivities' own error is ~1e-4 relative,
# sensitivity.RELATIVE_STEP, and a 0.1 % coupling gain is below what a prototype's scatter resolves)
K_GAIN_TOL = 1e-3
MIN_RADIUS = math.log(1.005)
# first trust radius of the k_eff ascent (a fraction of each parameter): an empirical choice, no independent source;
# a step of the full 20 % along the projected gradient lost the Cu-Be plate's (0,6) mode from the solve's window
# (docs/tuning.md), and the radius halves from here whenever a step loses k_eff or the targets
ASCENT_RADIUS = 0.05
# the second stage's model is resolved to this share of the targets' tol, so that at least the rest of it is left to
# the residual: resolved to tol itself, a stated error just under tol left the design no room (a bimorph's stated
# 0.499 % at tol 0.5 % asked a residual below 1e-5). A quarter of tol is room enough: one step of the second stage
# lands within 0.05 % of the target from 0.6-0.7 % off (the Cu-Be plate's (0,6), its feet moving meanwhile, and the
# ciliary beam's bending-z 6: docs/tuning.md), while half of tol asked the Cu-Be plate's 0.25 % at tol 0.5 %, three
# refinement steps (92k DOFs, ~60 s a solve) where its first (31k DOFs, 0.33-0.35 %) leaves 0.15 % to the residual
RESOLVED_SHARE = 0.75
# an active mode bound is aimed this share of tol inside its limit: a resolved step lands within 0.05 % of where it is
# aimed (docs/tuning.md), a quarter of the default tol (0.125 %) leaves that room more than twice over
BOUND_MARGIN = 0.25
# a bound's mode is resolved on the second stage only to this share of the room its limit leaves (where looser than
# the targets' tol): its stated error then takes at most half of that room, and a bound 14 % above its limit (the
# Cu-Be plate's (2,3) and 20 kHz) is shown met by the ladder's first rung instead of the targets' 0.375 %
# (stated 4.49 %; the run 54 s from an empty cache against 82 s, docs/tuning.md); capped at MAX_BOUND_TOL
BOUND_ROOM = 0.5
MAX_BOUND_TOL = 0.05


@dataclass(frozen=True)
class FrequencyBound:
    """A mode, by label, whose frequency stays at or above (``above``) or at or below ``frequency`` [Hz], its stated
    error included on the resolved model (module docstring)."""

    label: str
    frequency: float
    above: bool = True

    def describe(self) -> str:
        return f"{self.label} {'>=' if self.above else '<='} {self.frequency:g} Hz"

    def edge(self, frequency: float, error: float) -> float:
        """The frequency [Hz] the bound is held to: f (1 - e) above, f (1 + e) below; f where e is not estimated
        (NaN: the own mesh)."""
        e = 0.0 if math.isnan(error) else error
        return frequency * (1 - e) if self.above else frequency * (1 + e)

    def met(self, frequency: float, error: float) -> bool:
        """Whether a mode at ``frequency`` [Hz] with stated relative ``error`` keeps the bound (module docstring)."""
        edge = self.edge(frequency, error)
        return edge >= self.frequency if self.above else edge <= self.frequency


@dataclass(frozen=True)
class FrequencyTarget:
    """A mode, by label (``(0,6)``, ``bending-z 6``, a family ``(0,n)``), and its target frequency [Hz]."""

    label: str
    frequency: float


@dataclass(frozen=True)
class Iterate:
    """One evaluated design: parameter values [their units]; each target mode's frequency [Hz] and
    d ln f / d ln p; k_eff of the first target's mode (NaN unless maximizing); the smallest relative distance
    of that mode to its neighbours (NaN when not asked); the feet (x, y) [m] it was solved with (empty when not
    re-placed); eigen solves and seconds spent; whether it was kept (a k_eff step may be rejected); notes
    (steps shortened, feet moved, rejection)."""

    values: dict[str, float]
    frequencies: tuple[float, ...]
    relative_sensitivity: tuple[dict[str, float], ...]
    k_eff: float
    separation: float
    feet: tuple[tuple[float, float], ...]
    solves: int
    seconds: float
    accepted: bool = True
    notes: tuple[str, ...] = ()
    errors: tuple[float, ...] = ()  # each target mode's stated relative error (NaN: not estimated, own mesh)
    resolved: bool = False  # solved on the resolved model (``tune``'s second stage), else the scene's own mesh
    # an outcome objective (``modalfe.design.outcome``): the voltage it asks of this design (``LeastVoltage``) or
    # is given (``ReductionAt``) [V], A at the output that moves most [m/V, 0-peak], that output, the reduction at
    # that voltage and the merit maximized (NaN, "": not such an objective)
    volts: float = math.nan
    amplitude_per_volt: float = math.nan
    output: str = ""
    sought: tuple[float, ...] = ()  # the frequencies [Hz] each target's mode was sought near
    reduction: float = math.nan
    outcome_merit: float = math.nan
    area: float = math.nan  # ``LargestArea``: the true share of the touch surface reaching the reduction
    # ``mode_bounds``: each bound mode's frequency [Hz], stated relative error (NaN: not estimated) and d ln f / d ln p
    bounded: tuple[float, ...] = ()
    bound_errors: tuple[float, ...] = ()
    bound_sensitivity: tuple[dict[str, float], ...] = ()

    @property
    def merit(self) -> float:
        """What a maximizing run maximizes: ln k_eff, or an outcome objective's merit (-ln V for ``LeastVoltage``,
        the reduction for ``ReductionAt``, the smoothed share for ``LargestArea``; NaN: neither)."""
        return math.log(self.k_eff) if math.isfinite(self.k_eff) else self.outcome_merit


@dataclass(frozen=True)
class TuningResult:
    """The iterates, whether the final design meets the targets (and, maximizing, the optimality test), why the
    run ended, and the final design: its scene and its iterate."""

    targets: tuple[FrequencyTarget, ...]
    tol: float
    iterates: tuple[Iterate, ...]
    converged: bool
    reason: str
    scene: object
    final: Iterate  # the design in ``scene``
    maximize: str | LeastVoltage | ReductionAt | LargestArea | None = None
    mode_bounds: tuple[FrequencyBound, ...] = ()
    # an outcome objective: the chain (``modalfe.contact.chain.haptic_chain``) at the final design on the resolved
    # model: for ``LeastVoltage`` the voltage for the required reduction (``VoltageFor``), and the outcome
    # (``Outcome``) at that voltage or at ``ReductionAt``'s; for ``LargestArea`` the haptic map there (``HapticMap``)
    verified: object = None
    outcome: object = None

    @property
    def solves(self) -> int:
        return sum(it.solves for it in self.iterates)

    @property
    def seconds(self) -> float:
        return sum(it.seconds for it in self.iterates)

    @property
    def first_on_target(self) -> Iterate | None:
        """The first kept iterate within ``tol`` of every target (the reference of a k_eff gain), if any."""
        return next((it for it in self.iterates if it.accepted and all(
            abs(f / t.frequency - 1) <= self.tol for f, t in zip(it.frequencies, self.targets))), None)

    @property
    def residual(self) -> float:
        """Largest |f / target - 1| of the final design."""
        return max(abs(f / t.frequency - 1) for f, t in zip(self.final.frequencies, self.targets))


def tune(scene, targets: Sequence[FrequencyTarget], parameters: Sequence[str], *, tol: float = DEFAULT_TOL,
         bounds: Mapping[str, tuple[float, float]] | None = None,
         maximize: str | LeastVoltage | ReductionAt | LargestArea | None = None, separation: float | None = None,
         replace_feet: bool = False, max_iterations: int = 12,
         progress: Callable[[int, Iterate], None] | None = None, resolution: Mapping | None = None,
         mode_bounds: Sequence[FrequencyBound] = ()) -> TuningResult:
    """Change ``parameters`` (``frequency_sensitivities`` names, real and non-zero) until every target mode lies
    within ``tol`` (relative) of its frequency, optionally maximizing k_eff of the first (``maximize="k_eff"``),
    minimizing the voltage for a friction reduction (``maximize=LeastVoltage(...)``) or maximizing the reduction at a
    voltage (``maximize=ReductionAt(...)``) or the share of the touch surface reaching a reduction
    (``maximize=LargestArea(...)``), keeping ``mode_bounds`` (each mode's frequency above or below a limit, its stated
    error included on the resolved model) and keeping its
    ``separation`` from its neighbours and its feet on its antinodes (module docstring). ``bounds``: name ->
    (low, high) [its unit]. ``progress(k, iterate)`` after each evaluation (kept or rejected).

    Two stages: iterates on the scene's own mesh (cheap, no error estimate) until the targets are met there or,
    without ``maximize`` and ``separation``, a step is predicted (linearly, not cut by the trust region or the bounds)
    to meet them: the design that step reaches is not solved on the own mesh, whose answer differs from the resolved
    model's by more than that prediction's error anyway (Cu-Be plate (0,6): 0.5 % against 0.15 %); feet moved at the
    last iterate are carried over (the second stage converges only once they stay). Then, from that design, it
    iterates on the resolved model (the answer ``modes`` gives for each target mode at ``resolution``:
    ``solve_modes``' tol, fidelity, error_estimate; tol default ``RESOLVED_SHARE`` x ``tol``), steered by the first
    stage's Jacobian (module docstring), until every target is met within ``tol`` *including* its mode's stated
    error; only then converged. ``tol`` defaults to every command's (``DEFAULT_TOL``). ``max_iterations``
    evaluations at most in each stage. With ``LeastVoltage`` the final design's chain is built on the resolved model
    (``haptic_chain``, the first target's mode at ``resolution``) and its voltage for the reduction and outcome
    there are the result's ``verified`` and ``outcome``, with their stated errors; with ``LargestArea`` the haptic
    map of the final design's resolved mode is ``verified``."""
    targets = tuple(targets)
    names = list(dict.fromkeys(parameters))
    mode_bounds = tuple(mode_bounds)
    check_tune_inputs(scene, targets, list(parameters), tol, bounds, maximize, separation, replace_feet, mode_bounds)
    options = {"targets": targets, "names": names, "tol": tol, "bounds": dict(bounds or {}),
               "separation": separation, "replace_feet": replace_feet, "max_iterations": max_iterations,
               "mode_bounds": mode_bounds}
    cheap = _descend(scene, maximize=maximize, resolved=None, progress=progress, **options)
    if not cheap.converged:
        return replace(cheap, reason=f"{cheap.reason} (on the scene's own mesh, before the resolved model)")
    done = len(cheap.iterates)

    def onward(k: int, it: Iterate) -> None:
        if progress is not None:
            progress(done + k, it)

    resolved = {"tol": RESOLVED_SHARE * tol, **(resolution or {})}
    rows = cheap.final.relative_sensitivity + cheap.final.bound_sensitivity
    checked = _descend(cheap.scene, maximize=None, resolved=resolved, progress=onward,
                       jacobian=np.array([[row[n] for n in names] for row in rows]), sought=cheap.final.bounded,
                       **options)
    reason = (f"{checked.reason} on the model resolved to {100 * resolved['tol']:.3g} % (modes --tol "
              f"{resolved['tol']:g}), stated error included")
    if maximize:
        reason += f"; {_goal(maximize)} on the scene's own mesh ({cheap.reason})"
    result = replace(checked, iterates=cheap.iterates + checked.iterates, reason=reason, maximize=maximize,
                     mode_bounds=mode_bounds)
    if isinstance(maximize, OUTCOME_OBJECTIVES):
        from modalfe.contact.chain import haptic_chain, haptic_map

        question = {"selector": targets[0].label, "near": result.final.sought[0], **resolved}
        if isinstance(maximize, LargestArea):
            outputs, points, weights, grid = touch_points(result.scene, maximize)
            if grid:  # the chain read at the point that moved most on the last own-mesh design (its stated error
                # there), not at the scene's outputs: a fixed point of those may lie off the tuned device
                question["outputs"] = [o for o in outputs if o[0] == cheap.final.output]
        chain = haptic_chain(result.scene, maximize.contact, **question)  # the final iterate's solve, read back
        if isinstance(maximize, LargestArea):
            hmap = haptic_map(chain, points, maximize.voltage, weights=weights)
            result = replace(result, verified=hmap, outcome=chain.outcome(maximize.voltage))
        elif isinstance(maximize, LeastVoltage):
            verified = chain.voltage_for(maximize.reduction)
            result = replace(result, verified=verified, outcome=chain.outcome(verified.voltage))
        else:
            result = replace(result, outcome=chain.outcome(maximize.voltage))
    return result


def _goal(maximize: str | LeastVoltage | ReductionAt | LargestArea) -> str:
    """What a maximizing run does, in words."""
    if isinstance(maximize, LargestArea):
        return "the smoothed area reaching the reduction maximized"
    if isinstance(maximize, ReductionAt):
        return "the reduction at the voltage maximized"
    return "k_eff maximized" if maximize == "k_eff" else "the voltage for the reduction minimized"


def _descend(scene, *, targets, names, tol, bounds, maximize, separation, replace_feet, max_iterations, progress,
             resolved: Mapping | None, mode_bounds=(), jacobian: np.ndarray | None = None,
             sought: Sequence[float] | None = None) -> TuningResult:
    """One stage of ``tune``: its iterates from ``scene``, each solved on the scene's own mesh (``resolved`` None) or
    on the model resolved at ``resolved`` (``solve_modes`` keywords). ``jacobian`` (targets x parameters,
    d ln f / d ln p, then a row per mode bound): the resolved stage's first, Broyden-updated after each iterate
    instead of the resolved model's sensitivities (not with ``separation``: module docstring). A first stage that
    ends on a step predicted to meet the targets returns the design that step reaches as its ``scene`` (unsolved),
    with the iterate it was taken from. ``sought``: where the bound modes are first sought (default their limits;
    the resolved stage: where the first stage found them)."""
    low = np.array([bounds.get(n, (-math.inf, math.inf))[0] for n in names])
    high = np.array([bounds.get(n, (-math.inf, math.inf))[1] for n in names])
    iterates: list[Iterate] = []
    radius = math.log1p(ASCENT_RADIUS)
    near = [t.frequency for t in targets] + list(sought or [b.frequency for b in mode_bounds])
    notes: list[str] = []
    kept: Point | None = None  # the point the next step starts from
    best: Point | None = None  # maximizing: the point on the targets with the highest merit so far

    def finish(converged: bool, reason: str, ahead=None) -> TuningResult:
        # maximizing and stopped early: the best design on the targets, not the last one off them
        final = best if best is not None and not converged else kept
        if final is not kept:
            reason += "; the best design on the targets kept"
        broken = [f"{b.describe()} at {f:.6g} Hz" for b, f, e in zip(mode_bounds, final.iterate.bounded,
                                                                      final.iterate.bound_errors) if not b.met(f, e)]
        if broken and not converged:  # what the run could not do, beside why it stopped
            reason += f"; mode bounds not met: {', '.join(broken)}"
        return TuningResult(targets, tol, tuple(iterates), converged, reason,
                            final.scene if ahead is None else ahead, final.iterate, maximize, mode_bounds)

    def record(it: Iterate) -> None:
        iterates.append(it)
        if progress is not None:
            progress(len(iterates), it)

    x = taken = np.zeros(len(names))  # the kept design's values and the last step from it (ln |p|)
    base = scene  # the kept design's scene the last step was taken from (its feet re-placed)
    steer = jacobian if resolved is not None and separation is None else None
    for _ in range(max_iterations):
        try:
            point = _evaluate(scene, targets, names, near, maximize, separation, replace_feet, notes, resolved,
                              steer, mode_bounds, tol)
        except SolverError as exc:  # a target mode lost after a step: the step halved, from the kept design
            if kept is None or not np.any(taken):
                raise
            taken = taken / 2
            radius /= 2
            scene = with_values(base, dict(zip(names, (x * np.exp(taken)).tolist())))
            near = moved_frequencies(kept, taken)
            notes = [f"step halved: {exc}"]
            continue
        notes = []
        if steer is not None and kept is not None and kept.placed is None:  # the same feet: the step alone moved r
            steer = broyden(steer, np.log(np.array(list(point.iterate.values.values())) / x), point.lnf - kept.lnf)
            n = len(targets)
            point.J = steer[:n]
            point.bounds = [replace(b, a=row) for b, row in zip(point.bounds, steer[n:])]
            point.iterate = replace(point.iterate, relative_sensitivity=tuple(
                dict(zip(names, row.tolist())) for row in steer[:n]), bound_sensitivity=tuple(
                dict(zip(names, row.tolist())) for row in steer[n:]))
        x = np.array(list(point.iterate.values.values()))
        met = is_met(point, tol)
        if maximize and met and best is not None and point.iterate.merit < best.iterate.merit:
            record(replace(point.iterate, accepted=False, notes=(
                *point.iterate.notes, f"rejected: {_worse(point.iterate, best.iterate)}; trust radius halved")))
            radius /= 2
            point = kept = best
            x = np.array(list(point.iterate.values.values()))
        else:
            record(point.iterate)
            kept = point
            if maximize and met:
                best = point
        unverifiable = [f"{t.label} {100 * e:.3g} %" for t, e in zip(targets, point.iterate.errors)
                        if not (math.isnan(e) or e < tol)]
        if resolved is not None and unverifiable:  # inf or >= tol: no design can be shown within tol
            return finish(False, f"the resolved model's stated error is not below tol ({', '.join(unverifiable)}): "
                                 f"no design can be verified within {100 * tol:.3g} %; loosen --tol")
        unbounded = [f"{b.label} {100 * e:.3g} %" for b, e in zip(mode_bounds, point.iterate.bound_errors)
                     if not (math.isnan(e) or e < 1)]
        if unbounded:  # f (1 - e) with e >= 1 (or inf) shows no frequency above any limit
            return finish(False, f"the resolved model's stated error of a bound mode is 100 % or more "
                                 f"({', '.join(unbounded)}): its bound cannot be verified")
        ascend = bool(maximize) and met  # the ascent only from a point on the targets (restoration first)
        step, ascent = trust_step(point, radius if ascend else 0.0, x, low, high)
        moved = point.placed is not None
        if met and not moved:
            if not maximize:
                return finish(True, "within tol")
            if radius < MIN_RADIUS:
                return finish(True, "within tol; the trust region can no longer improve the objective")
            # predicted gain in the merit (ln k_eff, -ln V) of a step of max-norm ``radius`` along P g
            if radius * float(ascent @ ascent) / max(float(np.max(np.abs(ascent))), 1e-300) < K_GAIN_TOL:
                return finish(True, "within tol; the objective's projected gradient is small")
        if not np.all(np.isfinite(point.J)) or not np.any(point.J):
            return finish(False, "the modes do not move with these parameters")
        proposed = np.clip(x * np.exp(step), low, high)
        # stalled: off the targets (or the separation or a bound), and the step would move no target frequency nor
        # neighbour distance nor bound mode by a tenth of the room left within ``tol``
        rows = np.vstack([point.J] + [lim.a[None, :] for lim in point.limits])
        # the room a target has is tol less its stated error (on the resolved model)
        room = tol - max((e for e in point.iterate.errors if not math.isnan(e)), default=0.0)
        moves = float(np.max(np.abs(rows @ np.log(proposed / x))))
        if not moved and not ascend and moves < 0.1 * room:
            if np.any((x <= low) | (x >= high)):
                return finish(False, "the parameters sit on their bounds")
            # the figures that say why: a frequency that hardly feels its parameters (the ciliary beam's bending-z 6
            # and the sheets' position x0, stationary at the default) cannot be moved far by any step
            slopes = "; ".join(f"{t.label}: " + ", ".join(f"{n} {d:+.3g}" for n, d in zip(names, row))
                               for t, row in zip(targets, point.J))
            also = (" and the separation" if separation else "") + (" and the mode bounds" if mode_bounds else "")
            return finish(False, f"the targets{also} cannot all be met "
                                 f"with these parameters ({len(targets)} targets, {len(names)} parameters: the "
                                 f"least-squares step would move them by {100 * moves:.2g} % with "
                                 f"{100 * float(np.max(np.abs(np.expm1(point.r)))):.3g} % to go; d ln f / d ln p "
                                 f"{slopes})")
        base = point.scene
        if moved:
            base = base.with_overrides(feet=point.placed)
            notes.append("feet moved to the antinodes: " + feet_text(point.placed))
        scene, fraction, why = _feasible(base, names, x, proposed)
        if scene is None:
            return finish(False, f"no step is accepted by the scene: {why}")
        if fraction < 1:
            notes.append(f"step shortened to {fraction:g} of itself: {why}")
        taken = fraction * np.log(proposed / x)
        near = moved_frequencies(point, taken)
        if resolved is None and not maximize and separation is None and \
                np.all(np.abs(np.expm1(point.r + point.J @ taken)) <= tol) and \
                all(b.sigma * (b.d + b.a @ taken - b.limit) >= 0 for b in point.bounds):
            # the step is predicted to meet the targets: the resolved stage evaluates the design it reaches (feet
            # moved included), whose own-mesh solve would only be discarded
            return finish(True, "a step predicted within tol", ahead=scene)
    if best is not None:
        return finish(False, f"the objective not at its optimum after {max_iterations} evaluations")
    return finish(False, f"not within tol after {max_iterations} evaluations")


def _bound_question(resolved: Mapping, bound: FrequencyBound, near: float) -> dict:
    """``resolved`` for a bound's mode sought near ``near`` [Hz]: resolved only to ``BOUND_ROOM`` of the room its
    limit leaves (the largest stated error e that keeps it met: 1 - L / f above, L / f - 1 below), when that is looser
    than the targets' tol; a bound close to its limit (or broken) gets the targets' own."""
    room = 1 - bound.frequency / near if bound.above else bound.frequency / near - 1
    tol = resolved.get("tol", DEFAULT_TOL)
    return {**resolved, "tol": max(tol, min(BOUND_ROOM * room, MAX_BOUND_TOL))}


def _worse(it: Iterate, best: Iterate) -> str:
    """Why a maximizing iterate on the targets is rejected."""
    if math.isfinite(it.k_eff):
        return f"k_eff {it.k_eff:.5f} is below the best {best.k_eff:.5f}"
    if math.isfinite(it.area):  # ``LargestArea``
        return f"the smoothed area {it.outcome_merit:.4%} is below the best {best.outcome_merit:.4%}"
    if it.outcome_merit == it.reduction:  # ``ReductionAt``
        return f"the reduction {it.reduction:.4%} is below the best {best.reduction:.4%}"
    return f"{it.volts:.4g} V is above the best {best.volts:.4g} V"


def _evaluate(scene, targets, names, near, maximize, separation, replace_feet, notes, resolved=None,
              jacobian=None, mode_bounds=(), tol: float = DEFAULT_TOL) -> Point:
    """Solve ``scene`` near each target (maximizing k_eff, the open circuit of the same model beside the first): on
    its own mesh, where one solve serves every target inside its span of modes, or, with ``resolved``
    (``solve_modes`` keywords), each target on the model ``modes`` resolves that mode on; take the sensitivities
    (``jacobian`` given: its rows instead, no sensitivities, no ``maximize`` nor ``separation``; an outcome objective:
    the first target's with its amplitude's, ``modalfe.design.outcome.outcome_at``), re-place the feet
    (``replace_feet``: a solve without feet, ``modalfe.design.feet.feet_on_mode_antinodes``) and build the iterate.
    Each of ``mode_bounds`` is a mode sought and solved as a target is (the target's own when it has its label), near
    its entry of ``near`` after the targets'."""
    from modalfe.solve.api import open_circuit_modes, solid_modes, working_question

    need_k = maximize == "k_eff"
    wanted = maximize if isinstance(maximize, OUTCOME_OBJECTIVES) else None
    felt = None  # ``outcome_at`` of the first target's mode
    g = None
    start = time.perf_counter()
    solves: list = []  # (modes, Sensitivities)
    rows, found = [], []
    extra = 0
    labels = [t.label for t in targets] + [b.label for b in mode_bounds]
    for i, (label, f) in enumerate(zip(labels, near)):
        if label in labels[:i]:  # a bound on a target's mode: that mode
            rows.append(rows[labels.index(label)])
            found.append(found[labels.index(label)])
            continue
        # on the own mesh a solve serves every mode inside its span, and a bound's mode wherever it has that label;
        # resolved: each mode's own question
        use = next((k for k, (modes, _) in enumerate(solves)
                    if resolved is None and (modes.frequencies.min() <= f <= modes.frequencies.max()
                                             or (i >= len(targets) and any(m.label == label for m in modes)))), None)
        if use is None:
            if resolved is None:
                modes = solve_modes(scene, near=f, count=TUNE_COUNT, fidelity="solid", error_estimate=False)
            else:
                # the question ``modes`` and ``forced`` ask about that mode (the scene's count around it): the
                # chain's verification of a ``LeastVoltage`` run reads this answer back instead of solving again
                ask = resolved if i < len(targets) else _bound_question(resolved, mode_bounds[i - len(targets)], f)
                modes = solid_modes(scene, needs="tune", **working_question(scene, label, f), **ask)
            open_modes = None
            if need_k and i == 0:
                open_modes = open_circuit_modes(modes, near=f, count=TUNE_COUNT)
                extra = 1
            if jacobian is not None:
                sens = None
            elif wanted is not None and i == 0:
                felt = outcome_at(scene, modes, label, f, names, wanted)
                g, sens = felt.gradient, felt.sensitivities
            else:
                sens = frequency_sensitivities(modes, names, open_modes=open_modes)
            solves.append((modes, sens))
            use = len(solves) - 1
        modes, sens = solves[use]
        try:
            mode = select(modes, label, f)
        except SolverError as exc:
            raise SolverError(f"tune: the mode {label} is not found near {f:.6g} Hz ({exc})") from None
        row = [m.index for m in modes].index(mode.index)
        rows.append(sens.relative[row] if sens is not None else jacobian[i])
        found.append((mode, row, sens))
    n = len(targets)
    J = np.array(rows[:n])
    frequencies = tuple(float(mode.frequency) for mode, _, _ in found[:n])
    r = np.log(np.array(frequencies) / np.array([t.frequency for t in targets]))
    _, row0, sens0 = found[0]
    k = math.nan
    if need_k:
        k = float(sens0.k_eff[row0])
        if not (math.isfinite(k) and k > 0):
            raise SolverError(f"tune: k_eff of {targets[0].label} cannot be computed (no open-circuit mode alike "
                              f"in shape)")
        g = sens0.dk_eff[row0] * sens0.values / k  # d ln k / d ln p
    neighbours, gap = [], math.nan
    if separation is not None:
        f = sens0.frequencies
        elastic = [j for j in range(len(f)) if j != row0 and np.all(np.isfinite(sens0.relative[j]))]
        for j in elastic:  # every mode of the solve: one farther away may come closer faster than the nearest
            sigma = 1 if f[j] > f[row0] else -1
            edge = math.log1p(sigma * separation)  # met to tol / 2 of a frequency (``_met``), aimed at the limit
            neighbours.append(Limit(sigma, math.log(f[j] / f[row0]), sens0.relative[j] - sens0.relative[row0], edge,
                                     tol / 2, edge))
        gap = min((abs(math.expm1(lim.d)) for lim in neighbours), default=math.nan)
    limits, bounded, bound_errors = [], [], []
    for b, (mode, _, _), row in zip(mode_bounds, found[n:], rows[n:]):
        sigma, e = (1 if b.above else -1), float(mode.error_estimate)
        e = 0.0 if math.isnan(e) else e  # not estimated (the own mesh): the frequency as it is
        edge = math.log(b.frequency) - (math.log1p(-sigma * e) if sigma * e < 1 else -math.inf)
        limits.append(Limit(sigma, math.log(mode.frequency), np.asarray(row), edge, 0.0,
                             edge + sigma * math.log1p(BOUND_MARGIN * tol)))
        bounded.append(float(mode.frequency))
        bound_errors.append(float(mode.error_estimate))
    placed = None
    if replace_feet:
        # sought near the target, not this design's frequency: a design whose plate the feet were placed on last asks
        # the same question and reads the answer back (the resolved stage's first iterate)
        placed = feet_on_mode_antinodes(scene, targets[0].label, targets[0].frequency)
        extra += 1
    values = sens0.values if sens0 is not None else np.array([parameter_value(scene, n) for n in names])
    iterate = Iterate(dict(zip(names, values.tolist())), frequencies,
                      tuple(dict(zip(names, row.tolist())) for row in J), k, gap,
                      scene_feet(scene) if has_feet(scene) else (), len(solves) + extra, time.perf_counter() - start,
                      True, tuple(notes), tuple(float(mode.error_estimate) for mode, _, _ in found[:n]),
                      resolved is not None, sought=tuple(near))
    if felt is not None:
        iterate = replace(iterate, volts=felt.volts, amplitude_per_volt=felt.amplitude_per_volt, output=felt.output,
                          reduction=felt.reduction, outcome_merit=felt.merit, area=felt.area)
    if mode_bounds:
        iterate = replace(iterate, bounded=tuple(bounded), bound_errors=tuple(bound_errors),
                          bound_sensitivity=tuple(dict(zip(names, np.asarray(row).tolist())) for row in rows[n:]))
    return Point(scene, iterate, r, J, neighbours, g, placed, limits)


def _feasible(scene, names, x, proposed) -> tuple[object | None, float, str]:
    """The scene at ``proposed`` (values of ``names``), or, where the builder or the scene checks refuse it or a
    change of a parameter by ``PROBE_STEP`` (``check_variables``: a part off its support, parts apart), at the step
    from ``x`` halved until accepted (``MAX_HALVINGS``):
    (scene or None, fraction of the step taken, the last refusal)."""
    why = ""
    for halvings in range(MAX_HALVINGS + 1):
        fraction = 0.5**halvings
        values = proposed if halvings == 0 else x * (proposed / x) ** fraction  # exactly on a bound when clipped
        try:
            moved = with_values(scene, dict(zip(names, values.tolist())))
            check_variables(moved, names)  # its sensitivities can be taken (no part at the edge of its support)
            return moved, fraction, why
        except SceneError as exc:
            why = str(exc)
    return None, 0.0, why
