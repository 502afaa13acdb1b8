"""The normal-equations matrix ``M = A D A^T`` of an interior point, and its sparse Cholesky factor.

An interior point for the standard-form LP ``A x + f lambda = b, x >= 0``
solves, at every iteration, a system with ``M(d) = A diag(d) A^T`` for a new
positive diagonal ``d`` (:mod:`micro.backends.normal_ipm`). On a wall ``M``
has one row per equilibrium equation (``3 n_blocks``): 3,690 on the
1,230-block wall against the ~32,000 rows of the KKT system Clarabel
factorises there, and its pattern is fixed. So everything that depends only
on the pattern is done once here:

* the pattern of ``tril(A A^T)`` and a sparse map ``W`` with
  ``tril(M(d)).data = W d`` (each column of ``A`` adds the outer product of
  its few non-zeros), so forming ``M`` is one sparse product;
* CHOLMOD's symbolic analysis (fill-reducing ordering, supernodes), through
  cvxopt's binding (the SuiteSparse library in cvxopt's wheels; no other
  Python package ships CHOLMOD as a wheel). Per iteration only the numeric
  factorisation runs.

The supernodal factorisation of ``M`` is the fastest of those measured
(simplicial, SuperLU, QDLDL: the times, docs/speed.md).

Near the optimum ``d`` spans ~20 decades (``x_j / z_j`` of the generators
that carry force against those that do not) and CHOLMOD's last pivots lose
positivity to rounding. Every diagonal entry is therefore raised by
:attr:`NormalMatrix.regularization` times itself (a relative shift: an
absolute one is either lost on the large rows or swamps the small ones) and
solves are refined against the unshifted ``M`` (:meth:`NormalMatrix.solve`).

CHOLMOD's supernodal kernels are BLAS calls, and a multithreaded BLAS sums in
an order that depends on its thread count: the Table 9 wall came out at
lambda 0.507255117568 (40 iterations) with one OpenBLAS thread and
0.507255113477 (41) with two. :func:`one_blas_thread` (threadpoolctl) holds
BLAS to one thread while the interior point runs, so the load factor does not
depend on the machine's core count (the benchmarks measured one thread).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import scipy.sparse as sp

from micro.backends.base import FloatArray, check_integer, check_number


@contextlib.contextmanager
def cholmod_options(**options: int) -> Iterator[None]:
    """cvxopt's CHOLMOD options set to ``options`` within the block (they are module globals)."""
    from cvxopt import cholmod

    old = dict(cholmod.options)
    cholmod.options.update(options)
    try:
        yield
    finally:
        cholmod.options.clear()
        cholmod.options.update(old)


_CONTROLLER: Any = None


def one_blas_thread() -> contextlib.AbstractContextManager[Any]:
    """A context in which every BLAS library loaded (cvxopt's OpenBLAS among them) runs on one thread.

    The controller is made on first use, after cvxopt is imported (it finds
    the libraries loaded when it is made).
    """
    global _CONTROLLER
    if _CONTROLLER is None:
        import cvxopt.cholmod  # noqa: F401 - load cvxopt's BLAS before the controller looks
        from threadpoolctl import ThreadpoolController

        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER.limit(limits=1, user_api="blas")


class NotPositiveDefinite(ArithmeticError):
    """CHOLMOD met a non-positive pivot (the regularisation was too small)."""


