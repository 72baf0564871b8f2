"""The tuning loop's step (``modalfe.design.tuning``'s module docstring): what one evaluated design knows (``Point``:
residuals, Jacobian and the linearised inequality rows, ``Limit``), whether it meets the targets (``is_met``), the
trust-region step on the target rows and the active inequality rows with the projected merit gradient
(``trust_step``), where the modes are sought after a step (``moved_frequencies``) and Broyden's update of the
Jacobian (``broyden``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

MAX_RELATIVE_STEP = 0.2  # trust region: no parameter moves by more than this fraction of itself in one iterate


@dataclass(frozen=True)
class Limit:
    """A linearised inequality row sigma (d + a s - limit) >= 0 in the step s (module docstring): a separation from a
    neighbour or a mode bound; met within ``slack``, and aimed at ``aim`` when active."""

    sigma: int
    d: float
    a: np.ndarray
    limit: float
    slack: float
    aim: float


@dataclass
class Point:
    """What one evaluation knows: the iterate, the residuals r, Jacobian J (targets x parameters), the separation
    rows and the mode bounds' rows (``Limit``), the merit's gradient g (d ln k / d ln p or an outcome's), and the
    feet placed on its antinodes."""

    scene: object
    iterate: object  # its ``modalfe.design.tuning.Iterate``
    r: np.ndarray
    J: np.ndarray
    neighbours: list = field(default_factory=list)
    g: np.ndarray | None = None
    placed: tuple | None = None  # feet re-placed on the antinodes of this point's plate, when they moved
    bounds: list = field(default_factory=list)

    @property
    def limits(self) -> list[Limit]:
        return self.neighbours + self.bounds

    @property
    def lnf(self) -> np.ndarray:
        """ln f of the target modes and then the bound modes (the rows a Broyden update steers)."""
        return np.log(np.array(self.iterate.frequencies + self.iterate.bounded))


def moved_frequencies(point: Point, taken: np.ndarray) -> list[float]:
    """Where the target modes and then the bound modes are sought after the step ``taken`` from ``point``: their
    frequencies moved along their rows."""
    rows = list(point.J) + [b.a for b in point.bounds]
    return [f * math.exp(float(row @ taken)) for f, row in zip(point.iterate.frequencies + point.iterate.bounded, rows)]


def broyden(J: np.ndarray, s: np.ndarray, dr: np.ndarray) -> np.ndarray:
    """Broyden's ("good") rank-one update of the Jacobian ``J`` after the step ``s`` changed the residuals by ``dr``:
    J + (dr - J s) s^T / (s^T s), the least change of J (Frobenius) that maps s to dr (Broyden, Math. Comp. 19 (1965)
    577); ``J`` itself for a null step."""
    ss = float(s @ s)
    return J if ss == 0 else J + np.outer(dr - J @ s, s) / ss


def is_met(point: Point, tol: float) -> bool:
    """Every target within ``tol``, its mode's stated error included (where estimated), the first target's
    neighbours at least ``separation`` away, to ``tol`` / 2 of a frequency (an active separation row lands on its
    limit only as closely as the targets on theirs), and every mode bound met, its stated error included."""
    stated = point.iterate.errors if point.iterate is not None else ()
    errors = np.array([e if not math.isnan(e) else 0.0 for e in stated] or [0.0] * len(point.r))
    within = bool(np.all(np.abs(np.expm1(point.r)) + errors <= tol))
    return within and all(lim.sigma * (lim.d - lim.limit) >= -lim.slack for lim in point.limits)


def trust_step(point: Point, radius: float, x, low, high) -> tuple[np.ndarray, np.ndarray]:
    """The step in ln |p| (module docstring) and the projected k_eff gradient P g (zeros when not maximizing):
    the restoring minimum-norm step on the target rows and the active separation and bound rows, within the trust
    region ln(1 + ``MAX_RELATIVE_STEP``), plus the projected gradient over ``radius`` (at most what the restoring
    step leaves of the trust region; 0: none)."""
    n = point.J.shape[1]
    active: list[int] = []
    while True:
        limits = point.limits
        rows = [point.J] + [limits[i].a[None, :] for i in active]
        # active, a row reads d + a s = aim (a separation's limit ln(1 + sigma sep), a bound's inside its limit)
        rhs = [-point.r] + [np.array([limits[i].aim - limits[i].d]) for i in active]
        A, b = np.vstack(rows), np.concatenate(rhs)
        step = np.linalg.lstsq(A, b, rcond=None)[0]  # minimum-norm least squares
        largest, region = float(np.max(np.abs(step))), math.log1p(MAX_RELATIVE_STEP)
        if largest > region:
            step *= region / largest
        ascent = np.zeros(n)
        if point.g is not None:
            g = point.g
            # bounds g pushes against are held: g is along ln |p|, so along p it is sign(p) g; a design on a bound
            # reads it back from its scene to within rounding
            up = np.sign(x) * g
            on_low, on_high = (x <= low) | np.isclose(x, low, rtol=1e-9, atol=0), \
                (x >= high) | np.isclose(x, high, rtol=1e-9, atol=0)
            free = ~((on_high & (up > 0)) | (on_low & (up < 0)))
            Af = A[:, free]
            ascent[free] = g[free] - np.linalg.pinv(Af) @ (Af @ g[free])  # P g, P = I - A^+ A
            top = float(np.max(np.abs(ascent)))
            if top > 0:
                step = step + max(min(radius, region - largest), 0.0) * ascent / top
        broken = [i for i, lim in enumerate(limits)
                  if i not in active and lim.sigma * (lim.d + lim.a @ step - lim.aim) < -1e-12]
        if not broken:
            return step, ascent
        active += broken
