"""The proximal selection: the next ``nbar`` is ``nbar`` projected onto the fields its LP allows.

Gilbert's LP at ``nbar`` (``|s| <= mu nbar``, maximise ``lambda``) has a face
of optimal force fields; the vertex selection takes the simplex's vertex of
it, whose forces jump in the parts of the wall that do not move, and the
iteration ``nbar <- n`` is a discontinuous map that cycles on large walls
(Sets 2 and 9). Here the LP gives ``lambda*`` and the mechanism as before,
and the next ``nbar`` moves towards the field closest to ``nbar`` among those
that carry ``lambda* (1 - PROX_MARGIN)`` with the same capacities:

    min  1/2 |n - nbar|^2 + 1/2 |s|^2
    s.t. B_n n + B_s s = -f_D - d lambda* (1 - PROX_MARGIN) f_L,
         n >= 0,  |s| <= mu nbar,

then ``nbar <- nbar + beta (n - nbar)``. The objective is strictly convex,
so the field is unique and moves continuously with ``nbar`` (the ``|s|^2``
term only makes the shear forces unique). At a fixed point ``nbar`` itself
carries ``lambda*(nbar) (1 - PROX_MARGIN)`` with ``|s| <= mu nbar``: a force
field that satisfies Coulomb with its own normal forces within a margin of
the LP's optimum, which is what a non-associative collapse state is at
``PROX_MARGIN = 0`` (any optimal field and any optimal mechanism of one LP
are complementary). The iterate is converged only when the certificate
finds an exact state with the LP's mechanism, as for the other selections.

The QP is solved by an interior point on the normal equations
(:class:`LeastDistanceQP`), and by Clarabel where that does not converge.
With the identity Hessian and bounds only, each Newton system reduces, as
for the associative LP of ``normal-ipm`` (:mod:`micro.backends.normal_ipm`),
to one system with ``A diag(1 / h) A^T`` of order ``3 n_blocks``, ``h = 1 +
z_l / (x - lower) + z_u / (upper - x)``, factorised by CHOLMOD
(:class:`~micro.backends.normal_matrix.NormalMatrix`) where Clarabel
factorises a KKT system with a row per variable and per bound (``5P + 3
n_blocks`` rows): 2.7-3.9 times faster per QP on Sets 2 and 9
(``docs/micro/nonassociative.md``). CHOLMOD's simplicial factorisation, not
its supernodal one: the supernodal kernels are BLAS calls, whose last bits
differ between OpenBLAS's kernels, and the projection decides the next
``nbar``; with them Set 9's sequence reached another state on another
machine (``docs/research/2026-11-28-blas-independent-descent.md``). Mehrotra's
predictor-corrector, one step length for the primal and the dual (the
Hessian couples them). Both solvers are built once per direction; only the
right-hand side, the target and the bounds change between iterates
(Clarabel's ``update`` needs its presolve off).
"""

from __future__ import annotations

import dataclasses
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
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]

#: The solvers of the projection (:class:`Projection`'s ``solver``).
PROJECTION_SOLVERS = ("normal-ipm", "clarabel")
#: Clarabel statuses whose solution is taken as the projection.
_SOLVED = ("Solved", "AlmostSolved")

#: The proximal selection's margin below the LP's optimum: its QP asks for the
#: field closest to ``nbar`` that carries ``lambda* (1 - PROX_MARGIN)``
#: (:class:`Projection`). At 1e-5 Clarabel stopped at its
#: iteration cap ("AlmostSolved", 200 iterations) on most QPs of Sets 2 and 9
#: (the feasible set is too thin); at 1e-3 Set 9's sequence had not been
#: certified after 40 LPs; at 1e-4 it was after 38 (and Set 2 after 21).
PROX_MARGIN = 1e-4
#: Clarabel settings of the proximal QP: a projection needs no more than
#: 1e-8 (it only chooses the next ``nbar``; the certificate decides
#: convergence); QDLDL named as for the LPs (``CLARABEL_TIGHT``).
PROX_CLARABEL: dict[str, Any] = {
    "direct_solve_method": "qdldl",
    "tol_gap_abs": 1e-8,
    "tol_gap_rel": 1e-8,
    "tol_feas": 1e-8,
    "max_iter": 400,
}


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


@dataclass(frozen=True)
class ProjectionResult:
    """One proximal projection.

    Attributes:
        normal: the projected normal forces ``n`` (scaled), or ``None`` when
            the QP was not solved.
        shear: its shear forces ``s`` (scaled), or ``None``.
        step: ``|n - nbar|_1 / |nbar|_1`` (NaN when not solved).
        status: the solver's status (``"converged"`` and the normal-equations
            interior point's other reasons, or Clarabel's).
        iterations: interior-point iterations (of both solvers when Clarabel took over).
        seconds: wall time.
        solver: ``"normal-ipm"`` or ``"clarabel"``: which one gave the answer (or failed last).
    """

    normal: FloatArray | None
    shear: FloatArray | None
    step: float
    status: str
    iterations: int
    seconds: float
    solver: str = "clarabel"


