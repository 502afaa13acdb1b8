"""The global search's MIP solved by SCIP instead of HiGHS (optional: ``pip install xcheck-masonry[global]``).

The model is the big-M MIP of :mod:`micro.global_search.model`, read
column by column from the HiGHS model that :func:`~micro.global_search.model.build_mip`
assembles, so both solvers see the same rows, bounds and start. SCIP's answer
goes through the same rebuild and check as HiGHS' (:mod:`micro.global_search.search`).
Measured against HiGHS in ``docs/micro/global-search.md``.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.global_search import highs as gh

FloatArray = NDArray[np.float64]

#: SCIP statuses in HiGHS' words (what :mod:`micro.global_search.search` reads).
_STATUS = {"optimal": "Optimal", "gaplimit": "Optimal", "infeasible": "Infeasible", "nodelimit": "Node limit reached",
           "totalnodelimit": "Node limit reached", "timelimit": "Time limit reached"}


def from_model(h: gh.Model) -> tuple[Any, list[Any]]:
    """The model held by ``h`` (costs, bounds, rows, integrality) as a SCIP model.

    Returns:
        ``(pyscipopt.Model, its variables in the HiGHS model's column order)``.
    """
    import pyscipopt as ps

    cost, A, (row_lo, row_up), (col_lo, col_up), integer = gh.read_model(h)
    m = ps.Model()
    m.hideOutput(True)

    def bound(x: float) -> float | None:
        return float(x) if math.isfinite(x) else None

    xs = [m.addVar(lb=bound(col_lo[j]), ub=bound(col_up[j]), obj=float(cost[j]), vtype="I" if integer[j] else "C")
          for j in range(A.shape[1])]
    R = A.tocsr()
    for i in range(A.shape[0]):
        cols, vals = R.indices[R.indptr[i]:R.indptr[i + 1]], R.data[R.indptr[i]:R.indptr[i + 1]]
        expr = ps.quicksum(float(c) * xs[j] for j, c in zip(cols, vals, strict=True))
        lo, up = bound(row_lo[i]), bound(row_up[i])
        if lo is not None and up is not None:
            m.addCons(expr == lo if lo == up else lo <= (expr <= up))
        elif up is not None:
            m.addCons(expr <= up)
        elif lo is not None:
            m.addCons(expr >= lo)
    return m, xs


def set_start(m: Any, xs: list[Any], x: FloatArray) -> bool:
    """Hand SCIP a feasible point (all columns) as its first solution; True when accepted."""
    sol = m.createSol()
    for var, val in zip(xs, np.asarray(x, dtype=float), strict=True):
        m.setSolVal(sol, var, float(val))
    return bool(m.addSol(sol, free=True))


def run(m: Any, xs: list[Any], *, node_limit: int | None, time_limit: float | None, mip_gap: float,
        abs_gap: float, feasibility: float, seed: int = 0, log: bool = False) -> gh.MipOutcome:
    """Solve; the outcome in the shape of :func:`micro.global_search.highs.run`'s.

    Raises:
        KeyboardInterrupt: Ctrl-C (SCIP's own handler stops it within a node).
    """
    m.hideOutput(not log)
    if node_limit is not None:
        m.setParam("limits/nodes", int(node_limit))
    if time_limit is not None:
        m.setParam("limits/time", float(time_limit))
    m.setParam("limits/gap", float(mip_gap))
    m.setParam("limits/absgap", float(abs_gap))
    m.setParam("numerics/feastol", float(feasibility))
    m.setParam("randomization/randomseedshift", int(seed))
    t0 = time.perf_counter()
    m.optimize()
    secs = time.perf_counter() - t0
    status = str(m.getStatus())
    if status == "userinterrupt":
        raise KeyboardInterrupt
    x = np.array([m.getVal(v) for v in xs]) if m.getNSols() > 0 else None
    obj = float(m.getObjVal()) if x is not None else math.nan
    return gh.MipOutcome(_STATUS.get(status, status), x, obj, float(m.getDualbound()), int(m.getNNodes()), secs)
