"""A least-distance QP with box bounds by an interior point on the normal equations.

The proximal selection of the iterated LP (:mod:`micro.nonassociative.proximal`)
projects its normal forces onto the force fields its LP allows::

    minimise  1/2 |x - t|^2   subject to   A x = b,   lower <= x <= upper

(``x = [n, s]``, ``t = [nbar, 0]``, ``A = [B_n, B_s]`` the equilibrium rows,
``n >= 0`` and ``|s| <= mu nbar``; ``upper`` may be infinite and a column
with ``upper <= lower`` is fixed at ``lower``). With the identity Hessian and
bounds only, each Newton system of a primal-dual interior point reduces, as
for the associative LP of ``normal-ipm`` (:mod:`micro.backends.normal_ipm`),
to one system with ``A diag(1 / h) A^T`` of order ``3 n_blocks``, ``h = 1 +
z_l / (x - lower) + z_u / (upper - x)``, factorised by CHOLMOD
(:class:`~micro.backends.normal_matrix.NormalMatrix`; its pattern analysed
once per wall). Mehrotra's predictor-corrector, one step length for the
primal and the dual (the Hessian couples them).

Why: Clarabel factorises the quasi-definite KKT system with a row per
variable and per bound (``5P + 3 n_blocks`` rows, 39,190 on the 1,230-block
wall) where ``M`` has 3,690. Measured on the proximal QPs of Sets 2 and 9
(1,230 and 1,830 blocks, docs/research/2026-11-26-proximal-projection.md): 0.25-0.32 s
against Clarabel's 0.76-1.07 s on Set 2, 0.43-0.62 s against 1.42-1.96 s on
Set 9, with a lower objective than Clarabel's at its 1e-8 tolerances (the
fields within 2e-6 of the largest normal force).

The answer is unique (the objective is strictly convex). A run that does not
reach the tolerances (an infeasible QP, a factorisation that fails with its
shift raised 10^4 times, the iteration limit) says so
(:attr:`LeastDistanceResult.converged`); its caller decides what to do (the
proximal selection then asks Clarabel).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.base import FloatArray
from micro.backends.normal_matrix import (
    InteriorPointSettings,
    InteriorPointStop,
    NormalMatrix,
    NotPositiveDefinite,
    one_blas_thread,
)


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
    """``min 1/2 |x - t|^2`` s.t. ``A x = b``, ``lower <= x <= upper`` (module docstring).

    Args:
        A: ``(rows, columns)`` sparse matrix of full row rank; the pattern
            is analysed once, every :meth:`solve` changes ``t``, ``b`` and the bounds.
        settings: tolerances and limits.
    """

    def __init__(self, A: sp.spmatrix, settings: LeastDistanceSettings = LEAST_DISTANCE) -> None:
        self.settings = settings
        self.M = NormalMatrix(A, regularization=settings.regularization, refine_steps=settings.refine_steps,
                              refine_tol=settings.refine_tol)
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
