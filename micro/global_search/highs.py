"""A thin HiGHS layer for the global (mixed-integer) search and its small LPs.

The global search (:mod:`micro.global_search`) builds its own models, column by
column, from the matrices of :class:`micro.lp.LimitLP`; this module passes
such a model to ``highspy`` and reads the outcome back in one shape, so that
the bounds, the pattern LPs and the MIP do not each repeat the ``HighsLp``
plumbing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import highspy
import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.highs_runs import quiet_highs

FloatArray = NDArray[np.float64]
#: The HiGHS model object the global search holds (its modules name the type
#: through this alias: they do not import ``highspy`` themselves).
Model = highspy.Highs

#: Primal and dual feasibility tolerance of the small LPs (scaled units:
#: forces in block weights, rates normalised to at most 1).
LP_TOLERANCE = 1e-10
#: How often (seconds) the main thread wakes while HiGHS' branch and bound
#: runs in its own thread, so that Ctrl-C is acted on.
POLL_SECONDS = 0.1
#: How long (seconds) to wait for HiGHS to stop once interrupted.
STOP_SECONDS = 10.0


@dataclass(frozen=True, eq=False)
class MipOutcome:
    """What one HiGHS run returned.

    Attributes:
        status: HiGHS model status as text (``"Optimal"``, ``"Infeasible"``,
            ``"Time limit reached"``, ...).
        x: primal values of the columns (``None`` when HiGHS has none).
        objective: objective value (NaN without a solution).
        dual_bound: MIP dual bound (the objective for an LP; NaN if unknown).
        nodes: branch-and-bound nodes (0 for an LP).
        seconds: run time.
    """

    status: str
    x: FloatArray | None = field(repr=False)
    objective: float
    dual_bound: float
    nodes: int
    seconds: float

    @property
    def optimal(self) -> bool:
        """True when HiGHS proved optimality."""
        return self.status == "Optimal"


def _finite(a: FloatArray, inf: float) -> FloatArray:
    """``a`` with ``+-inf`` replaced by HiGHS' infinity."""
    return np.where(np.isposinf(a), inf, np.where(np.isneginf(a), -inf, a)).astype(np.float64)


def build(
    cost: FloatArray,
    A: sp.csc_matrix,
    row_bounds: tuple[FloatArray, FloatArray],
    col_bounds: tuple[FloatArray, FloatArray],
    integer: NDArray[np.int64] | None = None,
) -> highspy.Highs:
    """A silent HiGHS model ``min cost x`` s.t. ``rl <= A x <= ru``, ``cl <= x <= cu``.

    Args:
        cost: objective coefficients.
        A: constraint matrix (converted to CSC).
        row_bounds: ``(lower, upper)`` of the rows (``+-inf`` allowed).
        col_bounds: ``(lower, upper)`` of the columns.
        integer: indices of the integer columns (``None``: an LP).

    Returns:
        The ``highspy.Highs`` object, ready to ``run()``.

    Raises:
        RuntimeError: HiGHS rejected the model.
    """
    h = quiet_highs()
    inf = h.getInfinity()
    A = sp.csc_matrix(A)
    A.sort_indices()
    m = highspy.HighsLp()
    m.num_col_, m.num_row_ = int(A.shape[1]), int(A.shape[0])
    m.col_cost_ = np.asarray(cost, dtype=np.float64)
    m.col_lower_, m.col_upper_ = (_finite(np.asarray(b, dtype=np.float64), inf) for b in col_bounds)
    m.row_lower_, m.row_upper_ = (_finite(np.asarray(b, dtype=np.float64), inf) for b in row_bounds)
    m.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    m.a_matrix_.num_col_, m.a_matrix_.num_row_ = m.num_col_, m.num_row_
    m.a_matrix_.start_ = A.indptr.astype(np.int32)
    m.a_matrix_.index_ = A.indices.astype(np.int32)
    m.a_matrix_.value_ = A.data.astype(np.float64)
    if integer is not None and len(integer) > 0:
        kinds = np.full(m.num_col_, highspy.HighsVarType.kContinuous)
        kinds[np.asarray(integer, dtype=np.int64)] = highspy.HighsVarType.kInteger
        m.integrality_ = list(kinds)
    if h.passModel(m) == highspy.HighsStatus.kError:
        raise RuntimeError("HiGHS rejected the model (passModel returned kError)")
    return h