class Projection:
    """The proximal QP of one load direction (module docstring), built once.

    Args:
        lp: the wall's LP.
        direction: ``+1`` or ``-1``.
        time_limit: the user's limit in seconds per solve (``inf``: none; the
            normal-equations interior point has no clock: its iteration cap bounds it).
        solver: ``"normal-ipm"`` (Clarabel where it does not converge) or ``"clarabel"``.
    """

    def __init__(self, lp: LimitLP, direction: int, time_limit: float = math.inf,
                 solver: str = "normal-ipm") -> None:
        if solver not in PROJECTION_SOLVERS:
            raise ValueError(f"solver must be one of {', '.join(PROJECTION_SOLVERS)}, got {solver!r}")
        P = lp.n_points
        self.lp, self.d, self.P, self.solver_name = lp, direction, P, solver
        self.normal_qp: LeastDistanceQP | None = None
        #: projections the normal-equations interior point left to Clarabel
        self.fallbacks = 0
        self.time_limit = time_limit
        self.solver: clarabel.DefaultSolver | None = None  # built on first use

    def _equilibrium_rhs(self, lam: float) -> FloatArray:
        """The equilibrium rows' right-hand side at ``lam (1 - PROX_MARGIN)``."""
        return self.lp.rhs - (self.d * lam * (1.0 - PROX_MARGIN)) * self.lp.live

    def project(self, nbar: FloatArray, lam: float) -> ProjectionResult:
        """The field closest to ``nbar`` that carries ``lam (1 - PROX_MARGIN)``
        with the capacities ``mu nbar`` (``lam``: the LP's optimum at ``nbar``)."""
        if self.solver_name == "clarabel":
            return self._clarabel(nbar, lam)
        lp, P = self.lp, self.P
        if self.normal_qp is None:
            self.normal_qp = LeastDistanceQP(sp.hstack([lp.Bn, lp.Bs], format="csc"))
        cap = lp.mu * nbar
        out = self.normal_qp.solve(np.concatenate([nbar, np.zeros(P)]), self._equilibrium_rhs(lam),
                                   np.concatenate([np.zeros(P), -cap]), np.concatenate([np.full(P, np.inf), cap]))
        if out.converged:
            return self._result(nbar, out.x, out.reason, out.iterations, out.seconds, "normal-ipm")
        self.fallbacks += 1
        other = self._clarabel(nbar, lam)
        return dataclasses.replace(other, iterations=other.iterations + out.iterations,
                                   seconds=other.seconds + out.seconds)

    def _result(self, nbar: FloatArray, x: FloatArray, status: str, iterations: int, seconds: float,
                solver: str) -> ProjectionResult:
        n = np.maximum(x[: self.P], 0.0)
        step = float(np.abs(n - nbar).sum()) / max(float(np.abs(nbar).sum()), 1e-300)
        return ProjectionResult(n, x[self.P :], step, status, iterations, seconds, solver)

    def _clarabel(self, nbar: FloatArray, lam: float) -> ProjectionResult:
        """:meth:`project` by Clarabel."""
        t0 = time.perf_counter()
        lp, P = self.lp, self.P
        cap = lp.mu * nbar
        b = np.concatenate([self._equilibrium_rhs(lam), np.zeros(P), cap, cap])
        q = np.concatenate([-nbar, np.zeros(P)])
        if self.solver is None:
            eye = sp.identity(P, format="csc")
            zero = sp.csc_matrix((P, P))
            # rows: equilibrium (zero cone), then -n <= 0, s <= mu nbar, -s <= mu nbar
            A = sp.vstack([sp.hstack([lp.Bn, lp.Bs]), sp.hstack([-eye, zero]), sp.hstack([zero, eye]),
                           sp.hstack([zero, -eye])], format="csc")
            cones = [clarabel.ZeroConeT(lp.n_eq), clarabel.NonnegativeConeT(3 * P)]
            settings = clarabel_settings(PROX_CLARABEL)
            settings.presolve_enable = False  # update() needs it off
            if math.isfinite(self.time_limit):
                settings.time_limit = float(self.time_limit)
            self.solver = clarabel.DefaultSolver(sp.identity(2 * P, format="csc"), q, A, b, cones, settings)
        else:
            self.solver.update(q=q, b=b)
        sol = solve_interruptibly(self.solver)
        status = str(sol.status)
        seconds = time.perf_counter() - t0
        if status not in _SOLVED:
            return ProjectionResult(None, None, float("nan"), status, int(sol.iterations), seconds)
        return self._result(nbar, np.asarray(sol.x), status, int(sol.iterations), seconds, "clarabel")

