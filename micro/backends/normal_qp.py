"""The least-distance QP ``min 1/2 |x - t|^2, A x = b, lower <= x <= upper``: two back ends.

The proximal selection of the iterated LP (:mod:`micro.nonassociative.proximal`)
projects its ``nbar`` onto the force fields its LP allows; this module holds the
solvers of that projection, so that the method itself imports no solver (only
``micro.backends`` does). Both are built once and solve a sequence of QPs whose
matrix ``A`` stays and whose ``t``, ``b`` and bounds change.

:class:`LeastDistanceQP`, the default: an interior point on the normal
equations. With the identity Hessian and bounds only, each Newton system
reduces, as for the associative LP of ``normal-ipm``
(:mod:`micro.backends.normal_ipm`), to one system with ``A diag(1 / h) A^T`` of
order ``rows`` (``3 n_blocks`` for a wall), ``h = 1 + z_l / (x - lower) + z_u /
(upper - x)``, factorised by CHOLMOD
(:class:`~micro.backends.normal_matrix.NormalMatrix`) where Clarabel
factorises a KKT system with a row per variable and per bound. CHOLMOD's
simplicial factorisation, not its supernodal one: the supernodal kernels are
BLAS calls, whose last bits differ between OpenBLAS's kernels, and the
projection decides the next ``nbar``; with them Set 9's sequence reached
another state on another machine
(the research page on the BLAS-independent descent (``docs/research/``)). Mehrotra's
predictor-corrector, one step length for the primal and the dual (the
Hessian couples them). Why it is the default (faster per QP than Clarabel on
the walls where the proximal selection runs): the measurement is on
the research page on the proximal projection (``docs/research/``).

:class:`ClarabelLeastDistance`: the same QP by Clarabel's interior point, where
the first does not converge. Clarabel's ``update`` changes ``q`` and ``b``
only, so its presolve is off and the bound rows are fixed when it is built:
the columns with a finite lower bound and no upper one first (``-x <= -lower``),
then the boxed columns' upper rows (``x <= upper``), then their lower rows. The
order is part of the contract: it decides the factorisation's rounding, and
with it every projection the golden values were computed with.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import clarabel
import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.clarabel import clarabel_settings, solve_interruptibly
from micro.backends.normal_matrix import (
    InteriorPointSettings,
    InteriorPointStop,
    NormalMatrix,
    NotPositiveDefinite,
    one_blas_thread,
)

FloatArray = NDArray[np.float64]

#: Clarabel statuses whose solution is taken as the answer.
CLARABEL_SOLVED = ("Solved", "AlmostSolved")


@dataclass(frozen=True)
class LeastDistanceSettings(InteriorPointSettings):
    """Tolerances and limits of :class:`LeastDistanceQP` (the fields of
    :class:`~micro.backends.normal_matrix.InteriorPointSettings`: the gap is the
    sum of the complementarity products relative to ``1 +`` the objective, the
    primal residual relative to ``1 + max |b|``, the dual one to ``1 + max |t|``).

    Attributes:
        start_floor: the starting ``x`` is at least this fraction of
            ``max |t|`` above its lower bound (an interior start).
    """

    NUMBERS = (*InteriorPointSettings.NUMBERS, "start_floor")

    start_floor: float = 1e-2


#: The settings of the proximal projection.
LEAST_DISTANCE = LeastDistanceSettings()


@dataclass(frozen=True, eq=False)
class LeastDistanceResult(InteriorPointStop):
    """Where the interior point stopped (the fields of
    :class:`~micro.backends.normal_matrix.InteriorPointStop`, and the answer).

    Attributes:
        x: the last iterate (the projection when :attr:`converged`).
        seconds: wall time.
    """

    x: FloatArray
    seconds: float


class LeastDistanceQP:
    """``min 1/2 |x - t|^2`` s.t. ``A x = b``, ``lower <= x <= upper``, by the interior point on the
    normal equations (module docstring).

    Args:
        A: ``(rows, columns)`` sparse matrix of full row rank; the pattern
            is analysed once, every :meth:`solve` changes ``t``, ``b`` and the bounds.
        settings: tolerances and limits.
    """

    def __init__(self, A: sp.spmatrix, settings: LeastDistanceSettings = LEAST_DISTANCE) -> None:
        self.settings = settings
        # simplicial: CHOLMOD's supernodal kernels are BLAS calls, whose last bits depend on the
        # kernel, and the projection decides the next nbar (the path of the sequence)
        self.M = NormalMatrix(A, regularization=settings.regularization, supernodal=False,
                              refine_steps=settings.refine_steps, refine_tol=settings.refine_tol)
        self.A, self.AT = self.M.A, self.M.AT

    def solve(self, t: FloatArray, b: FloatArray, lower: FloatArray, upper: FloatArray) -> LeastDistanceResult:
        """The projection of ``t`` (module docstring).

        Args:
            t: the point projected, ``(columns,)``.
            b: the equality right-hand side, ``(rows,)``.
            lower: finite lower bounds.
            upper: upper bounds (``inf``: none); ``upper <= lower`` fixes the column at ``lower``.
        """
        t0 = time.perf_counter()
        # an infeasible QP drives the iterates to overflow: the run then says "not finite"
        with one_blas_thread(), np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            out = self._run(np.asarray(t, float), np.asarray(b, float), np.asarray(lower, float),
                            np.asarray(upper, float))
        x, reason, iterations, gap, primal, dual = out
        return LeastDistanceResult(reason=reason, iterations=iterations, gap=gap, primal=primal, dual=dual, x=x,
                                   seconds=time.perf_counter() - t0)

    def _run(self, t: FloatArray, b: FloatArray, lower: FloatArray,
             upper: FloatArray) -> tuple[FloatArray, str, int, float, float, float]:
        st, A, AT = self.settings, self.A, self.AT
        free = upper > lower
        up = free & np.isfinite(upper)
        n_bounds = int(free.sum() + up.sum())
        lo = np.where(free, lower, 0.0)
        hi = np.where(up, upper, 0.0)
        scale = max(float(np.max(np.abs(t), initial=0.0)), 1.0)
        # the start: inside the box, near t
        width = np.where(up, upper - lower, np.inf)
        margin = np.minimum(st.start_floor * scale, 0.25 * width)
        x = np.where(free, np.clip(t, lower + margin, np.where(up, upper - margin, np.inf)), lower)
        zl = np.where(free, scale, 0.0)
        zu = np.where(up, scale, 0.0)
        y = np.zeros(A.shape[0])
        b_scale, t_scale = 1.0 + float(np.max(np.abs(b), initial=0.0)), 1.0 + scale
        gap = primal = dual = math.inf
        for it in range(1, st.max_iter + 1):
            sl = np.where(free, x - lo, 1.0)
            su = np.where(up, hi - x, 1.0)
            rd = np.where(free, x - t - AT @ y - zl + zu, 0.0)
            rp = A @ x - b
            products = float(np.sum((sl * zl)[free]) + np.sum((su * zu)[up]))
            objective = 0.5 * float(np.sum((x - t) ** 2))
            gap = products / (1.0 + objective)
            primal = float(np.max(np.abs(rp), initial=0.0)) / b_scale
            dual = float(np.max(np.abs(rd), initial=0.0)) / t_scale
            if not (math.isfinite(gap) and math.isfinite(primal) and math.isfinite(dual)):
                return x, "not finite", it, gap, primal, dual
            if gap <= st.gap_tol and primal <= st.primal_tol and dual <= st.dual_tol:
                return x, "converged", it - 1, gap, primal, dual
            mu = products / max(n_bounds, 1)
            dinv = np.where(free, 1.0 / (1.0 + zl / sl + np.where(up, zu / su, 0.0)), 0.0)
            try:
                self.M.factor_raising(dinv)
            except NotPositiveDefinite:
                return x, "not positive definite", it, gap, primal, dual
            frame = _Frame(free, up, sl, su, zl, zu, rd, rp, dinv)
            # Mehrotra: the affine direction, then the centred and corrected one
            dx, dy, dzl, dzu = self._direction(frame, np.where(free, -sl * zl, 0.0), np.where(up, -su * zu, 0.0))
            a = frame.longest(dx, dzl, dzu)
            mu_aff = float(np.sum(((sl + a * dx) * (zl + a * dzl))[free])
                           + np.sum(((su - a * dx) * (zu + a * dzu))[up])) / max(n_bounds, 1)
            sigma = (mu_aff / mu) ** 3 if mu > 0 else 0.0
            rcl = np.where(free, sigma * mu - sl * zl - dx * dzl, 0.0)
            rcu = np.where(up, sigma * mu - su * zu + dx * dzu, 0.0)
            dx, dy, dzl, dzu = self._direction(frame, rcl, rcu)
            a = min(1.0, st.step_fraction * frame.longest(dx, dzl, dzu))
            x, y, zl, zu = x + a * dx, y + a * dy, zl + a * dzl, zu + a * dzu
        return x, "iteration limit", st.max_iter, gap, primal, dual

    def _direction(self, f: _Frame, rcl: FloatArray,
                   rcu: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """The Newton direction ``(dx, dy, dz_l, dz_u)`` for the complementarity
        right-hand sides ``rcl``, ``rcu``: with ``dz_l``, ``dz_u`` eliminated the
        stationarity rows read ``H dx - A^T dy = r1``, and ``A dx = -r_p`` gives
        ``A H^{-1} A^T dy = -r_p - A H^{-1} r1`` (the factorised ``M``)."""
        r1 = np.where(f.free, -f.rd + rcl / f.sl - np.where(f.up, rcu / f.su, 0.0), 0.0)
        dy = self.M.solve(-f.rp - self.A @ (f.dinv * r1))
        dx = f.dinv * (r1 + self.AT @ dy)
        return dx, dy, np.where(f.free, (rcl - f.zl * dx) / f.sl, 0.0), np.where(f.up, (rcu + f.zu * dx) / f.su, 0.0)


@dataclass(frozen=True, eq=False)
class _Frame:
    """One iterate's slacks, multipliers, residuals and ``H^{-1}`` (masks: the free
    columns and those with a finite upper bound)."""

    free: NDArray[np.bool_]
    up: NDArray[np.bool_]
    sl: FloatArray
    su: FloatArray
    zl: FloatArray
    zu: FloatArray
    rd: FloatArray
    rp: FloatArray
    dinv: FloatArray

    def longest(self, dx: FloatArray, dzl: FloatArray, dzu: FloatArray) -> float:
        """The largest step ``<= 1`` that keeps every slack and multiplier non-negative."""
        a = 1.0
        for v, dv, mask in ((self.sl, dx, self.free), (self.su, -dx, self.up), (self.zl, dzl, self.free),
                            (self.zu, dzu, self.up)):
            neg = mask & (dv < 0.0)
            if np.any(neg):
                a = min(a, float(np.min(-v[neg] / dv[neg])))
        return a


@dataclass(frozen=True, eq=False)
class ClarabelAnswer:
    """Where Clarabel stopped.

    Attributes:
        x: the solution, or ``None`` when Clarabel's status is not in :data:`CLARABEL_SOLVED`.
        status: Clarabel's status.
        iterations: its iterations.
        seconds: wall time (the build included on the first solve).
    """

    x: FloatArray | None
    status: str
    iterations: int
    seconds: float


class ClarabelLeastDistance:
    """``min 1/2 |x - t|^2`` s.t. ``A x = b``, ``lower <= x <= upper`` by Clarabel (module docstring).

    Args:
        A: ``(rows, columns)`` sparse equality matrix.
        finite_lower, finite_upper: ``(columns,)`` masks of the columns with a
            finite lower (every column here) and a finite upper bound; fixed
            for the life of the solver (the bound rows are built once).
        settings: Clarabel settings by name (:func:`micro.backends.clarabel.clarabel_settings`).
        time_limit: seconds per solve (``inf``: none).
    """

    def __init__(self, A: sp.spmatrix, finite_lower: NDArray[np.bool_], finite_upper: NDArray[np.bool_],
                 settings: dict[str, Any], time_limit: float = math.inf) -> None:
        if not np.all(finite_lower):
            raise ValueError("ClarabelLeastDistance needs a finite lower bound on every column")
        self.A = sp.csc_matrix(A)
        self.one_sided = np.flatnonzero(~finite_upper)
        self.boxed = np.flatnonzero(finite_upper)
        self.settings, self.time_limit = settings, time_limit
        self.solver: clarabel.DefaultSolver | None = None  # built on the first solve

    def _rhs(self, b: FloatArray, lower: FloatArray, upper: FloatArray) -> FloatArray:
        """Equality rows, then ``-x <= -lower`` (one-sided), ``x <= upper``, ``-x <= -lower`` (boxed)."""
        return np.concatenate([b, 0.0 - lower[self.one_sided], upper[self.boxed], 0.0 - lower[self.boxed]])

    def solve(self, t: FloatArray, b: FloatArray, lower: FloatArray, upper: FloatArray) -> ClarabelAnswer:
        """The projection of ``t``: a new ``t``, ``b`` and new bound values (the same masks)."""
        t0 = time.perf_counter()
        q = 0.0 - np.asarray(t, float)
        rhs = self._rhs(np.asarray(b, float), np.asarray(lower, float), np.asarray(upper, float))
        if self.solver is None:
            n = self.A.shape[1]
            eye = sp.identity(n, format="csc")
            rows = sp.vstack([self.A, -eye[self.one_sided], eye[self.boxed], -eye[self.boxed]], format="csc")
            cones = [clarabel.ZeroConeT(self.A.shape[0]), clarabel.NonnegativeConeT(rows.shape[0] - self.A.shape[0])]
            settings = clarabel_settings(self.settings)
            settings.presolve_enable = False  # update() needs it off
            if math.isfinite(self.time_limit):
                settings.time_limit = float(self.time_limit)
            self.solver = clarabel.DefaultSolver(sp.identity(n, format="csc"), q, rows, rhs, cones, settings)
        else:
            self.solver.update(q=q, b=rhs)
        sol = solve_interruptibly(self.solver)
        status = str(sol.status)
        x = np.asarray(sol.x) if status in CLARABEL_SOLVED else None
        return ClarabelAnswer(x, status, int(sol.iterations), time.perf_counter() - t0)
