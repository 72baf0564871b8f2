"""The open circuit of a model solved in short circuit, from that solve.

The open circuit's unknowns are the short circuit's plus one potential per floating electrode (the last ones), which
carry no mass: its matrix is the short one bordered, [[A, b], [b^T, c]], and the floating potentials condense out,
phi = -c^-1 b^T u, leaving (A - b c^-1 b^T) u = lam B u: the short-circuit pencil stiffened by a rank-m term (m
floating electrodes; Allik & Hughes, Int. J. Numer. Meth. Eng. 2 (1970) 151, the static condensation of the
potential). Each open mode near the short solve's shift sigma is then

    u = sum_r phi_r (phi_r^T b) / (lam_r - lam) + sum_j (lam - sigma)^j (S^-1 B)^j S^-1 b_left,   S = A - sigma B

(times the floating potentials), the short modes phi_r nearest sigma and a power series in the rest (b_left: b with
those modes' part taken out), which converges as (lam - sigma) / (the distance from sigma to the nearest short mode not
kept). So the short modes and a few Krylov blocks S^-1 B ... S^-1 b_left, each one solve with the factorization the
short solve kept, span the open modes near sigma to working precision: a Rayleigh-Ritz projection on them gives the
open eigenpairs without a factorization or a Lanczos run of their own (``bordered_ritz``).
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.linalg as sla

from modalfe.models.constraints import free_values

log = logging.getLogger(__name__)

MAX_BLOCKS = 20  # Krylov blocks tried before the Lanczos search answers instead
CONVERGED = 1e-11  # relative change of every sought Ritz value over one more block that ends the extension (its
# frequency to 5e-12: far below the 1e-9 the commands must agree to, and below every printed digit)
RESIDUAL = 1e-6  # most relative residual of a sought Ritz pair (a spurious interior Ritz value has one near 1)


def open_circuit_solve(b: np.ndarray, c: np.ndarray, factor: tuple) -> tuple:
    """(solve, shift) with A_open - shift B_open from the short-circuit factorization ``factor`` of the same model:
    the open circuit's unknowns are the short circuit's plus one potential per floating electrode (the last
    columns of ``PiezoUnknowns.constraints``), which carry no mass, so the shifted matrix is the short one
    bordered by [b; c] (``Constraints.border``) and solves by its Schur complement c - b^T S^-1 b (one block solve,
    a column per floating electrode)."""
    short_solve, shift = factor
    if b.shape[1] == 0:  # no floating electrode in this model: the same matrix
        return factor
    n_short = b.shape[0]
    W = short_solve(b).reshape(b.shape)
    schur = c - b.T @ W

    def solve(r):
        x = short_solve(r[:n_short])
        y = np.linalg.solve(schur, r[n_short:] - b.T @ x)
        return np.concatenate([x - W @ y, y])

    return solve, shift


def open_circuit_start(T, known, solve, floating: int) -> np.ndarray:
    """A Lanczos start vector for the open-circuit modes from the short-circuit ones ``known`` of the same model
    (open-circuit unknowns ``T``): their sum, each B-normalised, and the static response to a charge on each of
    the ``floating`` electrodes (the open circuit's last unknowns; ``solve`` with the open matrix at the shift),
    scaled like one mode: the open modes are the short ones but for that part."""
    x = free_values(T, np.column_stack([m.shape for m in known])).sum(axis=1)
    n = len(x)
    for j in range(n - floating, n):
        charge = np.zeros(n)
        charge[j] = 1.0
        static = solve(charge)
        x = x + static * (np.linalg.norm(x) / len(known) / np.linalg.norm(static))
    return x


def bordered_ritz(b: np.ndarray, c: np.ndarray, A_short, B_short, factor: tuple, Phi: np.ndarray, count: int):
    """(values (count,), vectors (n_open, count)): the ``count`` open-circuit eigenpairs nearest the shift of the
    short-circuit pencil (``A_short``, ``B_short``; its factorization ``factor``: solve, sigma) bordered by the
    floating electrodes' ``b`` and ``c`` (``Constraints.border``), by Rayleigh-Ritz
    on the short modes ``Phi`` (n_short, k; the solve's) and Krylov blocks S^-1 b, S^-1 B S^-1 b, ... each made
    B-orthogonal to the space before (so S^-1 b_left: module docstring), one block more until every sought Ritz
    value changes by less than ``CONVERGED`` of itself and its residual is below ``RESIDUAL``. Each block costs one
    solve and one product with B: its product with A follows from the solve's (A y = r + sigma B y for y = S^-1 r).
    Vectors B-orthonormal, floating potentials last. An open mode the electrodes do not couple (b^T phi = 0) is a
    short mode unchanged, which no block reaches: it is among the answer only if in ``Phi``. None where
    ``MAX_BLOCKS`` blocks do not converge (the Lanczos search then answers)."""
    solve, sigma = factor
    c_inv_bT = np.linalg.solve(c, b.T)
    empty = np.zeros((A_short.shape[0], 0))
    space = _extended((empty, empty, empty), (Phi, B_short @ Phi, A_short @ Phi))
    raw, previous = b, None  # the next block's right-hand side; the Ritz values before it
    for blocks in range(1, MAX_BLOCKS + 1):
        block = solve(raw).reshape(raw.shape)
        B_block = B_short @ block
        grown = _extended(space, (block, B_block, raw + sigma * B_block))
        if grown[0].shape[1] == space[0].shape[1]:  # the space is invariant: no new direction
            break
        raw, space = grown[1][:, space[0].shape[1]:], grown
        basis, B_basis, A_basis = space
        K_basis = A_basis - b @ (c_inv_bT @ basis)  # the condensed open-circuit stiffness (A - b c^-1 b^T) on it
        theta, S = sla.eigh(basis.T @ K_basis, basis.T @ B_basis)
        if len(theta) < count:
            continue
        nearest = np.sort(np.argsort(np.abs(theta - sigma), kind="stable")[:count])
        values, coefficients = theta[nearest], S[:, nearest]
        stiff = K_basis @ coefficients
        residual = np.linalg.norm(stiff - (B_basis @ coefficients) * values, axis=0)
        settled = previous is not None and np.all(np.abs(values - previous) <= CONVERGED * np.abs(values))
        if settled and np.all(residual < RESIDUAL * np.maximum(np.linalg.norm(stiff, axis=0), 1e-300)):
            log.info("open circuit: %d modes by Rayleigh-Ritz on %d short modes and %d Krylov blocks", count,
                     Phi.shape[1], blocks)
            vectors = basis @ coefficients
            return values, np.vstack([vectors, -(c_inv_bT @ vectors)])
        previous = values
    log.info("open circuit: Rayleigh-Ritz not settled in %d Krylov blocks; Lanczos instead", MAX_BLOCKS)
    return None


def _extended(space: tuple, new: tuple) -> tuple:
    """The basis (V, B V, A V) ``space`` (V B-orthonormal) with the columns of ``new`` (X, B X, A X) added: made
    B-orthogonal to V (twice: classical Gram-Schmidt loses orthogonality once) and B-orthonormal, the columns that
    are (numerically) in V's span dropped."""
    V, BV, AV = space
    X, BX, AX = new
    for _ in range(2):
        coefficients = BV.T @ X
        X, BX, AX = X - V @ coefficients, BX - BV @ coefficients, AX - AV @ coefficients
    gram = 0.5 * (X.T @ BX + BX.T @ X)
    size, axes = np.linalg.eigh(gram) if gram.size else (np.zeros(0), np.zeros((0, 0)))
    keep = size > 1e-12 * max(size.max(initial=0.0), np.finfo(float).tiny)
    to_unit = axes[:, keep] / np.sqrt(size[keep])
    return np.hstack([V, X @ to_unit]), np.hstack([BV, BX @ to_unit]), np.hstack([AV, AX @ to_unit])
