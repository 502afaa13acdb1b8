"""Big-M bounds of the global search, each one provable (no heuristic bound).

Every collapse state of the non-associative problem (see
``docs/micro/global-search.md``) is in particular statically admissible for the
ASSOCIATIVE problem: equilibrium, ``n >= 0``, ``|s| <= mu n``. Hence

* its load factor lies in the associative interval
  ``[lambda_min, lambda_max]`` of the load direction (two LPs: min and max
  ``lambda`` over the statically admissible fields), and below any known
  collapse state's load factor when we only look for better ones;
* its load factor is ``>= 0`` when no admissible mechanism lowers the dead
  load (``lift = -f_D . v >= 0`` whenever ``B_n^T v >= 0``; one LP proves it
  for the wall): by virtual work ``lambda * (live work) = dissipation + lift``
  with a positive live work and a non-negative dissipation;
* its normal force at point ``p`` is at most ``N_p``, the largest ``n_p``
  over ALL statically admissible fields with ``lambda`` in that interval (an
  LP per point, policy ``"per_point"``), or at most the largest TOTAL normal
  force ``sum_p n_p`` over them (one LP, policy ``"uniform"``, looser).

The LP optima carry the solver's tolerance (:data:`~micro.global_search.highs.LP_TOLERANCE`);
each ``N_p`` is widened by :data:`BOUND_MARGIN` so that rounding cannot cut a
state off. The rate bounds of the mechanism need no LP: the mechanism is
normalised so that its rates (opening rates, absolute slip rates) sum to 1,
so each is at most 1.
"""

from __future__ import annotations

import math
import time
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from micro.global_search import highs as gh
from micro.global_search.global_types import BigM
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]

#: Relative widening of every LP bound on a normal force (plus the same
#: fraction of the largest one, absolute): far above the LPs' tolerance.
BOUND_MARGIN = 1e-6
#: The lowest dead-load work an admissible mechanism may do (rates in
#: ``[-1, 1]``) and still count as "never lowers the dead load" (LP noise).
LIFT_TOLERANCE = 1e-9


class BoundError(RuntimeError):
    """A bound could not be established (an LP failed or is unbounded)."""


def _static_model(lp: LimitLP, direction: int) -> gh.Model:
    """The associative static LP in generator form with the column ``lambda``
    (``B_n n + B_s s + d lambda f_L = -f_D``), zero cost."""
    A = lp.A.tocsc(copy=True)
    A[:, lp.lam_col] = A[:, lp.lam_col] * float(direction)
    h = gh.build(np.zeros(lp.n_cols), A, (lp.rhs, lp.rhs), (lp.col_lower, lp.col_upper))
    return gh.tight_lp(h)


def _optimum(h: gh.Model, what: str) -> float:
    out = gh.run(h)
    if not out.optimal:
        raise BoundError(f"the LP for {what} ended with status {out.status!r}")
    return out.objective


def lift_nonnegative(lp: LimitLP) -> bool:
    """True when no mechanism with ``B_n^T v >= 0`` lowers the dead load.

    One LP: ``min lift = -f_D . v`` over ``B_n^T v >= 0``, ``-1 <= v <= 1``
    (the set is a cone cut by a box, so the minimum is 0 or negative).
    """
    nv = lp.n_eq
    h = gh.tight_lp(gh.build(-lp.dead, lp.Bn.T.tocsc(), (np.zeros(lp.n_points), np.full(lp.n_points, np.inf)),
                             (-np.ones(nv), np.ones(nv))))
    return _optimum(h, "the lift of the mechanisms") >= -LIFT_TOLERANCE


def big_m(lp: LimitLP, direction: int, *, lambda_upper: float = math.inf,
          policy: Literal["per_point", "uniform"] = "per_point") -> BigM:
    """The bounds of the global search in one load direction.

    Args:
        lp: the LP of the wall.
        direction: ``+1`` or ``-1``.
        lambda_upper: load factor of a known collapse state (only better
            ones are sought); ``inf``: none known.
        policy: ``"per_point"`` (an LP per point) or ``"uniform"`` (one LP).

    Returns:
        The :class:`BigM`.

    Raises:
        BoundError: an LP failed or a normal force is unbounded.
    """
    t0 = time.perf_counter()
    h = _static_model(lp, direction)
    col = lp.lam_col
    cost = np.zeros(lp.n_cols)
    cost[col] = -1.0
    h.changeColsCost(lp.n_cols, np.arange(lp.n_cols, dtype=np.int32), cost)
    lam_max = -_optimum(h, "the associative load factor")
    h.changeColCost(col, 1.0)
    lam_min = _optimum(h, "the lowest admissible load factor")
    lifting = lift_nonnegative(lp)
    lo = max(lam_min, 0.0) if lifting else lam_min
    up = min(lam_max, lambda_upper)
    h.changeColBounds(col, lo, up)
    h.changeColCost(col, 0.0)
    P = lp.n_points
    cols = np.arange(2 * P, dtype=np.int32)
    if policy == "uniform":
        h.changeColsCost(2 * P, cols, -np.ones(2 * P))
        normal = np.full(P, -_optimum(h, "the total normal force"))
        lps = 4
    else:
        normal = np.empty(P)
        for p in range(P):
            c = np.zeros(2 * P)
            c[[p, P + p]] = -1.0
            h.changeColsCost(2 * P, cols, c)
            normal[p] = -_optimum(h, f"the normal force at point {p}")
        lps = 3 + P
    if not np.all(np.isfinite(normal)):
        raise BoundError("a normal force is unbounded over the statically admissible fields")
    normal = np.maximum(normal, 0.0)
    normal = normal * (1.0 + BOUND_MARGIN) + BOUND_MARGIN * float(np.max(normal, initial=0.0))
    return BigM(normal, lo, up, lam_max, lifting, policy, lps, time.perf_counter() - t0)
