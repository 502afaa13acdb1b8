"""A bounded LP with one free column by an interior point on the normal equations.

The LPs of the iterated LP (:mod:`micro.nonassociative.model`) read, in
columns that carry the friction conditions as bounds::

    minimise  c . x - d lambda   subject to   A x + f lambda = b,   lower <= x <= upper

(``A`` the equilibrium rows of the columns, ``f`` the live load, ``d = +1``
or ``-1``, ``lower`` finite, ``upper`` possibly infinite; a column with
``upper <= lower`` is fixed at ``lower``). Eliminating ``dx`` and the bound
multipliers from each Newton system leaves, as for the associative LP of
``normal-ipm`` (:mod:`micro.backends.normal_ipm`)::

    M dy + f dlambda = h,   f . dy = r_lambda,   M = A diag(1 / H) A^T,

``H = z_l / (x - lower) + z_u / (upper - x)``, ``M`` of order ``3 n_bodies``
(:class:`~micro.backends.normal_matrix.NormalMatrix`, CHOLMOD, its pattern
analysed once per matrix), the free column by the bordered solve
``w = M^{-1} f``. Mehrotra's predictor-corrector with separate primal and
dual step lengths.

The same arithmetic on every CPU: the iterated LP's path through the
vertices the crossover reaches is chaotic (Set 9's diverged at its fifth LP
between two of OpenBLAS's kernels, Prescott and Haswell, with CHOLMOD's
supernodal factorisation and numpy's BLAS dot products), so ``M`` is
factorised by CHOLMOD's simplicial code, which calls no BLAS, and the scalar
products are exact sums (:func:`exact_dot`): the first ten LPs of Set 9 then
agree to the last digit under the Prescott, Haswell and Zen kernels. It costs
1.4-1.9 s per LP on Set 9 against ~1 s supernodal.

Why: the iterated LP needs a VERTEX of each LP (the vertex selection's next
capacities are a basic solution's forces). HiGHS' warm dual simplex takes
10-38 s per LP in the first LPs of Set 9 (1,830 blocks), its interior point
IPX 4-6 s; this interior point gives a primal-dual pair near the optimum in
1.4-1.9 s, from which HiGHS' crossover makes a basis (1-1.5 s) and a few
dual-simplex pivots clean it up
(:meth:`~micro.nonassociative.model.IterationModel.interior_vertex`,
``docs/research/2026-11-26-crossover-route.md``).

A run that does not reach its tolerances says so
(:attr:`BoxLPResult.converged`); the caller then solves the LP another way.
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
class BoxLPSettings(InteriorPointSettings):
    """Tolerances and limits of :class:`BoxLP` (the fields of
    :class:`~micro.backends.normal_matrix.InteriorPointSettings`: the gap
    ``|p - q| / (1 + |p|)``, the primal residual relative to ``1 + max |b|``,
    1e-8 here: near the optimum of Set 9's LPs it stalls at 1-2e-9 while the gap
    keeps falling, and the crossover's clean-up restores equilibrium; the dual
    one relative to ``1 + max |y|``).

    Attributes:
        fix_width: a column whose box is at most this times the widest box
            is held at its middle while the interior point runs, and put at
            the end its reduced cost points to in the answer, as is any
            column that ends within this times the widest box of the bound
            its reduced cost points to (the continuation's ``|h| <= c0`` where
            ``nbar = 0``, 1e-9 of the largest force, made the normal equations
            too ill-conditioned to keep equilibrium; the proximal sequence's
            capacities that decay towards 0 gave the crossover points off
            their bounds with non-zero reduced costs, and thousands of
            clean-up pivots).
    """

    NUMBERS = (*InteriorPointSettings.NUMBERS, "fix_width")

    primal_tol: float = 1e-8
    step_fraction: float = 0.995
    max_iter: int = 120
    fix_width: float = 1e-8


#: The settings of the iterated LP's interior-point route.
BOX_LP = BoxLPSettings()


@dataclass(frozen=True, eq=False)
class BoxLPResult(InteriorPointStop):
    """Where the interior point stopped (the fields of
    :class:`~micro.backends.normal_matrix.InteriorPointStop`, and the answer).

    Attributes:
        x: the columns' values.
        lam: the free column's value (``lambda``, not ``d lambda``).
        y: the equality rows' multipliers (``c - A^T y = z_l - z_u`` at the optimum).
        seconds: wall time.
    """

    x: FloatArray
    lam: float
    y: FloatArray
    seconds: float


class BoxLP:
    """``min c.x - d lambda`` s.t. ``A x + f lambda = b``, ``lower <= x <= upper`` (module docstring).

    Args:
        A: ``(rows, columns)`` sparse matrix of full row rank (its pattern is
            analysed once; :meth:`solve` changes everything else).
        f: the free column, ``(rows,)``.
        settings: tolerances and limits.
    """

    def __init__(self, A: sp.spmatrix, f: FloatArray, settings: BoxLPSettings = BOX_LP) -> None:
        self.settings = settings
        # simplicial: no BLAS call, so the same arithmetic on every CPU (module docstring)
        self.M = NormalMatrix(A, regularization=settings.regularization, supernodal=False,
                              refine_steps=settings.refine_steps, refine_tol=settings.refine_tol)
        self.A, self.AT = self.M.A, self.M.AT
        self.f = np.asarray(f, dtype=float)

    def solve(self, c: FloatArray, b: FloatArray, lower: FloatArray, upper: FloatArray,
              direction: int) -> BoxLPResult:
        """Solve the LP (module docstring) for ``d = direction``."""
        t0 = time.perf_counter()
        with one_blas_thread(), np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            out = self._run(np.asarray(c, float), np.asarray(b, float), np.asarray(lower, float),
                            np.asarray(upper, float), float(direction))
        x, lam, y, reason, iterations, gap, primal, dual = out
        return BoxLPResult(reason=reason, iterations=iterations, gap=gap, primal=primal, dual=dual, x=x, lam=lam,
                           y=y, seconds=time.perf_counter() - t0)

    def _run(self, c: FloatArray, b: FloatArray, lower: FloatArray, upper: FloatArray,
             d: float) -> tuple[FloatArray, float, FloatArray, str, int, float, float, float]:
        st, A, AT, f = self.settings, self.A, self.AT, self.f
        lower0, upper0 = lower, upper
        width = upper - lower
        widest = float(np.max(width[np.isfinite(width)], initial=0.0))
        thin = width <= st.fix_width * widest  # fixed at the middle of the box
        lower = np.where(thin, lower + 0.5 * np.where(np.isfinite(width), width, 0.0), lower)
        upper = np.where(thin, lower, upper)
        free = upper > lower
        up = free & np.isfinite(upper)
        n_bounds = max(int(free.sum() + up.sum()), 1)
        lo = np.where(free, lower, 0.0)
        hi = np.where(up, upper, 0.0)
        b_scale = 1.0 + float(np.max(np.abs(b), initial=0.0))
        # the start: mid-box for bounded columns, one b-scale above the bound for the others
        width = np.where(up, upper - lower, np.inf)
        x = np.where(free, np.where(up, lower + 0.5 * width, lower + b_scale), lower)
        zl = np.where(free, 1.0, 0.0)
        zu = np.where(up, 1.0, 0.0)
        y = np.zeros(A.shape[0])
        lam = 0.0
        gap = primal = dual = math.inf
        for it in range(1, st.max_iter + 1):
            sl = np.where(free, x - lo, 1.0)
            su = np.where(up, hi - x, 1.0)
            reduced = c - AT @ y
            rd = np.where(free, reduced - zl + zu, 0.0)
            rl = -d - exact_dot(f, y)
            rp = b - A @ x - f * lam
            p_obj = exact_dot(c, x) - d * lam
            # a fixed column's reduced cost is free in the dual: it adds its value times that cost
            q_obj = (exact_dot(b, y) + exact_dot(lo[free], zl[free]) - exact_dot(hi[up], zu[up])
                     + exact_dot(reduced[~free], lower[~free]))
            products = exact_dot(sl[free], zl[free]) + exact_dot(su[up], zu[up])
            gap = abs(p_obj - q_obj) / (1.0 + abs(p_obj))
            primal = float(np.max(np.abs(rp), initial=0.0)) / b_scale
            dual = max(float(np.max(np.abs(rd), initial=0.0)), abs(rl)) / (1.0 + float(np.max(np.abs(y), initial=0.0)))
            if not (math.isfinite(gap) and math.isfinite(primal) and math.isfinite(dual)):
                return x, lam, y, "not finite", it, gap, primal, dual
            if gap <= st.gap_tol and primal <= st.primal_tol and dual <= st.dual_tol:
                return _snapped(x, reduced, lower0, upper0, thin, st.fix_width * widest), lam, y, \
                    "converged", it - 1, gap, primal, dual
            mu = products / n_bounds
            H = np.where(free, zl / sl + np.where(up, zu / su, 0.0), 1.0)
            dinv = np.where(free, 1.0 / H, 0.0)
            try:
                self.M.factor_raising(dinv)
            except NotPositiveDefinite:
                return x, lam, y, "not positive definite", it, gap, primal, dual
            w = self.M.solve(f)
            fw = exact_dot(f, w)
            frame = _Frame(free, up, sl, su, zl, zu, rd, rl, rp, dinv, w, fw)
            # Mehrotra: the affine direction, then the centred and corrected one
            dx, dl, dy, dzl, dzu = self._direction(frame, np.where(free, -sl * zl, 0.0),
                                                   np.where(up, -su * zu, 0.0))
            ap, ad = frame.longest(dx, dzl, dzu)
            mu_aff = (exact_dot((sl + ap * dx)[free], (zl + ad * dzl)[free])
                      + exact_dot((su - ap * dx)[up], (zu + ad * dzu)[up])) / n_bounds
            sigma = min((mu_aff / mu) ** 3, 1.0) if mu > 0 else 0.0
            rcl = np.where(free, sigma * mu - sl * zl - dx * dzl, 0.0)
            rcu = np.where(up, sigma * mu - su * zu + dx * dzu, 0.0)
            dx, dl, dy, dzl, dzu = self._direction(frame, rcl, rcu)
            ap, ad = frame.longest(dx, dzl, dzu)
            ap, ad = min(1.0, st.step_fraction * ap), min(1.0, st.step_fraction * ad)
            x, lam = x + ap * dx, lam + ap * dl
            y, zl, zu = y + ad * dy, zl + ad * dzl, zu + ad * dzu
        return x, lam, y, "iteration limit", st.max_iter, gap, primal, dual

    def _direction(self, fr: _Frame, rcl: FloatArray,
                   rcu: FloatArray) -> tuple[FloatArray, float, FloatArray, FloatArray, FloatArray]:
        """The Newton direction ``(dx, dlambda, dy, dz_l, dz_u)`` for the complementarity
        right-hand sides ``rcl``, ``rcu``: with ``dz_l``, ``dz_u`` eliminated,
        ``dx = H^{-1} (A^T dy - r1)`` and ``A dx + f dlambda = r_p`` give
        ``M dy + f dlambda = r_p + A H^{-1} r1``; ``f . dy = r_lambda`` closes it."""
        r1 = np.where(fr.free, fr.rd - rcl / fr.sl + np.where(fr.up, rcu / fr.su, 0.0), 0.0)
        u = self.M.solve(fr.rp + self.A @ (fr.dinv * r1))
        dl = (exact_dot(self.f, u) - fr.rl) / fr.fw
        dy = u - dl * fr.w
        dx = fr.dinv * (self.AT @ dy - r1)
        dzl = np.where(fr.free, (rcl - fr.zl * dx) / fr.sl, 0.0)
        dzu = np.where(fr.up, (rcu + fr.zu * dx) / fr.su, 0.0)
        return dx, dl, dy, dzl, dzu


def _snapped(x: FloatArray, reduced: FloatArray, lower: FloatArray, upper: FloatArray, thin: NDArray[np.bool_],
             near: float) -> FloatArray:
    """``x`` with each column whose reduced cost points to one of its bounds put on that
    bound where it lies within ``near`` of it, and every thin column (``thin``) put on
    the bound its reduced cost points to: where a basis would put them, a move of at
    most ``near`` (a crossover from columns left just inside their boxes with non-zero
    reduced costs ended in dual-simplex clean-ups of thousands of pivots)."""
    to_lower = (reduced > 0.0) & (thin | (x - lower <= near))
    to_upper = (reduced < 0.0) & np.isfinite(upper) & (thin | (upper - x <= near))
    return np.where(to_lower, lower, np.where(to_upper, upper, x))


def exact_dot(a: FloatArray, b: FloatArray) -> float:
    """``a . b`` summed exactly (``math.fsum``): numpy's ``@`` calls its BLAS,
    whose kernels (and so the last bits) differ from CPU to CPU. Every scalar
    product of the crossover route goes through it."""
    return math.fsum((a * b).tolist())


@dataclass(frozen=True, eq=False)
class _Frame:
    """One iterate's slacks, multipliers, residuals, ``H^{-1}`` and the bordered
    solve ``w = M^{-1} f`` (masks: the free columns and those with a finite upper bound)."""

    free: NDArray[np.bool_]
    up: NDArray[np.bool_]
    sl: FloatArray
    su: FloatArray
    zl: FloatArray
    zu: FloatArray
    rd: FloatArray
    rl: float
    rp: FloatArray
    dinv: FloatArray
    w: FloatArray
    fw: float

    def longest(self, dx: FloatArray, dzl: FloatArray, dzu: FloatArray) -> tuple[float, float]:
        """The largest primal and dual steps ``<= 1`` that keep the slacks and multipliers non-negative."""
        steps = []
        for pairs in (((self.sl, dx, self.free), (self.su, -dx, self.up)),
                      ((self.zl, dzl, self.free), (self.zu, dzu, self.up))):
            a = 1.0
            for v, dv, mask in pairs:
                neg = mask & (dv < 0.0)
                if np.any(neg):
                    a = min(a, float(np.min(-v[neg] / dv[neg])))
            steps.append(a)
        return steps[0], steps[1]