class NormalMatrix:
    """``M(d) = A diag(d) A^T`` with its pattern analysed once (module docstring).

    Args:
        A: ``(n, m)`` sparse matrix of full row rank.
        regularization: the relative diagonal shift.
        supernodal: CHOLMOD's supernodal factorisation (``False``: simplicial,
            slower on walls (docs/speed.md), but no BLAS call: the same factors and
            solves under every BLAS kernel and on every CPU, for a solve that
            decides a path).
        refine_steps: refinement steps at most per solve.
        refine_tol: a solve stops refining when its residual is below this
            times the right-hand side (max norms).
    """

    def __init__(self, A: sp.spmatrix, *, regularization: float, supernodal: bool = True, refine_steps: int = 1,
                 refine_tol: float = 1e-10) -> None:
        from cvxopt import cholmod, matrix, spmatrix

        self._cholmod, self._matrix = cholmod, matrix
        A = sp.csc_matrix(A)
        A.sum_duplicates()
        A.sort_indices()
        self.A, self.AT = A, A.T.tocsr()
        n, m = A.shape
        self.regularization = regularization
        self.refine_steps = refine_steps
        self.refine_tol = refine_tol
        # every pair (p, q) of non-zeros of one column with row(p) >= row(q)
        count = np.diff(A.indptr)
        column = np.repeat(np.arange(m), count)
        per_nz = count[column]
        p = np.repeat(np.arange(A.nnz), per_nz)
        offset = np.arange(p.size) - np.repeat(np.cumsum(per_nz) - per_nz, per_nz)
        q = np.repeat(A.indptr[column], per_nz) + offset
        ri, rj = A.indices[p], A.indices[q]
        lower = ri >= rj
        p, q, ri, rj = p[lower], q[lower], ri[lower], rj[lower]
        # keys in CSC order of tril(M): column-major; the diagonal is always kept
        keys = np.concatenate([rj.astype(np.int64) * n + ri, np.arange(n, dtype=np.int64) * (n + 1)])
        unique, position = np.unique(keys, return_inverse=True)
        self.diagonal = position[p.size :]
        self.W = sp.csr_matrix((A.data[p] * A.data[q], (position[: p.size], column[p])), shape=(unique.size, m))
        rows = matrix((unique % n).astype(np.int64).tolist(), tc="i")
        cols = matrix((unique // n).astype(np.int64).tolist(), tc="i")
        self._M = spmatrix(np.ones(unique.size).tolist(), rows, cols, (n, n))
        with cholmod_options(supernodal=2 if supernodal else 0):
            self._factor = cholmod.symbolic(self._M)
        self.d: FloatArray = np.ones(m)
        self.factorizations = 0
        self.refinements = 0

    @property
    def nnz(self) -> int:
        """Non-zeros of ``tril(M)``."""
        return int(self.W.shape[0])

    def factor(self, d: FloatArray) -> None:
        """Factorise ``M(d)`` plus the relative diagonal shift.

        Raises:
            NotPositiveDefinite: CHOLMOD met a non-positive pivot.
        """
        self.d = d
        values = self.W @ d
        values[self.diagonal] *= 1.0 + self.regularization
        self._M.V = self._matrix(values)
        try:
            self._cholmod.numeric(self._M, self._factor)
        except ArithmeticError as err:
            raise NotPositiveDefinite(str(err)) from None
        self.factorizations += 1

    def factor_raising(self, d: FloatArray, raises: int = 2) -> None:
        """:meth:`factor`, raising the shift 100 times at most ``raises`` times
        when a pivot fails (the shift is restored after).

        Raises:
            NotPositiveDefinite: the factorisation failed with the largest shift.
        """
        reg = self.regularization
        try:
            for k in range(raises + 1):
                self.regularization = reg * 100.0**k
                try:
                    self.factor(d)
                    return
                except NotPositiveDefinite:
                    if k == raises:
                        raise
        finally:
            self.regularization = reg

    def product(self, v: FloatArray) -> FloatArray:
        """``M(d) v`` (one column or several) for the last ``d`` factorised, unshifted
        (the matrix of the refinement)."""
        d = self.d if v.ndim == 1 else self.d[:, None]
        return self.A @ (d * (self.AT @ v))

    def solve(self, rhs: FloatArray) -> FloatArray:
        """``M(d)^{-1} rhs`` (one column or several), refined against the unshifted ``M(d)``."""
        X = self._matrix(rhs)
        self._cholmod.solve(self._factor, X)
        v = np.array(X).reshape(rhs.shape)
        scale = np.max(np.abs(rhs), axis=0)
        for _ in range(self.refine_steps):
            r = rhs - self.product(v)
            if np.all(np.max(np.abs(r), axis=0) <= self.refine_tol * scale):
                break
            X = self._matrix(r)
            self._cholmod.solve(self._factor, X)
            v = v + np.array(X).reshape(rhs.shape)
            self.refinements += 1
        return v


@dataclass(frozen=True)
class InteriorPointSettings:
    """The tolerances and limits shared by the normal-equations interior points
    (``normal-ipm`` and the proximal QP's);
    each subclass sets its own defaults and adds its own fields.

    Attributes:
        gap_tol: relative duality gap at which it stops.
        primal_tol: largest equality residual (relative) at which it stops.
        dual_tol: largest dual residual (relative) at which it stops.
        step_fraction: fraction of the step to the boundary taken.
        regularization: relative shift of ``M``'s diagonal
            (:class:`NormalMatrix`); raised 100 times, at most twice, when a
            factorisation fails.
        refine_steps: refinement steps at most per solve with ``M``.
        refine_tol: a solve is refined until its residual is below this
            times its right-hand side.
        max_iter: iterations at most.
    """

    #: fields checked as positive finite numbers, and as integers of at least a minimum
    NUMBERS: ClassVar[tuple[str, ...]] = ("gap_tol", "primal_tol", "dual_tol", "refine_tol")
    INTEGERS: ClassVar[tuple[tuple[str, int], ...]] = (("refine_steps", 0), ("max_iter", 1))

    gap_tol: float = 1e-9
    primal_tol: float = 1e-9
    dual_tol: float = 1e-9
    step_fraction: float = 0.99
    regularization: float = 1e-14
    refine_steps: int = 2
    refine_tol: float = 1e-12
    max_iter: int = 100

    def __post_init__(self) -> None:
        """:attr:`NUMBERS` positive and finite, ``regularization`` non-negative,
        ``step_fraction`` in (0, 1), each of :attr:`INTEGERS` an integer of at
        least its minimum.

        Raises:
            ValueError: a bad setting (the message names it).
        """
        for name in self.NUMBERS:
            check_number(name, getattr(self, name))
        r = self.regularization
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not math.isfinite(r) or r < 0:
            raise ValueError(f"regularization must be a non-negative number, got {r!r}")
        if not (isinstance(self.step_fraction, float) and 0.0 < self.step_fraction < 1.0):
            raise ValueError(f"step_fraction must be in (0, 1), got {self.step_fraction!r}")
        for name, least in self.INTEGERS:
            check_integer(name, getattr(self, name), least)


@dataclass(frozen=True, eq=False)
class InteriorPointStop:
    """Where a normal-equations interior point stopped (each solver's result adds its answer).

    Attributes:
        reason: ``"converged"``, ``"iteration limit"``, ``"not positive definite"``,
            ``"not finite"`` (and ``normal-ipm``'s others).
        iterations: iterations run.
        gap, primal, dual: the last relative gap and residuals.
    """

    reason: str
    iterations: int
    gap: float
    primal: float
    dual: float

    @property
    def converged(self) -> bool:
        """The tolerances were met."""
        return self.reason == "converged"
