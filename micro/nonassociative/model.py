"""The iteration model: the rebuilt yield conditions as changes of one persistent HiGHS model.

Columns ``[n (P), s (P), lambda]`` over the equilibrium rows (plus, for
scheme (b), ``2P`` friction rows). Every iterate changes bounds (scheme (a)),
or row bounds and coefficients (scheme (b)), only, so the dual simplex
restarts from the previous basis.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.base import Outcome, Status
from micro.backends.roles import BASIC, LOWER, PersistentLP
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]


class IterationModel:
    """The persistent model of one load direction.

    Args:
        lp: the wall's LP (its equilibrium rows and loads).
        direction: ``+1`` or ``-1``; the ``lambda`` column holds ``d * lambda``.
        scheme: ``"a"`` (``|s| <= mu nbar`` as bounds of ``s``) or ``"b"``
            (the two friction rows ``+-s + alpha mu n <= c0 + (1 + alpha) mu nbar``).
        alpha0: the first slope of scheme (b).
    """

    def __init__(self, lp: LimitLP, direction: int, scheme: str, alpha0: float) -> None:
        P = lp.n_points
        self.lp, self.d, self.scheme, self.P = lp, direction, scheme, P
        self.nbar = np.zeros(P)
        live = sp.csc_matrix(lp.live.reshape(-1, 1))
        self.n_cols = np.arange(P)
        self.s_cols = np.arange(P, 2 * P)
        self.lam_col = 2 * P
        A = sp.hstack([lp.Bn, lp.Bs, live], format="csc")
        cost = np.zeros(2 * P + 1)
        cost[self.lam_col] = -float(direction)
        lower = np.concatenate([np.zeros(2 * P), [-np.inf]])
        upper = np.concatenate([np.full(P, np.inf), np.zeros(P), [np.inf]])
        self.model = PersistentLP(A, cost, lower, upper, lp.rhs.copy(), lp.rhs.copy(), algorithm="ipm")
        self.model.guard_stalls()  # a stalled warm run fails (and is recovered) instead of hanging
        self.in_fallback = False
        self.good_basis: Any = None
        self.alpha, self.c0 = alpha0, 0.0
        if scheme == "b":
            # rows n_eq + 2p (+s) and n_eq + 2p + 1 (-s): +-s + alpha mu n <= rhs
            self.model.add_rows(self._friction_rows(alpha0 * lp.mu), np.full(2 * P, -np.inf),
                                np.full(2 * P, np.inf))
            self.f_rows = lp.n_eq + np.arange(2 * P)
            self.model.set_col_bounds(self.s_cols, np.full(P, -np.inf), np.full(P, np.inf))

    def _friction_rows(self, n_coef: FloatArray) -> sp.csr_matrix:
        """``2P`` rows over the model's columns: row ``2p`` is
        ``+s_p + n_coef_p n_p``, row ``2p + 1`` is ``-s_p + n_coef_p n_p``."""
        P = self.P
        rows = np.repeat(np.arange(2 * P), 2)
        cols = np.empty(4 * P, dtype=np.int64)
        vals = np.empty(4 * P)
        cols[0::4], cols[1::4], cols[2::4], cols[3::4] = self.s_cols, self.n_cols, self.s_cols, self.n_cols
        vals[0::4], vals[1::4], vals[2::4], vals[3::4] = 1.0, n_coef, -1.0, n_coef
        return sp.csr_matrix((vals, (rows, cols)), shape=(2 * P, 2 * P + 1))

    # ------------------------------------------------------------ reading
    def forces(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(n, s)`` of a solution."""
        return x[: self.P], x[self.P : 2 * self.P]

    def load_factor(self, x: FloatArray) -> float:
        """``lambda`` of a solution (the column holds ``d * lambda``)."""
        return float(x[self.lam_col]) * self.d

    # ------------------------------------------------------------ updates
    def set_capacity(self, nbar: FloatArray, alpha: float, alpha_prev: float, c0: float) -> None:
        """Rebuild the yield condition of every point from ``nbar`` (bounds;
        for scheme (b) row
        bounds and, when ``alpha`` changed, coefficients: a small part of one
        warm simplex run, docs/speed.md)."""
        P, mu, m = self.P, self.lp.mu, self.model
        nbar = np.maximum(nbar, 0.0)
        self.nbar = nbar
        self.alpha, self.c0 = alpha, c0
        if self.scheme == "a":
            m.set_col_bounds(self.s_cols, -mu * nbar, mu * nbar)
            return
        if self.in_fallback:
            m.set_col_bounds(self.s_cols, np.full(P, -np.inf), np.full(P, np.inf))
            self.in_fallback = False
        if alpha != alpha_prev:
            m.change_coeffs(self.f_rows, np.repeat(self.n_cols, 2), np.repeat(alpha * mu, 2))
        rhs = c0 + (1.0 + alpha) * mu * nbar
        m.set_row_bounds(self.f_rows, np.full(2 * P, -np.inf), np.repeat(rhs, 2))

    def fallback_a_step(self, nbar: FloatArray, seconds: float | None, simplex_iterations: int) -> Outcome:
        """One LP of scheme (a) inside the scheme (b) model from the last good
        basis: friction rows switched off (infinite bounds), ``|s| <= mu nbar``
        as ``s`` bounds; restored by the next :meth:`set_capacity`. Bound
        changes only. The run is a :meth:`warm` run with its limits, or it
        could take as long as a cold dual simplex (minutes on 1,230 blocks)."""
        P, mu, m = self.P, self.lp.mu, self.model
        if self.good_basis is not None:
            m.set_basis(self.good_basis)  # the failed run's basis may be garbage
        nbar = np.maximum(nbar, 0.0)
        m.set_row_bounds(self.f_rows, np.full(2 * P, -np.inf), np.full(2 * P, np.inf))
        m.set_col_bounds(self.s_cols, -mu * nbar, mu * nbar)
        out = self.warm(seconds, simplex_iterations)
        self.in_fallback = True  # the model now holds a scheme (a) LP (for the cold check)
        return out

    def generator_basis(self) -> tuple[NDArray[np.int8], NDArray[np.int8]] | None:
        """The current basis carried over to the generator LP of the same wall
        (columns ``[g+, g-, lambda]``, ``n = g+ + g-``, ``s = mu (g+ - g-)``,
        :mod:`micro.lp`): the start of a descent LP
        (:class:`~micro.nonassociative.descent.states.ForceLP`) without a cold solve.

        Each point keeps its number of basic columns: ``n`` and ``s`` basic
        (a sticking point) make both generators basic; one of them basic
        makes the generator on the side of ``s`` basic (``g-`` where ``s``
        sits at its lower bound ``-mu nbar`` with ``n`` basic, else ``g+``);
        the ``lambda`` column and the rows keep their status. The vertex of
        the mapped basis is near the iterate's field, so a primal simplex
        from it is short (HiGHS repairs a singular basis).

        Returns:
            ``(column, row)`` status codes, or ``None`` for a model whose
            rows are not those of scheme (a)'s plain LP (scheme (b)'s
            friction rows).
        """
        if self.scheme != "a":
            return None
        cols, rows = self.model.basis_arrays()
        P, friction = self.P, self.lp.mu > 0.0
        n_basic, s_basic = cols[:P] == BASIC, cols[P : 2 * P] == BASIC
        both, one = n_basic & s_basic, n_basic ^ s_basic
        minus = one & n_basic & (cols[P : 2 * P] == LOWER) & friction
        gen = np.full(2 * P + 1, LOWER, dtype=np.int8)
        gen[:P][both | (one & ~minus)] = BASIC
        gen[P : 2 * P][both | minus] = BASIC
        gen[2 * P] = cols[2 * P]
        return gen, rows

    def keep_basis(self) -> None:
        """Remember the basis of a good scheme (b) iterate (for :meth:`fallback_a_step`)."""
        if self.scheme == "b":
            self.good_basis = self.model.get_basis()

    # --------------------------------------------------------------- runs
    def warm(self, seconds: float | None, simplex_iterations: int) -> Outcome:
        """Dual simplex from the current basis, limited to ``simplex_iterations``
        (and to the user's ``seconds``, ``None``: none); the later runs keep
        only the user's limit (re-armed from the run time so far)."""
        self.model.limit_next_run(seconds, simplex_iterations=simplex_iterations)
        out = self.model.run()
        self.model.limit_next_run(seconds)
        return out


def restart(model: PersistentLP) -> Outcome:
    """Solve ``model`` from scratch: interior point + crossover (a basis in
    seconds where a cold dual simplex takes minutes on a 1,230-block wall),
    then a dual-simplex clean-up from the crossover basis (crossover alone
    left residuals ~1e-4). The model is left on the dual simplex.

    Returns:
        The clean-up's outcome with the cost of both runs.
    """
    model.clear_solver()
    model.set_algorithm("ipm", crossover=True)
    first = model.run()
    model.set_algorithm("simplex")
    if first.status is not Status.OPTIMAL and first.status is not Status.INFEASIBLE:
        model.clear_solver()
    out = model.run()
    return dataclasses.replace(
        out, seconds=out.seconds + first.seconds, ipm_iterations=first.ipm_iterations,
        simplex_iterations=out.simplex_iterations + first.simplex_iterations + first.crossover_iterations,
    )
