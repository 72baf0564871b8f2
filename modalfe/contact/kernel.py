"""Event and shooting kernel shared by the contact simulators (``foot``, ``finger``; ``texture`` uses
their curves).

Both contact models are piecewise linear: each phase (contact, flight) has a closed-form solution, and
the phases switch at events where a scalar function of the state crosses zero.  This module holds the
model-independent parts:

- event location on a closed-form arc: ``first_crossing`` (first zero crossing in one direction, with
  grazing extrema between grid samples found through the rate), ``sign_changes``;
- quadrature: ``gauss_nodes`` (Gauss-Legendre, chunked);
- periodic orbits: ``shoot_periodic`` (Newton on the period map with the exact monodromy matrix,
  optionally deflated away from known orbits), ``find_orbit`` (period kT, k = 1..N, stable only);
- averaging windows: ``landed_window`` (the window starts at a touchdown so every contact's
  tangential history lies inside it) and ``touchdown_times``;
- ``batch_ratio`` (uncertainty of a time average by batch means, stated as an upper confidence bound).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

GAUSS_ORDER = 12  # Gauss-Legendre nodes per quadrature chunk
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(GAUSS_ORDER)
STABILITY_MARGIN = 1e-6
# A march that ends within this scaled distance of its state k periods before seeds Newton on k T.
# An attracting orbit is approached geometrically, so at the end of the march its states recur much
# closer than this; chaotic motion has near-returns too (unstable orbits embedded in the attractor,
# which Newton finds and the stability test rejects), and each costs a Newton run.
RECURRENCE = 1e-2  # |multiplier| below 1 + this counts as stable (rounding of the monodromy)


# ----------------------------------------------------------------------------------------------
# Events
# ----------------------------------------------------------------------------------------------


def _grid(t0: float, t1: float, step: float | tuple[float, float, float]) -> np.ndarray:
    """Sample times on [t0, t1]: spacing ``step``, or for ``(step, fine_step, fine_span)`` spacing
    ``fine_step`` over the first ``fine_span`` (where an arc's fast transients live) and ``step`` after."""
    if isinstance(step, tuple):
        step, fine_step, fine_span = step
        tf = min(t0 + fine_span, t1)
        if tf < t1:
            return np.concatenate([_uniform(t0, tf, fine_step), _uniform(tf, t1, step)[1:]])
    return _uniform(t0, t1, step)


def _uniform(t0: float, t1: float, step: float) -> np.ndarray:
    """Equally spaced times from t0 to t1 (both included), spacing at most ``step``."""
    n = max(1, math.ceil((t1 - t0) / step))
    t = t0 + (t1 - t0) / n * np.arange(n + 1.0)
    t[-1] = t1
    return t


def bracketed_root(fun: Callable[[float], float], a: float, b: float, xtol: float | None = None) -> float:
    """A zero of ``fun`` on a bracket [a, b] to rounding accuracy (or ``xtol``): the Illinois variant
    of regula falsi, which keeps the bracket and converges superlinearly (Dowell and Jarratt, BIT 11
    (1971) 168).  Without a sign change (rounding undid the bracket) the end nearer zero."""
    fa, fb = float(fun(a)), float(fun(b))
    if fa == 0:
        return a
    if fb == 0:
        return b
    if fa * fb > 0:
        return a if abs(fa) < abs(fb) else b
    tol = xtol if xtol is not None else 4 * np.finfo(float).eps * max(abs(a), abs(b), 1e-300)
    side, c = 0, a
    for _ in range(200):
        c = (fa * b - fb * a) / (fa - fb)
        if not a <= c <= b:
            c = 0.5 * (a + b)
        fc = float(fun(c))
        if fc * fb > 0:  # c replaces b
            b, fb = c, fc
            if side == -1:
                fa /= 2  # Illinois: halve the value at the end kept twice
            side = -1
        elif fa * fc > 0:  # c replaces a
            a, fa = c, fc
            if side == 1:
                fb /= 2
            side = 1
        else:
            return c
        if b - a <= tol:
            return c
    return c


_root = bracketed_root


def _newton_root(fr: Callable, a: float, b: float, fa: float | None = None, fb: float | None = None,
                 da: float | None = None, db: float | None = None) -> float:
    """Zero of f on [a, b] with f(a) <= 0 < f(b); ``fr(t) -> (f, f')``: Newton kept inside the bracket,
    from the secant point, or, with the rates ``da``, ``db`` at the ends, from the root of the cubic
    Hermite interpolant (``fa``, ``fb``: f at the ends when known)."""
    fa = fr(a)[0] if fa is None else fa
    fb = fr(b)[0] if fb is None else fb
    x = a - fa * (b - a) / (fb - fa) if fb > fa else 0.5 * (a + b)
    if da is not None and db is not None and fb > fa:
        x = _hermite_root(a, b, fa, fb, da, db, x)
    tol = 4 * np.finfo(float).eps * max(abs(a), abs(b))
    for _ in range(100):
        f, d = fr(x)
        if f > 0:
            b = x
        else:
            a = x
        xn = x - f / d if d != 0 else a - 1.0
        if not a <= xn <= b:
            xn = 0.5 * (a + b)
        if abs(xn - x) <= tol or b - a <= tol:
            return float(xn)
        x = xn
    return float(x)


def _hermite_root(a: float, b: float, fa: float, fb: float, da: float, db: float, x: float) -> float:
    """Root in [a, b] of the cubic Hermite interpolant of (f, f') at a and b, by a few Newton steps
    from ``x`` in the unit variable; ``x`` itself if that leaves the bracket."""
    h = b - a
    ma, mb = da * h, db * h
    s = (x - a) / h
    for _ in range(4):
        s2, s3 = s * s, s * s * s
        p = (2 * s3 - 3 * s2 + 1) * fa + (s3 - 2 * s2 + s) * ma + (-2 * s3 + 3 * s2) * fb + (s3 - s2) * mb
        dp = (6 * s2 - 6 * s) * fa + (3 * s2 - 4 * s + 1) * ma + (-6 * s2 + 6 * s) * fb + (3 * s2 - 2 * s) * mb
        if dp == 0:
            return x
        s -= p / dp
        if not 0 <= s <= 1:
            return x
    return a + s * h


def first_crossing(fun_rate: Callable, t0: float, t1: float, step: float | tuple[float, float, float], *,
                   upward: bool) -> float | None:
    """First time in (t0, t1] where a function crosses zero upward (or downward), else None.

    ``fun_rate(t) -> (f, df/dt)`` takes arrays and floats.  ``f`` is on the near side of zero at ``t0``
    up to rounding (an arc starts at the previous event).  Sign changes are found on a grid of spacing
    ``step`` (or finer at the start, see ``_grid``); a local extremum between two samples that reaches
    across zero (a grazing arc shorter than ``step``) is found through the rate.  Roots are polished by
    Newton's method inside the bracket, started from the cubic Hermite interpolant of the samples.
    Returns ``t0`` when the arc leaves at once (it starts moving towards its exit).  A start where
    both the function and its rate vanish to rounding is tangent: the samples after it decide.
    """
    sign = 1.0 if upward else -1.0

    def fr(t):
        f, d = fun_rate(t)
        return sign * f, sign * d

    def d(t):
        return fr(t)[1]

    t = _grid(t0, t1, step)
    fv, dv = fr(t)
    if abs(fv[0]) <= 1e-9 * np.max(np.abs(fv)) and abs(dv[0]) <= 1e-9 * np.max(np.abs(dv)):
        fv[0] = dv[0] = 0.0  # a tangent start (a Kelvin-Voigt layer's separation): the grid decides
    elif (fv[0] >= 0 and dv[0] > 0) or (fv[0] > 0 and dv[0] >= 0):
        return t0
    after = np.flatnonzero(fv[1:] > 0) + 1
    last = after[0] if after.size else len(t) - 1

    def low(i, b):
        # a point of [t_i, b) where f <= 0 after the start, with f there; at t0, f is zero or a
        # rounding residue
        if i > 0 or fv[0] < 0:
            return t[i], fv[i]
        tm = _root(d, t0, b) if d(b) > 0 else b
        fm = fr(tm)[0]
        return (tm, fm) if fm < 0 else (None, None)

    peaks = np.flatnonzero((dv[:last] > 0) & (dv[1 : last + 1] < 0))
    if peaks.size:
        # f is concave between two samples where f' falls from + to -: below both tangent lines,
        # so a peak whose tangent-line bound stays below zero cannot cross and needs no root
        h = t[peaks + 1] - t[peaks]
        bound = np.minimum(fv[peaks] + dv[peaks] * h, fv[peaks + 1] - dv[peaks + 1] * h)
        peaks = peaks[bound >= 0]
    for i in peaks:
        tm = _root(d, t[i], t[i + 1])
        fm = fr(tm)[0]
        if fm > 0:
            a, fa = low(i, tm)
            return t0 if a is None else _newton_root(fr, a, tm, fa, fm)
    if not after.size:
        return None
    a, fa = low(last - 1, t[last])
    if a is None:
        return t0
    if a == t[last - 1]:
        return _newton_root(fr, a, t[last], fa, fv[last], dv[last - 1], dv[last])
    return _newton_root(fr, a, t[last], fa, fv[last])


def sign_changes(fun: Callable, t0: float, t1: float, step: float) -> list[float]:
    """All sign changes of ``fun`` in (t0, t1) seen on a grid of spacing ``step``, polished by Brent."""
    t = _grid(t0, t1, step)
    fv = fun(t)
    idx = np.flatnonzero(np.sign(fv[:-1]) * np.sign(fv[1:]) < 0)
    return [_root(fun, t[i], t[i + 1]) for i in idx]


def gauss_nodes(a: float, b: float, chunk: float) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [a, b], split into chunks no longer than ``chunk``."""
    if b <= a:
        return np.empty(0), np.empty(0)
    edges = np.linspace(a, b, max(1, math.ceil((b - a) / chunk)) + 1)
    half = 0.5 * np.diff(edges)[:, None]
    mid = 0.5 * (edges[:-1] + edges[1:])[:, None]
    return (mid + half * _GAUSS_X).ravel(), (half * _GAUSS_W).ravel()


# ----------------------------------------------------------------------------------------------
# Periodic orbits
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PeriodicState:
    """Fixed point of a period map found by Newton shooting.

    state : the state at the start of the period; iterations : Newton steps taken;
    residual : scaled |P(x) - x| at the end; multipliers : Floquet multipliers (eigenvalues of dP/dx);
    converged : residual below tolerance.
    """

    state: np.ndarray
    iterations: int
    residual: float
    multipliers: np.ndarray
    converged: bool

    @property
    def stable(self) -> bool:
        """Every Floquet multiplier inside the unit circle (with a margin for rounding)."""
        return bool(np.all(np.abs(self.multipliers) < 1 + STABILITY_MARGIN))

    @property
    def largest_multiplier(self) -> float:
        return float(np.max(np.abs(self.multipliers)))


def shoot_periodic(period_map: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], x0: np.ndarray,
                   scale: np.ndarray, *, tol: float = 1e-11, max_iter: int = 40,
                   deflate: Sequence[np.ndarray] = ()) -> PeriodicState:
    """Periodic steady state x = P(x) by Newton's method (shooting).

    ``period_map(x) -> (P(x), dP/dx)``: the state one period later and the monodromy matrix.
    Works in the scaled variables ``x / scale``; ``tol`` bounds the scaled residual.  A Newton step
    that does not reduce the residual is halved up to six times, then replaced by one step of the map
    itself (time marching), which the physical attractor contracts.  ``deflate``: states of orbits
    already known; Newton then solves ``m(x) (P(x) - x) = 0`` with ``m = prod(1/|x - r|^2 + 1)``
    (Farrell, Birkisson and Funke, SIAM J. Sci. Comput. 37 (2015) A2026), which keeps it away from them.
    """
    scale = np.asarray(scale, float)
    n = len(scale)
    roots = [np.asarray(r, float) / scale for r in deflate]

    def residual(y):
        xT, Phi = period_map(y * scale)
        F, J = xT / scale - y, Phi * scale[None, :] / scale[:, None] - np.eye(n)
        m, grad = 1.0, np.zeros(n)
        for r in roots:
            d = y - r
            dd = min(max(float(d @ d), 1e-30), 1e30)
            mi = 1 / dd + 1
            grad = grad * mi - m * 2 * d / dd ** 2
            m *= mi
        return F, J, m * F, m * J + np.outer(F, grad)

    y = np.asarray(x0, float) / scale
    F, J, G, JG = residual(y)
    steps = 0
    while np.linalg.norm(F) >= tol and steps < max_iter:
        steps += 1
        try:
            dy = np.linalg.solve(JG, -G)
        except np.linalg.LinAlgError:
            dy = F
        norm = np.linalg.norm(G)
        for _ in range(7):
            new = residual(y + dy)
            if np.linalg.norm(new[2]) < (1 - 1e-4) * norm:
                y, (F, J, G, JG) = y + dy, new
                break
            dy = dy / 2
        else:
            y = y + F
            F, J, G, JG = residual(y)
    res = float(np.linalg.norm(F))
    return PeriodicState(y * scale, steps, res, np.linalg.eigvals(J + np.eye(n)), res < tol)


@dataclass(frozen=True)
class OrbitSearch:
    """Outcome of ``find_orbit``.

    period : k of the stable periodic orbit of period k T found (its minimal period), 0 if none;
    state : the state at t = 0 on that orbit, or (k = 0) a state reached by marching, to average from;
    shooting : the accepted orbit's shooting result (or the period-1 attempt when k = 0);
    unstable : (k, largest |multiplier|) of every periodic orbit found and rejected as unstable.
    """

    period: int
    state: np.ndarray
    shooting: PeriodicState
    unstable: tuple[tuple[int, float], ...]


def find_orbit(period_map: Callable[..., tuple[np.ndarray, np.ndarray | None]], x0: np.ndarray,
               scale: np.ndarray, *, max_period: int = 8, march_periods: int = 300,
               hints: Sequence[tuple[int, np.ndarray]] = (), march_from: np.ndarray | None = None) -> OrbitSearch:
    """A stable periodic orbit of period k T, k = 1..``max_period``, by shooting on k T.

    ``period_map(k, x, sensitivity) -> (x(k T), dx(k T)/dx(0) or None)``.  Order of the attempts:
    k = 1 from ``x0``; each ``hints`` entry (k, state), e.g. a neighbouring amplitude's orbit; for
    an unstable period-1 orbit with a multiplier below -1 (period doubling), k = 2 from both sides of
    it along that eigenvector (cold starts only, without ``march_from``); then ``march_periods``
    periods of time marching (from ``march_from`` if given: a state on a neighbouring amplitude's
    attractor) and, for each k, Newton on k T from the last marched state if it came back within
    RECURRENCE of itself after k periods.  Orbits already
    found are deflated (a period-1 orbit is also a fixed point of the 2T map); an orbit is accepted
    when Newton converged and every Floquet multiplier of its k T monodromy lies inside the unit circle,
    and it is reported with its minimal period.  When none is found the caller averages in time from
    the marched state (``period = 0``).
    """
    scale = np.asarray(scale, float)
    known: list[np.ndarray] = []
    unstable: list[tuple[int, float]] = []

    def attempt(k: int, start: np.ndarray, max_iter: int):
        sol = shoot_periodic(lambda x: period_map(k, x, True), start, scale, max_iter=max_iter, deflate=known)
        if not sol.converged:
            return sol, 0
        points, x, minimal = [sol.state], sol.state, k
        for j in range(1, k):
            x = period_map(1, x, False)[0]
            if np.linalg.norm((x - sol.state) / scale) < 1e-7:
                minimal = j
                break
            points.append(x)
        known.extend(points[:minimal])
        if sol.stable:
            return sol, minimal
        unstable.append((minimal, sol.largest_multiplier))
        return sol, 0

    first, k = attempt(1, np.asarray(x0, float), 40)
    if k:
        return OrbitSearch(k, first.state, first, ())
    for kh, xh in hints:
        if 1 < kh <= max_period:
            sol, k = attempt(kh, np.asarray(xh, float), 12)
            if k:
                return OrbitSearch(k, sol.state, sol, tuple(unstable))
    start = first.state if first.converged else np.asarray(x0, float)
    if first.converged and max_period >= 2 and march_from is None:
        _, Phi = period_map(1, first.state, True)
        lam, vec = np.linalg.eig(Phi * scale[None, :] / scale[:, None])
        i = int(np.argmin(lam.real))
        if lam[i].real < -1 and abs(lam[i].imag) < 1e-12:  # a flip: the period-2 orbit lies along v
            v = vec[:, i].real * scale / np.linalg.norm(vec[:, i].real)
            for side in (0.3, -0.3):  # the two sides lead to the two phases of one period-2 orbit
                sol, k = attempt(2, first.state + side * v, 12)
                if k:
                    return OrbitSearch(k, sol.state, sol, tuple(unstable))
                if sol.converged:
                    break
            start = first.state + 0.05 * v
        i = int(np.argmax(np.abs(lam)))
        if abs(lam[i]) > 1 and abs(lam[i].imag) < 1e-12:
            start = first.state + 0.05 * vec[:, i].real * scale / np.linalg.norm(vec[:, i].real)
    # the first half of the march in one call (no states kept: an arc is not cut at each period's end, a third of the
    # march's cost), the second half period by period, where a recurrence is looked for
    head = march_periods // 2
    states = [start if march_from is None else np.asarray(march_from, float)]
    if head:
        states = [period_map(head, states[0], False)[0]]
    for _ in range(march_periods - head):
        states.append(period_map(1, states[-1], False)[0])
    tail = np.array(states) / scale
    for k in range(2, max_period + 1):
        if len(tail) <= k:
            break
        gap = np.linalg.norm(tail[-1] - tail[-1 - k])
        if gap < RECURRENCE:  # the march ends coming back near itself after k periods: a candidate
            sol, kk = attempt(k, tail[-1] * scale, 6)
            if kk:
                return OrbitSearch(kk, sol.state, sol, tuple(unstable))
    return OrbitSearch(0, states[-1], first, tuple(unstable))


# ----------------------------------------------------------------------------------------------
# Averaging windows
# ----------------------------------------------------------------------------------------------


def touchdown_times(pieces: Sequence, first: float = -math.inf) -> list[float | None]:
    """Touchdown time t_c of the contact each piece belongs to (None for a flight piece).

    ``pieces`` have ``contact``, ``t0`` and ``t1`` and follow each other in time.  A contact piece
    after a flight of positive duration starts at a touchdown; one after a contact piece (a window
    boundary, or a flight of zero length, i.e. a tangency that is no flight) continues that contact.
    ``first``: t_c of a contact piece that opens the list (-inf: in contact since ever).
    """
    out: list[float | None] = []
    tc, flew = first, False
    for i, q in enumerate(pieces):
        if not q.contact:
            flew = flew or q.t1 > q.t0
            out.append(None)
            continue
        if i > 0 and flew:
            tc = q.t0
        flew = False
        out.append(tc)
    return out


def landed_window(advance: Callable[[float, float], list], span: float,
                  periodic: bool) -> tuple[list, list[float | None]]:
    """The pieces to average over and their touchdown times (``touchdown_times``).

    ``advance(t0, t1)`` returns the pieces of the solution on [t0, t1] from the start state, which
    on a periodic orbit of period ``span`` is the state at t0 = 0 and at t0 = span alike.  The window
    starts at the first touchdown (a contact piece after a flight of positive duration), so each
    contact's tangential history (Coulomb-Orowan displacement, stick phase) lies inside it.  On a
    periodic orbit the window is [t_l, span] followed by [span, span + t_l] (the same orbit one
    period on): no second integration of the whole period, so a touchdown that the shooting's
    residual moves by a rounding error is neither counted twice nor lost.  A time average drops the
    pieces before the first touchdown.  Without a touchdown the whole span is returned, contact
    pieces with t_c = -inf (permanent contact).
    """
    pieces = [q for q in advance(0.0, span)]
    tcs = touchdown_times(pieces)
    i = next((j for j in range(1, len(pieces)) if pieces[j].contact and tcs[j] == pieces[j].t0), None)
    if i is None:
        return pieces, tcs
    if not periodic:
        window = pieces[i:]
        return window, touchdown_times(window, first=window[0].t0)
    end = span + pieces[i].t0
    tail = advance(span, end)  # its last event, if any, is the window's first touchdown again
    window = pieces[i:] + [q for q in tail if q.t1 > q.t0 and q.t0 < end - 1e-9 * span]
    return window, touchdown_times(window, first=window[0].t0)


# A time average's stated standard error is an upper confidence bound on it: n batch means with sample
# standard deviation s have (n - 1) s^2 / sigma^2 ~ chi2(n - 1) (normal batch means), so
# s / sqrt(n) * sqrt((n - 1) / chi2_{1 - COVERAGE}(n - 1)) is at least the true standard error with probability
# COVERAGE (the factor is 1.80 for 8 batches).  The plain estimate s / sqrt(n) of one run is as likely low as high,
# and on the chaotic finger it is biased low as well: at 66 kHz, 3.2 and 5 um pp, batches of 71-568 periods give
# 0.86-0.99 of the scatter between averages (correlations longer than a batch; studies/finger_uncertainty.py).
COVERAGE = 0.95


def chi2_cdf(x: float, dof: int) -> float:
    """P(chi2(dof) <= x) for a whole ``dof`` >= 1, in closed form (Abramowitz & Stegun 26.4.4-26.4.5): the even
    case a Poisson tail, the odd case erf less a finite sum; scipy.special's import (0.1 s) is not paid for it."""
    h = x / 2
    if dof % 2 == 0:
        return 1.0 - math.exp(-h) * sum(h**j / math.factorial(j) for j in range(dof // 2))
    return math.erf(math.sqrt(h)) - math.exp(-h) * sum(h ** (j + 0.5) / math.gamma(j + 1.5) for j in range(dof // 2))


@functools.lru_cache(maxsize=64)
def chi2_quantile(p: float, dof: int) -> float:
    """The x with P(chi2(dof) <= x) = p, by bisection on ``chi2_cdf`` to a relative 1e-12."""
    low, high = 0.0, dof + 20.0 * math.sqrt(2 * dof) + 20.0
    while high - low > 1e-12 * high:
        mid = 0.5 * (low + high)
        low, high = (mid, high) if chi2_cdf(mid, dof) < p else (low, mid)
    return 0.5 * (low + high)


def batch_ratio(numerators: np.ndarray, denominators: np.ndarray, batches: int = 8) -> tuple[float, float]:
    """Ratio of sums and an upper bound (at confidence COVERAGE) on its standard error by batch means: the
    per-period (or per-piece) sums cut into ``batches`` consecutive groups, std(ratio of each group) / sqrt(batches)
    (Law and Kelton, Simulation Modeling and Analysis, 2000, sec. 9.5.3) times the chi-square factor above."""
    num, den = np.asarray(numerators, float), np.asarray(denominators, float)
    ratio = float(num.sum() / den.sum())
    groups = [g for g in np.array_split(np.arange(len(num)), batches) if len(g)]
    if len(groups) < 2:
        return ratio, math.inf
    r = np.array([num[g].sum() / den[g].sum() for g in groups])
    dof = len(r) - 1
    bound = math.sqrt(dof / chi2_quantile(1 - COVERAGE, dof))
    return ratio, float(np.std(r, ddof=1) / math.sqrt(len(r)) * bound)
