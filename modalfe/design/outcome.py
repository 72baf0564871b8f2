"""The felt outcome as a tuning objective (the method in ``modalfe.design.tuning``'s module docstring):

* ``LeastVoltage``: the least drive voltage for a required friction reduction, V = W_R(f) / A, maximized as -ln V
  with the gradient d ln A / d ln p (the contact model's frequency term drops out on the targets);
* ``ReductionAt``: the largest friction reduction at a given drive voltage V, R(W = V A, f), maximized as R with the
  gradient (dR / d ln W)(d ln A / d ln p); dR / d ln W by a central difference of the contact model's steady state
  (``REDUCTION_STEP``), exact to O(h^2) on the foot's periodic orbit;
* ``LargestArea``: the largest share of the touch surface (``touch_points``: the main part's top face for a finger,
  the feet for a foot) whose reduction reaches ``required`` at the drive voltage V. The share itself is a step
  function of the design; the merit is its logistic smoothing S = sum_i w_i sigma((R_i - required) / width) /
  sum_i w_i, sigma(z) = 1 / (1 + e^-z), with R_i = R(V A_i, f) the haptic map's (``modalfe.contact.chain.
  contact_map``: the contact model tabulated and interpolated linearly) and A_i the amplitude per volt at point i;
  its gradient dS / d ln p = sum_i w_i sigma'(z_i) / width (dR / dW)_i V dA_i / d ln p / sum_i w_i, dR / dW the
  map's interpolant's slope (``HapticMap.reduction_slope``), dA_i / d ln p from ``amplitude_sensitivities`` at every
  point (the same two assemblies per parameter; the grid's points read where they sit in the mesh, moving with it,
  as the grid scales with its face). The true share (the map's ``area_fraction``, unsmoothed) is reported beside it.

``outcome_at`` evaluates either at one design from the amplitude sensitivities of its mode (``OutcomeAt``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from modalfe.errors import SceneError, SolverError
from modalfe.results.modes import select

# relative amplitude step of dR / d ln W's central difference: the reduction of the foot model is smooth in W (a
# periodic orbit), its truncation error h^2 R''' / 6 ~ 2e-7 of the slope; a time-averaged finger state's noise
# (its standard error, ~1e-3) divided by 2 h would swamp the slope there: ``ReductionAt`` is meant for the foot
REDUCTION_STEP = 1e-3


@dataclass(frozen=True)
class LeastVoltage:
    """The objective "the least drive voltage for a required friction reduction" (module docstring): reduction
    (a fraction in (0, 1)) and the contact model (``modalfe.contact.chain.FootContact`` or ``FingerContact``, its
    preload and speed; the drive frequency and the number of feet are set at each design)."""

    reduction: float
    contact: object

    def describe(self) -> str:
        return f"the voltage for a {self.reduction:.2%} friction reduction ({self.contact.describe()})"


@dataclass(frozen=True)
class ReductionAt:
    """The objective "the largest friction reduction at a drive voltage" (module docstring): voltage [V] and the
    contact model (as ``LeastVoltage``'s)."""

    voltage: float
    contact: object

    def describe(self) -> str:
        return f"the friction reduction at {self.voltage:g} V ({self.contact.describe()})"


# the logistic's width in reduction (a fraction): 0.02, two points of reduction, a tenth of a required 20 %: a map
# point within 4 points of the required reduction (|z| < 2) carries gradient, one farther off hardly any (sigma' <
# 0.1 of its peak), and the smoothed share differs from the true one only by the points within that band
AREA_WIDTH = 0.02
AREA_POINTS = 400  # points of the touch surface's grid, as ``finger --map``'s default


@dataclass(frozen=True)
class LargestArea:
    """The objective "the largest share of the touch surface reaching a friction reduction" (module docstring):
    required reduction (a fraction in (0, 1)), drive voltage [V], the contact model (as ``LeastVoltage``'s), the
    logistic's width (a fraction of reduction) and the touch surface's grid points (a finger's)."""

    required: float
    voltage: float
    contact: object
    width: float = AREA_WIDTH
    points: int = AREA_POINTS

    def describe(self) -> str:
        return (f"the area reaching a {self.required:.2%} friction reduction at {self.voltage:g} V (smoothed over "
                f"{self.width:g} of reduction; {self.contact.describe()})")


OUTCOME_OBJECTIVES = (LeastVoltage, ReductionAt, LargestArea)


@dataclass(frozen=True)
class OutcomeAt:
    """An outcome objective at one design: volts [V] (asked by ``LeastVoltage``, given by ``ReductionAt`` and
    ``LargestArea``), the amplitude per volt A [m/V, 0-peak] at ``output`` (``LargestArea``: the touch point that
    moves most), the reduction reached at that voltage (``LargestArea``: its area-weighted mean over the touch
    surface), the merit maximized (-ln V, R or the smoothed share), its gradient d merit / d ln p on the parameters,
    and every mode's ``Sensitivities``."""

    volts: float
    amplitude_per_volt: float
    output: str
    reduction: float
    merit: float
    gradient: np.ndarray
    sensitivities: object
    area: float = math.nan  # ``LargestArea``: the true (unsmoothed) share of the surface reaching the reduction


def touch_points(scene, objective: LargestArea) -> tuple[list, np.ndarray, np.ndarray, bool]:
    """(outputs, their points (n, 3) [m], area weights, whether they are a grid of the surface) of ``objective``'s
    touch surface: for a finger
    the main part's top face (``contact.chain.surface_points``, as ``finger --map``), its points as outputs
    (``("touch_i", (x, y, z))``); for a foot the scene's ``foot*`` outputs, equal weights (as ``friction --map``).
    SceneError naming ``objective`` where the scene has none (before any solve)."""
    from modalfe.contact.chain import FingerContact, foot_outputs, surface_points

    if isinstance(objective.contact, FingerContact):
        try:
            points, weights = surface_points(scene, count=objective.points)
        except SceneError as exc:
            raise SceneError(f"objective: the scene '{scene.name}' has no touch surface for the area (the main part's "
                             f"top face: {exc})") from None
        return [(f"touch_{i}", tuple(p)) for i, p in enumerate(points.tolist())], points, weights, True
    feet = foot_outputs(scene.drive.outputs)
    if not feet:
        raise SceneError(f"objective: the scene '{scene.name}' has no touch surface for the area with contact=foot "
                         f"(no foot* outputs in drive.outputs); contact=finger maps the main part's top face")
    from modalfe.response.loads import output_points

    return feet, np.array(list(output_points(scene, feet).values())), np.ones(len(feet)), False


def outcome_at(scene, modes, label: str, near: float, names, objective: LeastVoltage | ReductionAt | LargestArea
               ) -> OutcomeAt:
    """``objective`` at one design (module docstring), from ``amplitude_sensitivities`` of the mode ``label`` at
    the scene's outputs with its damping (the materials', as ``forced``), read at the output that moves most
    (``reduce``'s reference rule: the first of equals), and the contact model at the mode's frequency (its feet the
    outputs' ``foot*``): ``amplitude_for`` for ``LeastVoltage``, its steady state for ``ReductionAt``."""
    from modalfe.contact.chain import amplitude_for, feet_among
    from modalfe.response.forced import REFERENCE_TIE
    from modalfe.response.losses import mode_damping, resolve_losses
    from modalfe.response.sensitivity import amplitude_sensitivities

    try:
        mode = select(modes, label, near)
    except SolverError as exc:
        raise SolverError(f"tune: the mode {label} is not found near {near:.6g} Hz ({exc})") from None
    outputs = tuple(scene.drive.outputs)
    damping, _ = mode_damping(mode, resolve_losses(scene))
    if isinstance(objective, LargestArea):
        return _area_at(scene, modes, mode, names, objective, damping)
    amp = amplitude_sensitivities(modes, names, mode=mode, outputs=outputs, damping=damping)
    o = next(i for i, a in enumerate(amp.amplitude) if a >= (1 - REFERENCE_TIE) * amp.amplitude.max())
    A, dlnA = float(amp.amplitude[o]), amp.relative[o]
    contact = objective.contact.tuned(mode.frequency, feet_among(outputs))
    if isinstance(objective, LeastVoltage):
        volts = amplitude_for(contact, objective.reduction) / A
        return OutcomeAt(volts, A, amp.outputs[o], objective.reduction, -math.log(volts), dlnA, amp.modal)
    W = objective.voltage * A
    reduction = contact.state(W).reduction
    up, down = (contact.state(W * (1 + s * REDUCTION_STEP)).reduction for s in (1, -1))
    slope = (up - down) / math.log((1 + REDUCTION_STEP) / (1 - REDUCTION_STEP))  # dR / d ln W
    return OutcomeAt(objective.voltage, A, amp.outputs[o], reduction, reduction, slope * dlnA, amp.modal)


def _area_at(scene, modes, mode, names, objective: LargestArea, damping) -> OutcomeAt:
    """``LargestArea`` at one design (module docstring): the map at the touch surface's points from their amplitudes
    per volt and their derivatives; the map's largest amplitude and its output stand for A and the output."""
    from modalfe.contact.chain import contact_map, feet_among
    from modalfe.response.sensitivity import amplitude_sensitivities

    outputs, points, weights, grid = touch_points(scene, objective)
    amp = amplitude_sensitivities(modes, names, mode=mode, outputs=outputs, damping=damping, material_points=grid)
    contact = objective.contact.tuned(mode.frequency, None if grid else feet_among(outputs))
    V = objective.voltage
    hmap = contact_map(contact, mode.frequency, points, V, V * amp.amplitude, 0.0, weights=weights)
    w = weights / weights.sum()
    sigma = 1 / (1 + np.exp(-(hmap.reduction - objective.required) / objective.width))
    dA = amp.damplitude * amp.modal.values[None, :]  # dA_i / d ln p [m/V]
    gradient = (w * sigma * (1 - sigma) / objective.width * hmap.reduction_slope() * V) @ dA
    top = int(np.argmax(amp.amplitude))
    return OutcomeAt(V, float(amp.amplitude[top]), amp.outputs[top], float(np.average(hmap.reduction, weights=w)),
                     float(w @ sigma), gradient, amp.modal, hmap.area_fraction(objective.required)[0])
