"""The checks of a tuning run's inputs, before any solve (``modalfe.design.tuning.tune``, ``modalfe tune``, and the
calibration's varied parameters): each refusal a one-line SceneError naming the argument at fault."""

from __future__ import annotations

import math
from collections.abc import Sequence

from modalfe.design.feet import builder_parameters_of
from modalfe.design.outcome import OUTCOME_OBJECTIVES, LargestArea, LeastVoltage, ReductionAt, touch_points
from modalfe.errors import SceneError
from modalfe.response.sensitivity import check_parameters, parameter_value, with_values
from modalfe.results.labels import check_selector

# a varied parameter must survive this relative change both ways, before any solve and at every design (
# ``check_variables``): the sensitivities perturb it by sensitivity.RELATIVE_STEP (3e-5), and a part edge closer to
# another's than this meshes as a sliver (a ceramic 11.7 um from the plate's end, 2e-4 of the length, made one that
# stalled the point probes' inverse map and then could not be perturbed: docs/tuning.md)
PROBE_STEP = 1e-3


def check_tune_inputs(scene, targets, names, tol, bounds, maximize, separation, replace_feet, mode_bounds=()) -> None:
    """SceneError naming the first bad argument of ``modalfe.design.tuning.tune`` (before any solve)."""
    if not targets:
        raise SceneError("target: give one or more LABEL=HZ")
    for t in targets:
        check_selector(t.label, "target")  # its form, before any solve
        if not (math.isfinite(t.frequency) and t.frequency > 0):
            raise SceneError(f"target: must be a positive frequency in Hz, got {t.frequency}")
    if len({t.label for t in targets}) != len(targets):
        raise SceneError("target: give each mode label once")
    if not names or len(set(names)) != len(names) or not all(isinstance(n, str) and n for n in names):
        raise SceneError("vary: give one or more distinct parameters")
    if not (math.isfinite(tol) and 0 < tol < 0.5):
        raise SceneError(f"tol: must lie in (0, 0.5), got {tol}")
    check_variables(scene, names)
    unknown = sorted(set(bounds or {}) - set(names))
    if unknown:
        raise SceneError(f"bounds: {unknown[0]} is not among the parameters varied {names}")
    for name in names:  # the steps are relative (in ln |p|): a start at 0 or outside its bounds cannot move in
        value = parameter_value(scene, name)
        lo, hi = (bounds or {}).get(name, (-math.inf, math.inf))
        if value == 0 or not lo <= value <= hi:
            raise SceneError(f"{name}: {value:g} cannot be tuned (must be non-zero and within its bounds "
                             f"{lo:g}-{hi:g})")
    if not (maximize in (None, "k_eff") or isinstance(maximize, OUTCOME_OBJECTIVES)):
        raise SceneError(f"maximize: k_eff or an outcome objective (LeastVoltage, ReductionAt, LargestArea), got "
                         f"{maximize!r}")
    if maximize and "drive" not in scene.electrodes.values():
        raise SceneError(f'maximize: {"k_eff" if maximize == "k_eff" else "a voltage"} needs a driven electrode '
                         f'(electrodes.GROUP = "drive")')
    if isinstance(maximize, OUTCOME_OBJECTIVES):
        from modalfe.contact.chain import Contact
        from modalfe.response.loads import check_outputs

        if isinstance(maximize, LeastVoltage) and not 0 < maximize.reduction < 1:
            raise SceneError(f"objective: the reduction must lie strictly between 0 and 1, got {maximize.reduction:g}")
        if isinstance(maximize, ReductionAt | LargestArea) and not (math.isfinite(maximize.voltage)
                                                                     and maximize.voltage > 0):
            raise SceneError(f"objective: the voltage must be positive, got {maximize.voltage:g}")
        if isinstance(maximize, LargestArea):
            if not 0 < maximize.required < 1:
                raise SceneError(f"objective: the required reduction must lie strictly between 0 and 1, got "
                                 f"{maximize.required:g}")
            if not (math.isfinite(maximize.width) and 0 < maximize.width < 1):
                raise SceneError(f"objective: the width must lie in (0, 1) (a fraction of reduction), got "
                                 f"{maximize.width:g}")
            if maximize.points < 1:
                raise SceneError(f"objective: at least one point of the touch surface, got {maximize.points}")
        if not isinstance(maximize.contact, Contact):
            raise SceneError(f"objective: the contact must be a FootContact or FingerContact, got {maximize.contact!r}")
        if not scene.drive.outputs:
            raise SceneError("objective: the scene has no outputs to read the amplitude at (drive.outputs)")
        check_outputs(scene, scene.drive.outputs)
        if isinstance(maximize, LargestArea):
            touch_points(scene, maximize)  # the touch surface exists
    if separation is not None and not (math.isfinite(separation) and 0 < separation < 1):
        raise SceneError(f"separation: must lie in (0, 1) (a fraction of the frequency), got {separation}")
    for b in mode_bounds:
        check_selector(b.label, "mode_bounds")
        if not (math.isfinite(b.frequency) and b.frequency > 0):
            raise SceneError(f"mode_bounds: {b.label} must be bounded by a positive frequency in Hz, got {b.frequency}")
    if len({(b.label, b.above) for b in mode_bounds}) != len(mode_bounds):
        raise SceneError("mode_bounds: give each mode at most one lower and one upper bound")
    if replace_feet and "feet" not in builder_parameters_of(scene):
        raise SceneError(f"replace_feet: the scene '{scene.name}' has no feet to place (its device takes no "
                         f"'feet')")


def check_variables(scene, names: Sequence[str]) -> None:
    """SceneError naming the first of ``names`` that ``frequency_sensitivities`` cannot take or whose small change
    (``PROBE_STEP`` of itself, up and down) the scene refuses, before any solve: cube_plate's ``width`` in its half
    model moves the y mid-plane while the ceramic rows stay at their y, so the ceramics lose their mirror images;
    the message then suggests solving the whole device."""
    check_parameters(scene, names)
    for name in names:
        value = parameter_value(scene, name)
        try:
            for sign in (1, -1):  # the sensitivities' central differences move it both ways
                with_values(scene, {name: value * (1 + sign * PROBE_STEP) if value else sign * PROBE_STEP})
        except SceneError as exc:
            hint = "; solve the whole device: --set 'symmetry=[]'" if str(exc).startswith("symmetry") else ""
            raise SceneError(f"vary: {name} cannot change in '{scene.name}' ({exc}){hint}") from None
