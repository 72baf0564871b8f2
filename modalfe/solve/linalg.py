"""Sparse direct factorization for shift-invert: PARDISO (MKL, via pypardiso) when installed,
else SuperLU with a symmetric ordering. Both are checked by the residual of one solve."""

from __future__ import annotations

import contextlib
import ctypes
import functools
import glob
import logging
import os
import sys
import weakref

import numpy as np
import scipy.sparse as sp

import modalfe.caches as caches
from modalfe.errors import SolverError

log = logging.getLogger(__name__)

# a PARDISO solve whose relative residual is above this gets MKL's iterative refinement on every solve
# (``_PardisoFactor.refine``). Bare solves over the report's 73 factorizations: median 1.2e-12; the tile's solid
# (springs, a 2.3 kg mass smeared on a 0.8 mm facing) up to 1.8e-8, whose 5 eigen solves then refine
REFINED_ABOVE = 1e-10
# PARDISO orders a matrix with at least this many nonzeros a row by minimum degree, else by nested dissection (MKL's
# default). Measured, one thread, factorization seconds nested dissection / minimum degree: cubic and quartic
# Lagrange hexahedra (283-560 a row) 0.22 / 0.11 (Cu-Be plate, cubic, 7,048 DOFs), 0.77 / 0.36 (quartic, 15,514),
# 1.11 / 0.48 (glass plate, quartic, 18,348), 1.72 / 1.22 (Cu-Be, quartic, 30,170), 1.31 / 1.10 (tile, quartic,
# 23,088); quadratic serendipity (about 130 a row) 2.19 / 4.31 (Cu-Be, 34,547), 0.47 / 0.55 (tile, 12,103),
# 11.1 / 27.1 (glass, 93,994): few large dense element blocks make the dissection's graph partitioning the larger cost
MINIMUM_DEGREE_ROWS = 200


def available_solvers() -> list[str]:
    """Direct solvers usable here, fastest first: PARDISO when MKL loads, SuperLU always."""
    return (["pardiso"] if _mkl_found() else []) + ["superlu"]


@functools.cache
def _mkl_found() -> bool:
    """Whether pypardiso can load MKL; helps it find libmkl_rt in the base interpreter's lib folder
    (a virtual environment's own prefix does not have it), and remembers the answer."""
    if "PYPARDISO_MKL_RT" not in os.environ:  # must be set before pypardiso is imported
        for prefix in dict.fromkeys((sys.prefix, sys.base_prefix)):
            found = sorted(glob.glob(os.path.join(prefix, "lib", "libmkl_rt.so*"))
                           + glob.glob(os.path.join(prefix, "Library", "bin", "mkl_rt*.dll")), key=len)
            if found:
                os.environ["PYPARDISO_MKL_RT"] = found[0]
                break
    try:
        import pypardiso

        solver = pypardiso.PyPardisoSolver()
    except (ImportError, OSError) as exc:
        log.warning("PARDISO unavailable (%s): using SuperLU", exc)
        return False
    # pypardiso otherwise searches the whole environment for MKL on every new solver
    os.environ.setdefault("PYPARDISO_MKL_RT", solver.libmkl._name)
    return True


class Shifted:
    """A - shift B of symmetric A, B, not formed, for ``factorize`` and ``counted_factorization``: a factorization takes
    its upper triangle from the pair's ``_Pencil`` (made on the pair's first shift and kept while the pair lives), a
    residual multiplies by A and B. Every shift of a pair then has one pattern (PARDISO's analysis shared,
    ``_Analysis``) and costs one vector operation: forming A - s B and taking its triangle on every shift cost 0.2-0.4
    CPU seconds on the Cu-Be plate's quartic model (30,865 DOFs, 16.5 million entries; two patterns merged by
    ``scipy.sparse``)."""

    def __init__(self, A: sp.spmatrix, B: sp.spmatrix, shift: float):
        self.A, self.B, self.shift = A, B, float(shift)
        self.shape = A.shape

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        return self.A @ x - self.shift * (self.B @ x)

    def upper(self) -> sp.csr_matrix:
        """The upper triangle (diagonal included) in canonical form, on A's pattern (its explicit zeros kept) where
        B's pattern lies in it (a mass matrix in its stiffness matrix's), else the formed matrix's."""
        pencil = _pencil(self.A, self.B)
        if pencil is None:
            return upper_triangle(sp.csr_matrix(self.A - self.shift * self.B, dtype=float))
        return pencil.upper(self.shift)

    def tocsr(self) -> sp.csr_matrix:
        return sp.csr_matrix(self.A - self.shift * self.B)


