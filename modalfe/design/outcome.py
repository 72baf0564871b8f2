"""The felt outcome as a tuning objective: the least drive voltage for a required friction reduction
(``LeastVoltage``), V = W_R(f) / A, and its value and gradient at one design (``least_voltage``; the method in
``modalfe.design.tuning``'s module docstring)."""

from __future__ import annotations

from dataclasses import dataclass

from modalfe.errors import SolverError
from modalfe.results.modes import select


@dataclass(frozen=True)
class LeastVoltage:
    """The objective "the least drive voltage for a required friction reduction" (module docstring): reduction
    (a fraction in (0, 1)) and the contact model (``modalfe.contact.chain.FootContact`` or ``FingerContact``, its
    preload and speed; the drive frequency and the number of feet are set at each design)."""

    reduction: float
    contact: object

    def describe(self) -> str:
        return f"the voltage for a {self.reduction:.2%} friction reduction ({self.contact.describe()})"


def least_voltage(scene, modes, label: str, near: float, names, least: LeastVoltage):
    """``LeastVoltage`` at one design (module docstring): (V [V], A [m/V], the output, the gradient of -ln V on the
    targets, d ln A / d ln p, and every mode's ``Sensitivities``), from ``amplitude_sensitivities`` of the mode
    ``label`` at the scene's outputs with its damping (the materials', as ``forced``), read at the output that
    moves most (``reduce``'s reference rule: the first of equals), and the contact model's amplitude W_R for the
    reduction at the mode's frequency (``amplitude_for``)."""
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
    needed = amplitude_for(least.contact.tuned(mode.frequency, feet_among(outputs)), least.reduction)
    return needed / amp.amplitude[o], float(amp.amplitude[o]), amp.outputs[o], amp.relative[o], amp.modal
