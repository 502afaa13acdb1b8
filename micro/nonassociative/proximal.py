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

The QP is solved by the suite's interior point on the normal equations
(:mod:`micro.backends.normal_qp`, ``Tuning.projection_solver="normal-ipm"``,
3-4 times faster than Clarabel on Sets 2 and 9), and by Clarabel where that
does not converge or with ``projection_solver="clarabel"`` (the path before
2026-11-26). Both are built once per direction; only the right-hand side,
the target and the bounds change between iterates (Clarabel's ``update``
needs its presolve off).

With ``Tuning.anderson = m > 0`` the relaxed step is replaced by Anderson
acceleration of depth ``m`` (:class:`Anderson`) of the same fixed-point
iteration, residual ``f(nbar) = P(nbar) - nbar``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import clarabel
import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.clarabel import clarabel_settings, solve_interruptibly
from micro.backends.normal_qp import LeastDistanceQP
from micro.lp import LimitLP
from micro.nonassociative.tuning import ANDERSON_GROWTH, ANDERSON_RCOND, PROX_CLARABEL, PROX_MARGIN

FloatArray = NDArray[np.float64]

#: The solvers of the projection (``Tuning.projection_solver``).
PROJECTION_SOLVERS = ("normal-ipm", "clarabel")
#: Clarabel statuses whose solution is taken as the projection.
_SOLVED = ("Solved", "AlmostSolved")


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


class Anderson:
    """Anderson acceleration (type II, Walker & Ni 2011) of the relaxed
    fixed-point iteration ``x <- x + beta f(x)``, ``f(x) = g(x) - x``.

    With the last ``depth + 1`` iterates ``x_i`` and residuals ``f_i`` kept,
    ``dX`` and ``dF`` their consecutive differences:

        gamma   = argmin |f_k - dF gamma|_2
        x_(k+1) = max(x_k + beta f_k - (dX + beta dF) gamma, 0).

    The safeguard: where ``|f_k|_2`` exceeds :data:`ANDERSON_GROWTH` times
    ``|f_(k-1)|_2`` the history is dropped (a restart) and the step is the
    plain relaxed one; so is the first step, and a step whose least-squares
    problem is not finite.

    Args:
        depth: ``m >= 1``, the differences kept.
        beta: the relaxation.
    """

    def __init__(self, depth: int, beta: float) -> None:
        self.depth, self.beta = depth, beta
        self.xs: list[FloatArray] = []
        self.fs: list[FloatArray] = []
        self.restarts = 0
        self.accelerated = 0

    def reset(self) -> None:
        """Drop the history (the next step is a plain one)."""
        self.xs.clear()
        self.fs.clear()

    def step(self, x: FloatArray, g: FloatArray) -> FloatArray:
        """The next iterate from ``x`` and its map's value ``g = g(x)``."""
        f = g - x
        if self.fs and float(np.linalg.norm(f)) > ANDERSON_GROWTH * float(np.linalg.norm(self.fs[-1])):
            self.reset()
            self.restarts += 1
        self.xs.append(np.array(x, dtype=float))
        self.fs.append(f)
        if len(self.fs) > self.depth + 1:
            self.xs.pop(0)
            self.fs.pop(0)
        plain = np.maximum(x + self.beta * f, 0.0)
        if len(self.fs) < 2:
            return plain
        dF = np.column_stack([b - a for a, b in zip(self.fs[:-1], self.fs[1:], strict=True)])
        dX = np.column_stack([b - a for a, b in zip(self.xs[:-1], self.xs[1:], strict=True)])
        gamma = np.linalg.lstsq(dF, f, rcond=ANDERSON_RCOND)[0]
        nxt = x + self.beta * f - (dX + self.beta * dF) @ gamma
        if not np.all(np.isfinite(nxt)):
            self.reset()
            self.restarts += 1
            return plain
        self.accelerated += 1
        return np.maximum(nxt, 0.0)
