"""The eigen solve: shift-invert Lanczos (ARPACK) around a target with one sparse factorization, and a
band search made complete by Sturm counts.

The coupled piezoelectric problem K x = omega^2 M x has a singular M (no inertia on the potential);
ARPACK's shift-invert mode accepts a positive semi-definite M, and the potential unknowns only
add eigenvalues at infinity, which shift-invert maps to zero and never returns.

Band completeness (``band``): the number of eigenvalues below a shift s is the number of negative
eigenvalues of A - s B (Sylvester's law of inertia; the Sturm-sequence count of Bathe, Finite Element
Procedures, 1996, sec. 10.2.4 and 11.6), less the negative eigenvalues of A's block on the unknowns without
inertia (the potential: -K_phiphi), which the condensed problem does not have (Haynsworth's inertia
additivity of the Schur complement). The band is cut into windows holding at most ``WINDOW_MODES`` modes by
those counts; each window is solved at the midpoint of its eigenvalue interval, where its modes are exactly
the nearest ones (a bottom window with no eigenvalue below it at its lower end, whose count's factorization serves),
and the modes found in it must equal its count, or the solve fails saying so.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, LinearOperator, eigsh

from modalfe.errors import SolverError
from modalfe.results.labels import RIGID_FRACTION  # a band starting below it (of its top) holds the rigid-body modes
from modalfe.solve.linalg import (
    Shifted,
    checked,
    counted_factorization,
    factorize,
    negative_eigenvalue_count,
    pardiso_inertia,
)

log = logging.getLogger(__name__)

WINDOW_MODES = 24  # most modes one shift-invert Lanczos run is asked for in a band (ncv = 2k + 1 vectors)
# the relative shift moves tried when a shift is singular (on an eigenvalue) or too close to one to factor
# well: growing, alternating in sign, so that a mode exactly on the shift is not jumped over by a near pair
NUDGES = (1e-6, -1e-5, 1e-4, -1e-3, 1e-2)
LANCZOS_BYTES = 2e9  # refuse a near/count solve whose Lanczos basis alone needs more memory than this


@dataclass(frozen=True, eq=False)
class EigenSolution:
    """Eigenpairs of A x = lam B x sorted by lam: ``values`` (k,) [rad^2/s^2], ``vectors`` (n, k) B-orthonormal;
    seconds of the factorization and of the Lanczos iteration; the direct ``solver`` used; for a band, the
    Sturm count of eigenvalues in it (``expected``; None for near/count)."""

    values: np.ndarray
    vectors: np.ndarray
    factorization_seconds: float
    eigensolve_seconds: float
    solver: str
    expected: int | None = None
    factor: tuple | None = None  # (solve, shift): the factorization of A - shift B used (near/count solves)


def eigenpairs(A, B, analysis, solver: str = "auto", factor: tuple | None = None,
               known: tuple | None = None, start: np.ndarray | None = None) -> EigenSolution:
    """Eigenpairs of A x = lam B x near ``analysis``'s target (``near`` and ``count``, or every mode in ``band``);
    ``factor`` and ``start``: see ``near_eigenpairs``; ``known``: see ``band_eigenpairs``."""
    if analysis.band is not None:
        return band_eigenpairs(A, B, analysis.band, solver, known)
    return near_eigenpairs(A, B, analysis.near, analysis.count, solver, factor, start)


def near_eigenpairs(A, B, near: float, count: int, solver: str = "auto", factor: tuple | None = None,
                    start: np.ndarray | None = None) -> EigenSolution:
    """The ``count`` eigenpairs nearest ``near`` [Hz] (nearest in omega^2, as shift-invert finds them); ``factor``
    (solve, shift): a solve with A - shift B to use instead of factorizing, when its shift is this one; ``start``
    (n,): a Lanczos start vector rich in the eigenvectors sought (``_lanczos``)."""
    n = A.shape[0]
    if count > n - 2:
        raise SolverError(f"count: {count} modes asked but the model has {n} unknowns (at most {max(n - 2, 0)})")
    ncv = lanczos_vectors(count, n)
    if ncv * n * 8 > LANCZOS_BYTES:
        raise SolverError(f"count: {count} modes of {n} unknowns need {ncv * n * 8 / 1e9:.1f} GB of Lanczos "
                          f"vectors; ask for fewer, or for a band (solved in windows)")
    sigma = (2 * np.pi * near) ** 2
    floor = _shift_scale(A, B)
    if sigma < 1e2 * floor:
        return _lowest(A, B, sigma, count, floor, solver)
    t = time.perf_counter()
    if factor is not None and factor[1] == sigma:
        (solve, moved), used = factor, "reused"
    else:
        solve, used, moved = _factor_nudged(A, B, sigma, solver)
    t_fact = time.perf_counter() - t
    t = time.perf_counter()
    # on a moved shift, two more modes, then the ``count`` nearest the shift asked for
    k = count if moved == sigma else min(count + 2, n - 2)
    lam, X = _lanczos(A, B, moved, k, solve, start=start)
    if k > count:
        nearest = np.sort(np.argsort(np.abs(lam - sigma), kind="stable")[:count])
        lam, X = lam[nearest], X[:, nearest]
    return EigenSolution(lam, X, t_fact, time.perf_counter() - t, used, factor=(solve, moved))


def _lowest(A, B, sigma: float, count: int, floor: float, solver: str) -> EigenSolution:
    """The ``count`` eigenpairs nearest a shift ``sigma`` at or next to 0 (below ``1e2 floor``), complete by Sturm
    count. A shift at 0 on a free body is singular, and one next to it leaves the elastic modes 1e5 times below the
    rigid-body ones in the inverted operator, where they lose their accuracy (measured: residuals 7e-2 on a free
    plate), and ARPACK may return only some of the six rigid modes. So: grow an interval from just below 0 until
    its Sturm count holds ``count`` modes and its top lies at least as far above ``sigma`` as the ``count``-th
    nearest mode in it (so that no mode outside is nearer), solve it as a band and keep the ``count`` nearest."""
    offset = _massless_negatives(A, B, solver)
    counter = _SturmCounter(A, B, solver, offset)
    low, below_low = counter.count_near(-1e-2 * floor, outward=-1)
    top = max(1e2 * floor, 2 * sigma)
    while True:
        top, below_top = counter.count_near(top, outward=+1)
        everything = below_top - below_low >= A.shape[0] - offset - 2
        if below_top - below_low >= count or everything:
            solution = _interval(A, B, low, below_low, top, below_top, solver, counter)
            nearest = np.sort(np.argsort(np.abs(solution.values - sigma), kind="stable")[:count])
            if everything or np.abs(solution.values[nearest] - sigma).max() <= top - sigma:
                break
        top *= 4.0
    return EigenSolution(solution.values[nearest], solution.vectors[:, nearest], solution.factorization_seconds,
                         solution.eigensolve_seconds, solution.solver)


def band_eigenpairs(A, B, band: tuple[float, float], solver: str = "auto", known: tuple | None = None) -> EigenSolution:
    """Every eigenpair with frequency in ``band`` [Hz], certified complete by Sturm counts (module docstring);
    SolverError naming both numbers when the modes found are not the count. ``known`` ((solve, shift), values,
    vectors): eigenpairs of this pencil found already (B-orthonormal) and the factorization they were found with;
    where the band holds at most ``WINDOW_MODES`` modes, they complete it (``_completed``) instead of a window's own
    factorization and Lanczos run."""
    f1, f2 = band
    top = (2 * np.pi * f2) ** 2
    low = (2 * np.pi * f1) ** 2 if f1 > RIGID_FRACTION * f2 else -RIGID_FRACTION * top
    offset = _massless_negatives(A, B, solver)
    counter = _SturmCounter(A, B, solver, offset)
    low, below_low = counter.count_near(low, outward=-1, keep=True)
    top, below_top = counter.count_near(top, outward=+1, keep=known is not None)
    if below_top - below_low <= 0:
        raise SolverError(f"no modes in the band {f1:g}-{f2:g} Hz (Sturm count 0)")
    if known is not None and below_top - below_low <= WINDOW_MODES:
        (_, shift), lam_known, _ = known
        # the known pairs' factorization counts below its shift too: then only the band's ends with modes missing
        # between them and the known ones are searched
        below, sides = pardiso_inertia(known[0][0], A.shape[0]), (low, top)
        if below is not None and low < shift <= top:
            missing_below = below - offset - below_low - int(np.sum((lam_known > low) & (lam_known < shift)))
            missing_above = below_top - (below - offset) - int(np.sum((lam_known >= shift) & (lam_known <= top)))
            sides = tuple(end for end, missing in ((low, missing_below), (top, missing_above)) if missing > 0)
        ends = [(solve, end) for end in sides if (solve := counter.solve_at(end)) is not None]
        completed = _completed(A, B, low, top, below_top - below_low, known, ends)
        if completed is not None:
            return completed
    return _interval(A, B, low, below_low, top, below_top, solver, counter)


def _completed(A, B, low: float, top: float, expected: int, known: tuple, ends: list[tuple]) -> EigenSolution | None:
    """The ``expected`` eigenpairs with lam in (low, top] (their Sturm count) from ``known`` ((solve, shift), values,
    vectors): the known ones inside, the others sought by Lanczos at the factorizations at hand, with every pair found
    so far deflated (those outside the interval too, so that each run finds new ones). Those of the Sturm counts at
    the band's ends (``ends``: (solve, shift) each) first: the known pairs are every mode nearer their shift than the
    farthest of them, so the ones missing lie towards the ends, nearest there (the Cu-Be plate's widened band: its
    30.9 and 51.2 kHz modes, sought from the 39.6 kHz answer's shift past the modes below the band, took four runs).
    None where four rounds do not complete the count (the interval is then solved in windows)."""
    t = time.perf_counter()
    factor, lam_known, X_known = known
    inside = (lam_known > low) & (lam_known <= top)
    values, vectors, deflate = [lam_known[inside]], [X_known[:, inside]], X_known
    found, n = int(inside.sum()), A.shape[0]
    for _round in range(4):
        for solve, shift in (*ends, factor):
            if found >= expected or deflate.shape[1] + 2 >= n - 2:
                break
            lam, X = _lanczos(A, B, shift, min(expected - found + 2, n - 2 - deflate.shape[1]), solve,
                              deflate=deflate)
            new = (lam > low) & (lam <= top)
            values.append(lam[new])
            vectors.append(X[:, new])
            found += int(new.sum())
            deflate = np.hstack([deflate, X])
    if found != expected:
        log.info("band: %d of %d modes from the known ones and their shift; solving in windows", found, expected)
        return None
    lam, X = np.concatenate(values), np.hstack(vectors)
    order = np.argsort(lam, kind="stable")
    return EigenSolution(lam[order], X[:, order], 0.0, time.perf_counter() - t, "reused", expected=expected)


def _interval(A, B, low, below_low, top, below_top, solver, counter) -> EigenSolution:
    """Every eigenpair with lam in (low, top], whose Sturm counts are given: windows of at most ``WINDOW_MODES``
    modes, each solved at its midpoint (or its lower end, ``_SturmCounter.bottom_solve``), missing modes (a multiple
    eigenvalue Lanczos met once) sought again with the found ones deflated; SolverError if the count is still not
    met."""
    t0 = time.perf_counter()
    expected = below_top - below_low
    stack, windows = [(low, below_low, top, below_top)], []
    while stack:
        a, ca, b, cb = stack.pop()
        if cb - ca == 0:
            continue
        if cb - ca <= WINDOW_MODES or b - a <= 1e2 * counter.scale:  # a cluster narrower than a good shift
            windows.append((a, ca, b, cb))
            continue
        mid, cm = counter.count_near(0.5 * (a + b), outward=+1)
        stack += [(mid, cm, b, cb), (a, ca, mid, cm)]
    t_fact = time.perf_counter() - t0
    values, vectors, seconds_eig, used = [], [], 0.0, ""
    n = A.shape[0]
    for a, ca, b, cb in windows:
        t = time.perf_counter()
        mid = 0.5 * (a + b)
        bottom = counter.bottom_solve(a, ca) if mid >= 1e2 * counter.scale else None
        if bottom is not None:
            (solve, used), moved = bottom, a
        else:
            if mid < 1e2 * counter.scale:
                # a window at ~0 Hz (rigid-body modes): a shift below it, where its modes are the nearest
                # (a shift amid a free body's rigid modes is singular, see ``_lowest``)
                mid = min(a, 0.0) - 1e2 * counter.scale
            solve, used, moved = _factor_nudged(A, B, mid, solver)
        t_fact += time.perf_counter() - t
        t = time.perf_counter()
        want = cb - ca
        lam_w, X_w, seen = np.empty(0), np.empty((n, 0)), np.empty((n, 0))
        for _attempt in range(4):
            # every pair found so far deflated, those outside the window too: else the modes nearer the shift than the
            # window's missing ones came back in every attempt (a free steel ring's 100-8000 Hz band on a coarse
            # estimate level: 6 of 8 found)
            k = min(want - len(lam_w) + 2, n - 2 - seen.shape[1])
            if k < 1:
                break
            lam, X = _lanczos(A, B, moved, k, solve, deflate=seen)
            inside = (lam > a) & (lam <= b)
            lam_w, X_w = np.concatenate([lam_w, lam[inside]]), np.hstack([X_w, X[:, inside]])
            seen = np.hstack([seen, X])
            if len(lam_w) >= want:
                break
            log.info("window %.6g-%.6g: %d of %d modes found; deflating and searching again", a, b, len(lam_w), want)
        seconds_eig += time.perf_counter() - t
        if len(lam_w) != want:
            hz = np.sqrt(np.clip([a, b], 0, None)) / (2 * np.pi)
            raise SolverError(f"band: the Sturm count finds {want} modes in {hz[0]:.6g}-{hz[1]:.6g} Hz but the "
                              f"eigen solve found {len(lam_w)}; the result would be incomplete")
        values.append(lam_w)
        vectors.append(X_w)
    lam = np.concatenate(values)
    X = np.hstack(vectors)
    order = np.argsort(lam, kind="stable")
    lam, X = lam[order], X[:, order]
    if len(lam) != expected:
        raise SolverError(f"band: {len(lam)} modes found against a Sturm count of {expected}")
    log.info("%d modes in %d windows, complete by Sturm count", expected, len(windows))
    return EigenSolution(lam, X, t_fact, seconds_eig, used, expected=expected)


def sturm_count(A, B, sigma: float, solver: str = "auto") -> int:
    """Number of finite eigenvalues of A x = lam B x below ``sigma`` (module docstring)."""
    return negative_eigenvalue_count(Shifted(A, B, sigma), solver=solver) - _massless_negatives(A, B, solver)


def _massless_negatives(A, B, solver: str) -> int:
    """Negative eigenvalues of A on the unknowns without inertia (zero rows of the positive semi-definite B:
    a zero diagonal), which add to every shifted inertia and belong to no finite eigenvalue."""
    massless = np.flatnonzero(sp.csr_matrix(B).diagonal() == 0)
    if len(massless) == 0:
        return 0
    A = sp.csr_matrix(A)
    return negative_eigenvalue_count(A[massless][:, massless], solver=solver)


class _SturmCounter:
    """Sturm counts at shifts moved off the eigenvalues they would sit on; the factorizations of the counts asked to
    be kept (``kept``: shift -> (A - shift B, PARDISO factor))."""

    def __init__(self, A, B, solver, offset):
        self.A, self.B, self.solver, self.offset = A, B, solver, offset
        self.scale = _shift_scale(A, B)
        self.kept: dict[float, tuple] = {}

    def count_near(self, sigma: float, outward: int, *, keep: bool = False) -> tuple[float, int]:
        """(shift used, count below it): ``sigma``, else moved ``outward`` (+1 up, -1 down) by growing steps."""
        for step in (0.0, *(abs(x) for x in NUDGES)):
            shift = sigma + outward * step * max(abs(sigma), self.scale)
            try:
                matrix = Shifted(self.A, self.B, shift)
                negative, factor = counted_factorization(matrix, solver=self.solver)
            except SolverError as exc:
                log.info("Sturm count at %.6g: %s; moving the shift", shift, exc)
                continue
            if keep and factor is not None:
                self.kept[shift] = (matrix, factor)
            return shift, negative - self.offset
        raise SolverError(f"band: no regular shift found near {np.sqrt(abs(sigma)) / (2 * np.pi):.6g} Hz")

    def bottom_solve(self, a: float, below_a: int):
        """(solve, solver name) of A - a B from the count kept at ``a``, for a window (a, b] with no finite eigenvalue
        below a >= 0: its modes are then the ones nearest a, and shift-invert there finds them as at its midpoint,
        one factorization fewer (a band's three: the counts at both ends and the window's shift). None otherwise:
        modes below a (a free body's rigid ones at ~0) would be nearer a than the window's top."""
        if below_a != 0 or a < 0:
            return None
        solve = self.solve_at(a)
        return None if solve is None else (solve, "pardiso")

    def solve_at(self, shift: float):
        """The solve with A - shift B of the count kept at ``shift``; None where none was kept, or its pivots
        make it unfit to solve with (``modalfe.solve.linalg.checked``)."""
        if shift not in self.kept:
            return None
        try:
            return checked(*self.kept[shift], "pardiso")
        except SolverError:
            return None


def _shift_scale(A, B) -> float:
    """A small eigenvalue scale [rad^2/s^2] to move a zero shift by: 1e-8 of mean diag(A) / mean diag(B) over
    the unknowns with inertia (~ the mesh's highest eigenvalue, so some Hz for a solid)."""
    d = sp.csr_matrix(B).diagonal()
    heavy = d > 0
    if not heavy.any():
        return 1.0
    return 1e-8 * float(np.abs(sp.csr_matrix(A).diagonal()[heavy]).mean() / d[heavy].mean())


def _factor_nudged(A, B, sigma: float, solver: str):
    """(solve, solver name, shift factored): A - sigma B, else the first regular shift moved by ``NUDGES``
    (relative to sigma, or to a small eigenvalue scale for a zero shift), said in the log."""
    try:
        solve, used = factorize(Shifted(A, B, sigma), solver=solver)
        return solve, used, sigma
    except SolverError as exc:
        first = exc
    scale = max(abs(sigma), _shift_scale(A, B))
    for step in NUDGES:
        # a zero shift (a free body's rigid modes) moves down: nearness to 0 keeps its order for lam >= 0
        moved = sigma + (-abs(step) if sigma == 0 else step) * scale
        try:
            solve, used = factorize(Shifted(A, B, moved), solver=solver)
        except SolverError:
            continue
        log.warning("shift %.6g is singular (on an eigenvalue?); moved to %.6g", sigma, moved)
        return solve, used, moved
    raise SolverError(f"no regular shift near {np.sqrt(abs(sigma)) / (2 * np.pi):.6g} Hz ({first})")


def lanczos_vectors(k: int, n: int) -> int:
    """ARPACK's Lanczos basis size for ``k`` modes of ``n`` unknowns: 2k + 1, at least k + 8. Measured on the
    Cu-Be plate's (0,6) mode: one mode in 10 solves (scipy's floor of 20 vectors took 21), 8 modes in 39 (36)."""
    return min(n, max(2 * k + 1, k + 8))


def _lanczos(A, B, sigma: float, k: int, solve, deflate=None, start=None) -> tuple[np.ndarray, np.ndarray]:
    """ARPACK shift-invert on the factorization ``solve`` of A - sigma B: (values sorted, vectors). With
    ``deflate`` (n, m) B-orthonormal eigenvectors, the operator is projected B-orthogonally to them (their
    inverted eigenvalues become 0, never returned), so that the other copies of a multiple eigenvalue appear.
    ``start`` (n,): the start vector, else a fixed generic one; one near the sought eigenvectors' span (the
    short-circuit modes for the open circuit of the same model) converges in fewer solves (the Cu-Be plate's open
    circuit, 4 modes: 19 solves against 24), and a thousandth of the generic one is added to it so that no eigenvector
    it lacks is missed."""
    n = A.shape[0]
    if deflate is not None and deflate.shape[1]:
        V, BV = deflate, B @ deflate

        def matvec(b):
            x = solve(b)
            return x - V @ (BV.T @ x)
    else:
        matvec = solve
    op = LinearOperator(A.shape, matvec=matvec, dtype=float)
    # a fixed, generic Lanczos start vector: the same answer on every run (ARPACK's default is random)
    generic = np.random.default_rng(0 if deflate is None else deflate.shape[1]).standard_normal(n)
    v0 = generic if start is None else start / np.linalg.norm(start) + 1e-3 * generic / np.linalg.norm(generic)
    try:
        lam, X = eigsh(A, k=k, M=B, sigma=sigma, which="LM", OPinv=op, tol=1e-8, v0=v0,
                       ncv=lanczos_vectors(k, n))
    except (ArpackNoConvergence, ArpackError) as exc:
        near_hz = np.sqrt(abs(sigma)) / (2 * np.pi)
        raise SolverError(f"the eigen solve did not converge near {near_hz:.4g} Hz: {exc}") from None
    if not np.all(np.isfinite(lam)):
        raise SolverError("the eigen solve returned NaN eigenvalues")
    order = np.argsort(lam, kind="stable")
    return lam[order], X[:, order]
