"""The modes a question checks and the worst stated error among them, shared by the fidelity ladder
(``modalfe.solve.fidelity``) and the axisymmetric rung (``modalfe.solve.axisymmetric``)."""

from __future__ import annotations

import math

from modalfe.errors import SolverError
from modalfe.results.modes import Modes, select

NOT_ESTIMATED = ("none: error not estimated (error_estimate off, --no-error-estimate): the scene's own mesh solved "
                 "once, its error unknown")


def percent(x: float) -> str:
    """A relative tolerance as a percentage with two decimals, or two significant digits below 0.01 %
    (``tol 1e-05`` is ``0.0010%``, not ``0.00%``)."""
    if x >= 1e-4 or x <= 0:
        return f"{100 * x:.2f}%"
    return f"{100 * x:.{1 - math.floor(math.log10(100 * x))}f}%"


def checked_modes(modes: Modes, check) -> list:
    """The modes of ``modes`` that ``check`` ((selector, near Hz) pairs; None: every mode but rigid-body ones) asks
    about."""
    if check is None:
        rigid = modes.rigid_indices()
        return [m for m in modes if m.index not in rigid]
    return [modes.nearest(near) if selector is None else select(modes, selector, near) for selector, near in check]


def worst_checked(modes: Modes, check, *, what: str = "estimated error") -> tuple[float, str]:
    """(largest estimated error of the checked modes (every mode with no ``check``), a phrase saying which, calling
    it ``what``)."""
    try:
        found = checked_modes(modes, check)
    except SolverError as exc:
        return math.inf, f"working mode not found ({exc})"
    if not found:
        return 0.0, "no mode to check"
    worst = max(found, key=lambda m: m.error_estimate if not math.isnan(m.error_estimate) else math.inf)
    value = worst.error_estimate if not math.isnan(worst.error_estimate) else math.inf
    return value, f"{what} {percent(value)} on {worst.label} at {worst.frequency:.6g} Hz"