def read_model(h: highspy.Highs) -> tuple[FloatArray, sp.csc_matrix, tuple[FloatArray, FloatArray],
                                          tuple[FloatArray, FloatArray], NDArray[np.bool_]]:
    """The model ``h`` holds, as :func:`build` takes it (``+-inf`` for HiGHS' infinity).

    Returns:
        ``(cost, A, (row lower, row upper), (col lower, col upper), integer columns mask)``.
    """
    lp = h.getLp()
    inf = h.getInfinity()
    a = lp.a_matrix_
    A = sp.csc_matrix((np.asarray(a.value_), np.asarray(a.index_), np.asarray(a.start_)),
                      shape=(int(lp.num_row_), int(lp.num_col_)))

    def bounds(x: object) -> FloatArray:
        b = np.asarray(x, dtype=np.float64)
        return np.where(b >= inf, np.inf, np.where(b <= -inf, -np.inf, b))

    kinds = list(lp.integrality_)
    integer = np.array([k != highspy.HighsVarType.kContinuous for k in kinds], dtype=bool) if kinds else \
        np.zeros(int(lp.num_col_), dtype=bool)
    return (np.asarray(lp.col_cost_, dtype=np.float64), A, (bounds(lp.row_lower_), bounds(lp.row_upper_)),
            (bounds(lp.col_lower_), bounds(lp.col_upper_)), integer)


def tight_lp(h: highspy.Highs) -> highspy.Highs:
    """Set the tolerances of a small LP (:data:`LP_TOLERANCE`) and return ``h``."""
    h.setOptionValue("primal_feasibility_tolerance", LP_TOLERANCE)
    h.setOptionValue("dual_feasibility_tolerance", LP_TOLERANCE)
    return h


def set_start(h: highspy.Highs, x: FloatArray) -> None:
    """Hand HiGHS a feasible point ``x`` (all columns) as its first incumbent."""
    sol = highspy.HighsSolution()
    sol.col_value = list(np.asarray(x, dtype=np.float64))
    sol.value_valid = True
    h.setSolution(sol)


def run(h: highspy.Highs, *, mip: bool = False) -> MipOutcome:
    """Run ``h`` and collect the outcome.

    Args:
        h: a model from :func:`build` (options already set).
        mip: the model has integer columns (read the dual bound and nodes).

    Returns:
        The :class:`MipOutcome`.

    Raises:
        KeyboardInterrupt: Ctrl-C during a MIP: HiGHS is stopped (by its
            interrupt callback, within a node) before it is raised again.
    """
    if mip:
        _run_interruptible(h)
    else:
        h.run()
    status = h.modelStatusToString(h.getModelStatus())
    info = h.getInfo()
    sol = h.getSolution()
    has_x = bool(sol.value_valid) and info.primal_solution_status != 0
    x = np.asarray(sol.col_value, dtype=np.float64) if has_x else None
    obj = float(info.objective_function_value) if x is not None else math.nan
    bound = float(info.mip_dual_bound) if mip else obj
    nodes = int(info.mip_node_count) if mip else 0
    return MipOutcome(status, x, obj, bound, nodes, float(h.getRunTime()))


def _run_interruptible(h: highspy.Highs) -> None:
    """``h.run()`` in HiGHS' own thread, the main thread waiting in short
    slices: a plain ``run()`` holds the main thread in C++ until the search
    ends, so Python's Ctrl-C handler ran only when the time limit stopped it.
    On Ctrl-C the interrupt callbacks stop HiGHS and the interrupt is raised again."""
    h.HandleUserInterrupt = True
    h.startSolve()
    try:
        while not h.wait(POLL_SECONDS)[0]:
            pass
    except KeyboardInterrupt:
        h.cancelSolve()
        h.wait(STOP_SECONDS)
        raise
