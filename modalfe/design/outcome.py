"""The felt outcome as a tuning objective (the method in ``modalfe.design.tuning``'s module docstring):

* ``LeastVoltage``: the least drive voltage for a required friction reduction, V = W_R(f) / A, maximized as -ln V
  with the gradient d ln A / d ln p (the contact model's frequency term drops out on the targets);
* ``ReductionAt``: the largest friction reduction at a given drive voltage V, R(W = V A, f), maximized as R with the
  gradient (dR / d ln W)(d ln A / d ln p); dR / d ln W by a central difference of the contact model's steady state
  (``REDUCTION_STEP``), exact to O(h^2) on the foot's periodic orbit.

``outcome_at`` evaluates either at one design from the amplitude sensitivities of its mode (``OutcomeAt``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from modalfe.errors import SolverError
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


OUTCOME_OBJECTIVES = (LeastVoltage, ReductionAt)


@dataclass(frozen=True)
class OutcomeAt:
    """An outcome objective at one design: volts [V] (asked by ``LeastVoltage``, given by ``ReductionAt``), the
    amplitude per volt A [m/V, 0-peak] at ``output``, the reduction reached at that voltage, the merit maximized
    (-ln V or R), its gradient d merit / d ln p on the parameters, and every mode's ``Sensitivities``."""

    volts: float
    amplitude_per_volt: float
    output: str
    reduction: float
    merit: float
    gradient: np.ndarray
    sensitivities: object


def outcome_at(scene, modes, label: str, near: float, names, objective: LeastVoltage | ReductionAt) -> OutcomeAt:
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
