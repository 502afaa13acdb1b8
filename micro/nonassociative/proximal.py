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

The QP is solved by an interior point on the normal equations, and by
Clarabel where that does not converge: both are back ends
(:mod:`micro.backends.normal_qp`, which says why the first is the default
and where its measurement is). Both are built once per direction; only the
right-hand side, the target and the bounds change between iterates.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.roles import LeastDistance, LeastDistanceFallback
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]

#: The solvers of the projection (:class:`Projection`'s ``solver``).
PROJECTION_SOLVERS = ("normal-ipm", "clarabel")

#: The proximal selection's margin below the LP's optimum: its QP asks for the
#: field closest to ``nbar`` that carries ``lambda* (1 - PROX_MARGIN)``
#: (:class:`Projection`). Smaller, the feasible set is too thin for the QP's
#: solvers; larger, the sequence settles too far from a collapse state to be
#: certified within its cap: the values tried and what each gave are on
#: the research page on the proximal selection (``docs/research/``).
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
        self.normal_qp: LeastDistance | None = None
        #: projections the normal-equations interior point left to Clarabel
        self.fallbacks = 0
        self.time_limit = time_limit
        self.clarabel: LeastDistanceFallback | None = None  # built on first use

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
            self.normal_qp = LeastDistance(sp.hstack([lp.Bn, lp.Bs], format="csc"))
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
        lp, P = self.lp, self.P
        if self.clarabel is None:
            self.clarabel = LeastDistanceFallback(sp.hstack([lp.Bn, lp.Bs], format="csc"), np.ones(2 * P, bool),
                                                  np.arange(2 * P) >= P, PROX_CLARABEL, self.time_limit)
        cap = lp.mu * nbar
        out = self.clarabel.solve(np.concatenate([nbar, np.zeros(P)]), self._equilibrium_rhs(lam),
                                  np.concatenate([np.zeros(P), -cap]), np.concatenate([np.full(P, np.inf), cap]))
        if out.x is None:
            return ProjectionResult(None, None, float("nan"), out.status, out.iterations, out.seconds)
        return self._result(nbar, out.x, out.status, out.iterations, out.seconds, "clarabel")
