"""The eigen solve: shift-invert Lanczos (ARPACK) around a target with one sparse factorization.

The coupled piezoelectric problem K x = omega^2 M x has a singular M (no inertia on the potential);
ARPACK's shift-invert mode accepts a positive semi-definite M, and the potential unknowns only
add eigenvalues at infinity, which shift-invert maps to zero and never returns.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, LinearOperator, eigsh

from modalfe.errors import SolverError
from modalfe.solve.linalg import factorize

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class EigenSolution:
    """Eigenpairs of A x = lam B x sorted by lam: ``values`` (k,) [rad^2/s^2], ``vectors`` (n, k) B-orthonormal;
    seconds of the factorization and of the Lanczos iteration; the direct ``solver`` used."""

    values: np.ndarray
    vectors: np.ndarray
    factorization_seconds: float
    eigensolve_seconds: float
    solver: str


def eigenpairs(A, B, analysis, solver: str = "auto") -> EigenSolution:
    """Eigenpairs of A x = lam B x near ``analysis``'s target (``near`` and ``count``, or every mode in ``band``)."""
    two_pi = 2 * np.pi
    if analysis.band is not None:
        f1, f2 = analysis.band
        centre = 0.5 * (f1 + f2)
        sigma = (two_pi * centre) ** 2
        count = 12
    else:
        sigma = (two_pi * analysis.near) ** 2
        count = analysis.count
    n = A.shape[0]
    t = time.perf_counter()
    solve, used = _factor_shifted(A, B, sigma, solver)
    t_fact = time.perf_counter() - t
    op = LinearOperator(A.shape, matvec=solve, dtype=float)
    # a fixed, generic Lanczos start vector: the same answer on every run (ARPACK's default is random)
    start = np.random.default_rng(0).standard_normal(n)
    t = time.perf_counter()
    while True:
        k = min(count, n - 2)
        try:
            lam, X = eigsh(A, k=k, M=B, sigma=sigma, which="LM", OPinv=op, tol=1e-8, v0=start)
        except (ArpackNoConvergence, ArpackError) as exc:
            near_hz = np.sqrt(abs(sigma)) / two_pi
            raise SolverError(f"the eigen solve did not converge near {near_hz:.4g} Hz: {exc}") from None
        if not np.all(np.isfinite(lam)):
            raise SolverError("the eigen solve returned NaN eigenvalues")
        if analysis.band is None or k >= n - 2:
            break
        freqs = np.sqrt(np.abs(lam)) / two_pi
        # the returned set is the k nearest the centre: once it reaches past both band edges, all
        # modes inside are found (rigid-body modes sit at ~0 Hz, numerically a hair either side)
        low = max(analysis.band[0], 1e-6 * analysis.band[1])
        if freqs.min() <= low and freqs.max() >= analysis.band[1]:
            break
        if abs(freqs - centre).max() > max(centre - analysis.band[0], analysis.band[1] - centre):
            break
        count *= 2
    t_eig = time.perf_counter() - t
    order = np.argsort(lam)
    lam, X = lam[order], X[:, order]
    if analysis.band is not None:
        freqs = np.sqrt(np.clip(lam, 0, None)) / two_pi
        keep = (freqs >= analysis.band[0] - 1e-6 * analysis.band[1]) & (freqs <= analysis.band[1])
        lam, X = lam[keep], X[:, keep]
        if len(lam) == 0:
            raise SolverError(f"no modes in the band {analysis.band[0]:g}-{analysis.band[1]:g} Hz")
    return EigenSolution(lam, X, t_fact, t_eig, used)


def _factor_shifted(A, B, sigma, solver):
    """Factor A - sigma B; on a singular shift, move it by 1e-6 relative once and say so."""
    try:
        return factorize(A - sigma * B, solver=solver)
    except SolverError:
        moved = sigma * (1 + 1e-6) if sigma else 1e-6 * abs(A.diagonal()).mean() / abs(B.diagonal()).mean()
        log.warning("shift %.6g is singular (on an eigenvalue?); moved to %.6g", sigma, moved)
        return factorize(A - moved * B, solver=solver)