class _Pencil:
    """A's upper triangle in canonical form and B's upper triangle's values placed in its pattern (``b``), so that
    the triangle of A - s B of any s is one vector operation on A's values, on A's index arrays (``aligned`` makes
    it; None where B has an entry outside A's pattern)."""

    def __init__(self, a: sp.csr_matrix, b: np.ndarray):
        self.a, self.b = a, b

    @classmethod
    def aligned(cls, A: sp.spmatrix, B: sp.spmatrix) -> _Pencil | None:
        a, b = (upper_triangle(sp.csr_matrix(X, dtype=float)) for X in (A, B))
        # each of b's entries' position in a: a's positions (1-based, exact in a float) multiplied entry by entry
        # with b's pattern keep exactly the positions of b's entries, in b's (canonical) order
        positions = sp.csr_matrix((np.arange(1.0, a.nnz + 1), a.indices, a.indptr), shape=a.shape)
        at = positions.multiply(sp.csr_matrix((np.ones(b.nnz), b.indices, b.indptr), shape=b.shape)).tocsr()
        if at.nnz != b.nnz:
            return None
        placed = np.zeros(a.nnz)
        placed[at.data.astype(np.int64) - 1] = b.data
        return cls(a, placed)

    def upper(self, shift: float) -> sp.csr_matrix:
        values = np.multiply(self.b, -shift)  # one new array: a factorization keeps its matrix's values
        values += self.a.data
        upper = sp.csr_matrix((values, self.a.indices, self.a.indptr), shape=self.a.shape)
        upper.has_sorted_indices = True  # a's rows, canonical: PARDISO reads them in order
        return upper


# the pairs shifted last, while both live (``_pencil``), with their pencil: a band's Sturm counts, its eigen shift and
# its residual are shifts of one pair
KEPT_PENCILS = 3
_PENCILS: list[list] = []  # [weakref to A, weakref to B, _Pencil or None (B outside A's pattern)]
caches.register("shifted pencils", _PENCILS.clear)


def _pencil(A: sp.spmatrix, B: sp.spmatrix) -> _Pencil | None:
    """The pencil of (A, B), made on the pair's first shift and kept with the last ``KEPT_PENCILS`` pairs; None where
    B's pattern does not lie in A's."""
    kept = next((k for k in _PENCILS if k[0]() is A and k[1]() is B), None)
    if kept is None:
        kept = [weakref.ref(A, _forget_dead), weakref.ref(B, _forget_dead), _Pencil.aligned(A, B)]
        _PENCILS[:] = [*_PENCILS[-(KEPT_PENCILS - 1):], kept]
    return kept[2]


def _forget_dead(_ref) -> None:
    """Drops the pencils whose A or B has died, as soon as one dies (a pencil holds A's triangle: 100 MB on the Cu-Be
    plate's quartic model)."""
    _PENCILS[:] = [k for k in _PENCILS if k[0]() is not None and k[1]() is not None]


def factorize(A, *, solver: str = "auto"):
    """Factor symmetric ``A`` (a sparse matrix or ``Shifted``; possibly indefinite); return (solve(b) -> x, solver
    name).

    Raises SolverError when ``A`` is singular to working precision (e.g. a shift on an eigenvalue).
    """
    A = A if isinstance(A, Shifted) else sp.csr_matrix(A)
    names = available_solvers() if solver == "auto" else [solver]
    last = None
    for name in names:
        try:
            solve = _pardiso(A) if name == "pardiso" else _superlu(A)
        except (RuntimeError, ValueError, ImportError) as exc:
            last = exc
            log.warning("%s factorization failed: %s", name, exc)
            continue
        return checked(A, solve, name), name
    raise SolverError(f"the shifted matrix is singular or ill-conditioned ({last}); move the shift")


