"""Exhaustive search over contact-state patterns: the reference for the global MIP.

Written against :mod:`micro.lp` and ``highspy`` only (none of the
``micro.global_*`` code), so that it checks the MIP independently.

Every interface takes one of ten states: each of its two points closed or
open, times the slip sense (stick, ``+``, ``-``); with both points open the
forces vanish whatever the slip, so one state "separated, free slip" stands
for three. For a complete assignment the collapse conditions are two LPs:

* forces: least ``lambda`` with ``n = 0`` at open points and ``s = -mu n``
  (slip ``+``) or ``s = +mu n`` (slip ``-``) at the points of a slipping
  interface, Coulomb elsewhere;
* mechanism: largest live-load work over the velocities with zero opening
  rate at closed points, opening ``>= 0`` at open points, slip rates of the
  allowed sense, every rate in ``[-1, 1]``; a mechanism exists when it is
  positive (the definition: the live load does positive work).

The minimum over all assignments is found by depth-first search with two
exact prunings. A partial assignment (the other interfaces unrestricted in
their forces and free in their motion) has a force LP whose least ``lambda``
is at most that of any completion, and a mechanism LP whose largest work is
at least that of any completion: when the first is infeasible or not below
the best found, or the second has no mechanism, no completion can improve.
"""

from __future__ import annotations

import math

import highspy
import numpy as np
import scipy.sparse as sp

from micro.lp import LimitLP

#: Interface states: (point 0 open, point 1 open, slip) with slip 0, +1, -1,
#: and 2 = free (both points open).
STATES = [(o0, o1, sl) for o0, o1 in ((0, 0), (1, 0), (0, 1)) for sl in (0, 1, -1)] + [(1, 1, 2)]
#: A mechanism exists when its largest live work (rates in [-1, 1]) exceeds this.
WORK_TOL = 1e-9


def _model(cost: np.ndarray, A: sp.spmatrix, rows: tuple, cols: tuple) -> highspy.Highs:
    """A persistent silent HiGHS LP (bounds are changed between solves)."""
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("primal_feasibility_tolerance", 1e-10)
    h.setOptionValue("dual_feasibility_tolerance", 1e-10)
    inf = h.getInfinity()
    A = sp.csc_matrix(A)
    h.addVars(A.shape[1], np.clip(cols[0], -inf, inf), np.clip(cols[1], -inf, inf))
    h.changeColsCost(A.shape[1], np.arange(A.shape[1], dtype=np.int32), cost)
    R = A.tocsr()
    h.addRows(R.shape[0], np.clip(rows[0], -inf, inf), np.clip(rows[1], -inf, inf), R.nnz,
              R.indptr.astype(np.int32), R.indices.astype(np.int32), R.data)
    return h


class Enumerator:
    """Least non-associative collapse load factor of a small wall by exhaustive search."""

    def __init__(self, lp: LimitLP, direction: int) -> None:
        self.lp = lp
        self.d = direction
        P = lp.n_points
        self.C = P // 2
        A = lp.A.tocsc(copy=True)
        A[:, lp.lam_col] = A[:, lp.lam_col] * float(direction)
        cost = np.zeros(lp.n_cols)
        cost[lp.lam_col] = 1.0
        self.fm = _model(cost, A, (lp.rhs, lp.rhs), (lp.col_lower, lp.col_upper))
        M = sp.vstack([lp.Bn.T, lp.Bs.T.tocsr()[0::2]])
        nv = lp.n_eq
        self.mm = _model(-direction * lp.live, M, (np.zeros(P + self.C), np.zeros(P + self.C)),
                         (np.full(nv, -np.inf), np.full(nv, np.inf)))
        self.lps = 0

    def forces(self, states: list[tuple[int, int, int] | None], sense: float = 1.0) -> float:
        """Least (``sense=1``) or greatest (``-1``) lambda of the assignment's
        force fields (``None``: unrestricted interface); NaN if none."""
        lp, P = self.lp, self.lp.n_points
        up = lp.col_upper[: 2 * P].copy()
        for c, st in enumerate(states):
            if st is None:
                continue
            o0, o1, sl = st
            for k, o in enumerate((o0, o1)):
                p = 2 * c + k
                if o:
                    up[p] = up[P + p] = 0.0
                elif lp.mu[p] > 0 and sl == 1:
                    up[p] = 0.0  # g+ = 0: s = -mu n
                elif lp.mu[p] > 0 and sl == -1:
                    up[P + p] = 0.0  # g- = 0: s = +mu n
        h = self.fm
        h.changeColsBounds(2 * P, np.arange(2 * P, dtype=np.int32), lp.col_lower[: 2 * P],
                           np.minimum(up, h.getInfinity()))
        h.changeColCost(lp.lam_col, sense)
        self.lps += 1
        h.run()
        if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
            return math.nan
        return float(h.getSolution().col_value[lp.lam_col])

    def has_mechanism(self, states: list[tuple[int, int, int] | None]) -> bool:
        """True when the assignment (``None``: free interface) admits a mechanism."""
        P, C = self.lp.n_points, self.C
        lo, up = np.zeros(P + C), np.zeros(P + C)
        for c, st in enumerate(states):
            o0, o1, sl = (1, 1, 2) if st is None else st
            up[2 * c], up[2 * c + 1] = o0, o1
            lo[P + c] = -1.0 if sl in (-1, 2) else 0.0
            up[P + c] = 1.0 if sl in (1, 2) else 0.0
        h = self.mm
        h.changeRowsBounds(P + C, np.arange(P + C, dtype=np.int32), lo, up)
        self.lps += 1
        h.run()
        if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
            return False
        return -float(h.getInfo().objective_function_value) > WORK_TOL

    def minimum(self, cutoff: float = math.inf) -> tuple[float, list[tuple[int, int, int]] | None]:
        """``(least lambda, its assignment)`` over the assignments with
        ``lambda <= cutoff``; ``(inf, None)`` when there is none."""
        best: list = [cutoff, None]
        states: list = [None] * self.C
        lam = self.forces(states)
        if lam <= cutoff and self.has_mechanism(states):  # (NaN compares False)
            self._dfs(states, 0, lam, best)
        return (float(best[0]), best[1]) if best[1] is not None else (math.inf, None)

    def _dfs(self, states: list, c: int, lam: float, best: list) -> None:
        """Assignment ``states[:c]`` fixed, least lambda ``lam``, with a mechanism."""
        if c == self.C:
            best[0], best[1] = lam, list(states)
            return
        for st in STATES:
            states[c] = st
            # "stick" restricts no force (same lambda); "separated, free slip"
            # restricts no motion (the parent's mechanism still exists)
            child = lam if st == (0, 0, 0) else self.forces(states)
            if math.isnan(child) or child > best[0]:
                continue
            if st != (1, 1, 2) and not self.has_mechanism(states):
                continue
            self._dfs(states, c + 1, child, best)
        states[c] = None