# a solve at one shift from a factorization at another (``shifted_solve``) is accepted at the relative residual a bare
# PARDISO solve is (``REFINED_ABOVE``; GMRES aims 100x lower: measured 6.5e-14 beside the Cu-Be plate's (0,6), where
# forced solves at 0.97 f_r)
SHIFTED_RESIDUAL = REFINED_ABOVE
SHIFTED_ITERATIONS = 200  # most Krylov steps a shifted solve takes before it factorizes instead
SHIFTED_RESTART = 40  # GMRES's basis before a restart (the Cu-Be plate's solve beside resonance converges in 15)


def shifted_solve(A: sp.spmatrix, B: sp.spmatrix, shift: float, factor: tuple | None = None, *,
                  solver: str = "auto"):
    """solve(b) -> x with (A - shift B) x = b for symmetric A, B. ``factor`` (solve, its shift sigma) of A - sigma B,
    kept from an eigen solve: at ``shift`` == sigma that solve itself; at another shift GMRES on the operator
    (A - shift B) S^-1 (S = A - sigma B, right preconditioning: its residual is the true one), whose eigenvalues
    (lam - shift) / (lam - sigma) are 1 but for the few modes near the two shifts, converged to
    ``SHIFTED_RESIDUAL`` (a direct solve's bar; checked on A - shift B itself) in a few dozen solves with S
    instead of a new factorization; where it does not converge within ``SHIFTED_ITERATIONS``, or without
    ``factor``, A - shift B is factorized (``factorize``), once."""
    A = sp.csr_matrix(A)
    if factor is not None and factor[1] == shift:
        return factor[0]
    state: dict = {}

    def direct():
        if "solve" not in state:
            state["solve"] = factorize(Shifted(A, B, shift), solver=solver)[0]
        return state["solve"]

    if factor is None:
        return direct()
    from scipy.sparse.linalg import LinearOperator, gmres


    kept_solve, sigma = factor
    B = sp.csr_matrix(B)
    n = A.shape[0]
    # (A - shift B) S^-1 = I - (shift - sigma) B S^-1: a product with B, not with the shifted matrix (never formed)
    operator = LinearOperator((n, n), matvec=lambda y: y - (shift - sigma) * (B @ kept_solve(y)), dtype=float)

    def solve(b):
        b = np.asarray(b, dtype=float)
        if "solve" in state:
            return state["solve"](b)
        norm = np.linalg.norm(b)
        if norm == 0:
            return np.zeros_like(b)
        restart = min(SHIFTED_RESTART, SHIFTED_ITERATIONS)
        with single_threaded_blas():  # GMRES's many small dense products (``single_threaded_blas``)
            y, _ = gmres(operator, b, rtol=SHIFTED_RESIDUAL / 100, atol=0.0, restart=restart,
                         maxiter=-(-SHIFTED_ITERATIONS // restart))
        x = kept_solve(y)
        residual = np.linalg.norm(b - (A @ x - shift * (B @ x))) / norm  # the true one, whatever S's own error
        if residual <= SHIFTED_RESIDUAL and np.all(np.isfinite(x)):
            return x
        log.info("shifted solve: GMRES on the kept factorization left a residual %.1e; factorizing", residual)
        return direct()(b)

    return solve


def checked(A: sp.csr_matrix, solve, name: str):
    """``solve`` (a factorization of ``A`` by the solver ``name``) once its relative residual on a generic right-hand
    side is below 1e-6; a PARDISO one whose bare residual reaches ``REFINED_ABOVE`` refines its solves from now on.
    SolverError if ``A`` is singular to working precision (a singular matrix defeats every direct solver alike)."""
    rng = np.random.default_rng(0)
    b = rng.standard_normal(A.shape[0])
    x = solve(b)
    residual = np.linalg.norm(A @ x - b) / np.linalg.norm(b)
    if name == "pardiso" and not residual < REFINED_ABOVE:
        solve.refine()
        x = solve(b)
        residual = np.linalg.norm(A @ x - b) / np.linalg.norm(b)
    if np.all(np.isfinite(x)) and residual < 1e-6:
        return solve
    raise SolverError(f"the shifted matrix is singular to working precision ({name}: relative residual "
                      f"{residual:.1e}); move the shift")


def _pardiso(A: sp.csr_matrix):
    """PARDISO's LDL^T of symmetric ``A`` as a solve(b) (``_PardisoFactor``), on the symbolic analysis of a live
    factorization with the same sparsity pattern where one has a free slot (``_Analysis``), else on a new one."""
    upper = A.upper() if isinstance(A, Shifted) else upper_triangle(sp.csr_matrix(A, dtype=float))
    if not np.diff(upper.indptr).all():  # PARDISO crashes on an empty row; such a matrix is singular anyway
        raise ValueError("the matrix is singular: it has an empty row")
    analysis = next((a for a in _live_analyses() if a.holds(upper)), None) or _Analysis(upper)
    return analysis.factor(upper)


# numeric factorizations one symbolic analysis holds (PARDISO's maxfct). The shifted matrices A - sigma B of one model
# share their pattern, and the analysis (reordering and symbolic factorization, phase 11) took about as long as the
# numeric factorization (phase 22): measured on the Cu-Be plate's quartic model (30,865 DOFs), 0.87 s and 0.58-0.95 s,
# so a band's Sturm counts and residual beside a kept eigen solve's factorization cost about half each (a further
# shift 0.68 s shared against 1.64 s with its own analysis, quiet machine: studies/pardiso_sharing.py)
SHARED_FACTORS = 8
_ANALYSES: list = []  # weak references to the live ``_Analysis`` objects (their factorizations keep them alive)


def _live_analyses() -> list:
    _ANALYSES[:] = [ref for ref in _ANALYSES if ref() is not None]
    return [ref() for ref in _ANALYSES]


def _mkl_threads(ps) -> int:
    """MKL's thread count now (``threadpoolctl`` limits change it)."""
    return int(ps.libmkl.MKL_Get_Max_Threads())


class _Analysis:
    """One PARDISO handle: the symbolic analysis (phase 11) of one sparsity pattern of upper triangles, holding up to
    ``SHARED_FACTORS`` numeric factorizations of matrices with that pattern (phase 22, numbered ``mnum``; MKL
    reference, pardiso: maxfct and mnum). MKL's defaults for the matrix type (pardisoinit: nested dissection, 1e-8
    pivot perturbation, Bunch-Kaufman pivots, no scaling or matching, two iterative refinement steps), but for the
    ordering of dense-row matrices (``MINIMUM_DEGREE_ROWS``) and no iterative refinement unless pivots were
    perturbed (``_PardisoFactor``)."""

    def __init__(self, upper: sp.csr_matrix):
        import pypardiso

        self._ps = ps = pypardiso.PyPardisoSolver(mtype=-2)  # real symmetric indefinite
        ps.libmkl.pardisoinit.restype = None
        ps.libmkl.pardisoinit(ps.pt.ctypes.data_as(ctypes.POINTER(ps._pt_type[0])), ctypes.byref(ctypes.c_int32(-2)),
                              ps.iparm.ctypes.data_as(ctypes.POINTER(ctypes.c_int32)))
        if upper.nnz >= MINIMUM_DEGREE_ROWS * upper.shape[0]:
            ps.iparm[1] = 0  # minimum degree ordering (MINIMUM_DEGREE_ROWS)
        ps.iparm[7] = 0
        self.threads = _mkl_threads(ps)  # a numeric factorization with other threads than its analysis crashed MKL
        # conditional numerical reproducibility on these threads (MKL reference, pardiso iparm[33]): the threads'
        # partial sums in a fixed order, so one matrix factorizes to the same bits in every call and process (two
        # factorizations of the Cu-Be plate's pencil differed by 5e-15 in 2 of 3 runs, none with it; no cost measured:
        # `modes` 0.97x on the ciliary beam, 0.93x on the Cu-Be plate, paired medians of 5)
        ps.iparm[33] = self.threads
        self.n = upper.shape[0]
        self.indptr, self.indices = upper.indptr, upper.indices
        self.ia, self.ja = (upper.indptr + 1).astype(np.int32), (upper.indices + 1).astype(np.int32)
        self.free = list(range(1, SHARED_FACTORS + 1))
        self.analysed, self.mixed = False, False
        _ANALYSES.append(weakref.ref(self))

    def holds(self, upper: sp.csr_matrix) -> bool:
        """Whether ``upper`` has this analysis' pattern and a slot is free for it, under the MKL threads every call on
        this handle has had (``single_threaded_blas`` limits them to one): a numeric factorization under other threads
        than its analysis, or after a solve under other threads, crashed MKL (segmentation fault)."""
        return bool(self.free) and self.analysed and not self.mixed and _mkl_threads(self._ps) == self.threads \
            and upper.shape[0] == self.n and upper.nnz == len(self.indices) \
            and np.array_equal(upper.indptr, self.indptr) and np.array_equal(upper.indices, self.indices)

    def call(self, phase: int, mnum: int, iparm: np.ndarray, data: np.ndarray, rhs: np.ndarray | None = None):
        """One PARDISO call on factorization ``mnum`` (x for a solve phase); RuntimeError on PARDISO's error code."""
        self.mixed = self.mixed or _mkl_threads(self._ps) != self.threads
        rhs = np.zeros((self.n, 1), order="F") if rhs is None else rhs
        x = np.zeros_like(rhs)
        error = ctypes.c_int32(0)
        ps, int_p, double_p = self._ps, ctypes.POINTER(ctypes.c_int32), ctypes.POINTER(ctypes.c_double)
        ps._mkl_pardiso(ps.pt.ctypes.data_as(ctypes.POINTER(ps._pt_type[0])),
                        ctypes.byref(ctypes.c_int32(SHARED_FACTORS)), ctypes.byref(ctypes.c_int32(mnum)),
                        ctypes.byref(ctypes.c_int32(ps.mtype)), ctypes.byref(ctypes.c_int32(phase)),
                        ctypes.byref(ctypes.c_int32(self.n)), data.ctypes.data_as(double_p),
                        self.ia.ctypes.data_as(int_p), self.ja.ctypes.data_as(int_p), ps.perm.ctypes.data_as(int_p),
                        ctypes.byref(ctypes.c_int32(rhs.shape[1])), iparm.ctypes.data_as(int_p),
                        ctypes.byref(ctypes.c_int32(0)), rhs.ctypes.data_as(double_p), x.ctypes.data_as(double_p),
                        ctypes.byref(error))
        if error.value != 0:
            raise RuntimeError(f"PARDISO phase {phase} failed (error {error.value})")
        return x

    def factor(self, upper: sp.csr_matrix) -> _PardisoFactor:
        """The numeric factorization of ``upper`` (this pattern) in a free slot, the analysis made first if not yet."""
        if not self.analysed:
            self.call(11, 1, self._ps.iparm, upper.data)
            self.analysed = True
        mnum, iparm = self.free.pop(0), self._ps.iparm.copy()
        try:
            self.call(22, mnum, iparm, upper.data)
        except RuntimeError:
            self.free.insert(0, mnum)
            raise
        return _PardisoFactor(self, mnum, iparm, upper.data)

    def release(self, mnum: int) -> None:
        """Frees factorization ``mnum`` (phase 0), and the whole handle with the last one (phase -1)."""
        self.free.append(mnum)
        last = len(self.free) == SHARED_FACTORS
        self.analysed = self.analysed and not last
        self.call(-1 if last else 0, mnum, self._ps.iparm, np.zeros(1))


def upper_triangle(A: sp.csr_matrix) -> sp.csr_matrix:
    """The upper triangle (diagonal included) of a square CSR matrix in canonical form (sorted, no duplicates), by
    one mask on its entries: the same matrix as ``scipy.sparse.triu``, whose round trip through COO took 3-5x as
    long (0.70 s against 0.13-0.20 s on the Cu-Be plate's quartic 30,865 unknowns, 16.5 million entries)."""
    rows = np.repeat(np.arange(A.shape[0], dtype=A.indices.dtype), np.diff(A.indptr))
    keep = A.indices >= rows
    indptr = np.zeros(A.shape[0] + 1, dtype=A.indptr.dtype)
    np.cumsum(np.bincount(rows[keep], minlength=A.shape[0]), out=indptr[1:])
    upper = sp.csr_matrix((A.data[keep], A.indices[keep], indptr), shape=A.shape)
    upper.sum_duplicates()  # sorts and sums in place where A was not canonical (a triple product's order)
    return upper


def negative_eigenvalue_count(A: sp.spmatrix, *, solver: str = "auto") -> int:
    """Number of negative eigenvalues of symmetric ``A`` (its inertia, Sylvester's law: the signs of D in
    A = L D L^T). PARDISO reports it for a symmetric indefinite factorization (MKL reference, iparm(23));
    if it had to perturb pivots, or without PARDISO, SuperLU with a symmetric ordering and no off-diagonal
    pivoting gives P A P^T = L U with U = D L^T, whose diagonal signs are the inertia (Golub & Van Loan,
    Matrix Computations, 4th ed., sec. 4.1 and 8.1). SolverError if ``A`` is singular to working precision or
    the count cannot be certified (an off-diagonal pivot)."""
    return counted_factorization(A, solver=solver)[0]


def counted_factorization(A, *, solver: str = "auto") -> tuple[int, object | None]:
    """(``negative_eigenvalue_count`` of ``A``, the PARDISO factorization that counted it as an unchecked solve(b),
    or None where SuperLU counted): a Sturm count's factorization can then also serve a shift-invert solve at
    its shift (``checked`` first). ``A``: a sparse matrix or ``Shifted``."""
    A = A if isinstance(A, Shifted) else sp.csr_matrix(A)
    n = A.shape[0]
    if n == 0:
        return 0, None
    if solver in ("auto", "pardiso") and _mkl_found():
        try:
            factor = _pardiso(A)
        except (RuntimeError, ValueError) as exc:
            log.warning("pardiso inertia failed (%s): using SuperLU", exc)
        else:
            negative = pardiso_inertia(factor, n)
            if negative is not None:
                return negative, factor
            iparm = factor.iparm
            log.info("pardiso perturbed %d pivots (inertia %d + %d of %d): SuperLU counts instead",
                     int(iparm[13]), int(iparm[21]), int(iparm[22]), n)
    from scipy.sparse.linalg import splu

    try:
        lu = splu(A.tocsr().tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options={"SymmetricMode": True})
    except RuntimeError as exc:
        raise SolverError(f"the shifted matrix is singular ({exc}); move the shift") from None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        raise SolverError("inertia: SuperLU pivoted off the diagonal, the Sturm count is not certified")
    d = lu.U.diagonal()
    if not np.all(np.isfinite(d)) or np.min(np.abs(d)) <= 1e-14 * np.max(np.abs(d)):
        raise SolverError("the shifted matrix is singular to working precision (a zero pivot); move the shift")
    return int(np.sum(d < 0)), None


def pardiso_inertia(solve, n: int) -> int | None:
    """The negative eigenvalue count of the (n, n) matrix a PARDISO factorization ``solve`` factored (the signs of its
    D, iparm(23)), None where it perturbed pivots, its inertia does not add up to n, or ``solve`` is not a PARDISO
    factorization (then nothing certifies a count)."""
    iparm = getattr(solve, "iparm", None)
    if iparm is None or int(iparm[13]) != 0 or int(iparm[21]) + int(iparm[22]) != n:
        return None
    return int(iparm[22])


class _PardisoFactor:
    """A PARDISO factorization (slot ``mnum`` of an ``_Analysis``) as a callable solve(b); frees its slot when dropped.

    Solves call MKL's solve phase (33) directly with the pattern's 1-based index arrays made once (pypardiso's solve
    re-hashes the matrix and its call re-indexes it, each time), without iterative refinement (``_Analysis`` sets
    iparm[7] = 0; MKL still refines where it perturbed pivots): its default two steps a solve, each one more solve
    and one product with the matrix, took 7x the time of a bare solve of the glass plate's quartic model (18,348
    DOFs: 0.085 s against 0.011 s, relative residuals 1.3e-13 and 1.5e-13). ``refine`` restores them, for a
    factorization whose residual needs them (``factorize``). ``iparm`` holds what its factorization reported
    (iparm[13] perturbed pivots, iparm[21] and iparm[22] the inertia)."""

    def __init__(self, analysis: _Analysis, mnum: int, iparm: np.ndarray, data: np.ndarray):
        self._analysis, self._mnum, self.iparm, self._data = analysis, mnum, iparm, data

    def refine(self) -> None:
        """Two iterative refinement steps on every solve from now on (MKL's default)."""
        self.iparm[7] = 2

    def __call__(self, b):
        """x = A^-1 b for b of shape (n,) or (n, m) (m right-hand sides in one call).
        PARDISO reads b as contiguous column-major memory: a strided view (a column of a C-ordered array) is copied
        first, never passed as is (it was read as the wrong numbers)."""
        b = np.asarray(b, dtype=float)
        rhs = np.asfortranarray(b.reshape(len(b), -1))
        x = self._analysis.call(33, self._mnum, self.iparm, self._data, rhs)
        return np.ascontiguousarray(x).reshape(b.shape)

    def __del__(self, suppress=contextlib.suppress):  # bound now: at interpreter shutdown the module's globals are gone
        with suppress(Exception):  # and MKL may be gone too
            self._analysis.release(self._mnum)


def _superlu(A: sp.csr_matrix):
    from scipy.sparse.linalg import splu

    lu = splu(A.tocsr().tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
    return lu.solve


def condition_estimate(A, solve) -> float:
    """1-norm condition number estimate ||A||_1 ||A^-1||_1 (Higham & Tisseur 2000 block estimator),
    with ``solve`` applying A^-1 (an existing factorization: no second one is made)."""
    from scipy.sparse.linalg import LinearOperator, onenormest

    inverse = LinearOperator(A.shape, matvec=solve, rmatvec=solve, dtype=float)  # A symmetric
    return float(onenormest(A) * onenormest(inverse))


def solve_complex(M: sp.csr_matrix, b: np.ndarray) -> np.ndarray:
    """x = M^-1 b for a complex sparse M (a damped harmonic solve): PARDISO on the real form [[Re, -Im], [Im, Re]]
    (measured 7-10x faster than SuperLU's complex LU on the k31 bar's 3.2k DOFs), SuperLU where PARDISO is missing."""
    b = np.asarray(b, dtype=complex)
    try:
        import pypardiso
    except ImportError:
        from scipy.sparse.linalg import splu

        return splu(M.tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True}).solve(b)
    R = sp.bmat([[M.real, -M.imag], [M.imag, M.real]], format="csr")
    solver = pypardiso.PyPardisoSolver(mtype=11)  # real non-symmetric
    y = solver.solve(R, np.r_[b.real, b.imag])
    solver.free_memory(everything=True)
    n = len(b)
    return y[:n] + 1j * y[n:]


def single_threaded_blas():
    """Context with one BLAS thread. numpy's OpenBLAS threads spin while they wait; on a small machine shared
    with MKL PARDISO's threads and other processes, the small dense operations of a solve (the labels'
    interpolation) then ran up to 100x slower (measured: the Cu-Be plate's report row 6 s with one BLAS thread,
    30-40 s with two under load). The heavy work is sparse (PARDISO has its own threads), so this costs nothing.
    OpenBLAS only: MKL, loaded for PARDISO, keeps its threads (a limit on every BLAS reached MKL only where it was
    loaded before the context was entered, so that the same factorization ran on one or two threads by call order)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController().select(internal_api="openblas").limit(limits=1)
