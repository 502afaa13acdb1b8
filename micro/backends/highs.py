"""HiGHS through ``highspy``: a persistent model and the one-shot adapter on top of it.

:class:`PersistentHighsModel` holds one HiGHS model and changes it in place
between runs (column and row bounds, coefficients, cost, basis, algorithm):
the iterated non-associative LP (:mod:`micro.nonassociative`) talks to HiGHS
only through it. :class:`HighsBackend` is the one-shot back end of
:func:`micro.solve_associative`: the generator-form LP, one cost change per
direction.

HiGHS dual convention (pinned by ``tests/micro/backends``): for ``min c.x``
it returns row duals ``y`` with ``c = A^T y + z``; with ``c_lambda = -d``
this gives ``(d f_L) . y = -1``, so velocities are ``-y``
(:data:`DUAL_SIGN`); :class:`~micro.backends.base.Outcome` carries them in the
shared sign.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.base import Outcome, Status, recheck
from micro.backends.highs_runs import STALL_CALLS, RunCallback, StallGuard, quiet_highs
from micro.backends.interrupt import deferred_signals
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]

#: Multiply HiGHS's row duals by this to get the shared convention.
DUAL_SIGN = -1.0
#: Primal and dual feasibility tolerances of the dual simplex: HiGHS's
#: default 1e-7 gave "Optimal" with unscaled residuals of 1e-3.
SIMPLEX_TOLERANCE = 1e-10
ALGORITHMS = ("ipm", "simplex")
#: HiGHS' ``simplex_strategy`` values: the dual simplex (its default), the primal one (from a carried-over basis).
DUAL_STRATEGY, PRIMAL_STRATEGY = 1, 4
#: ``HighsBasisStatus`` codes of :meth:`PersistentHighsModel.basis_arrays`.
LOWER, BASIC, UPPER = 0, 1, 2
#: HiGHS' default (no limit) of ``simplex_iteration_limit`` and ``ipm_iteration_limit``.
_ITERATIONS_MAX = 2**31 - 1
def _highs_inf(a: FloatArray, inf: float) -> FloatArray:
    a = np.array(a, dtype=np.float64, copy=True)
    a[np.isposinf(a)] = inf
    a[np.isneginf(a)] = -inf
    return a


def _check_algorithm(algorithm: str) -> None:
    if algorithm not in ALGORITHMS:
        raise ValueError(f"algorithm must be 'ipm' or 'simplex', got {algorithm!r}")


class PersistentHighsModel:
    """One HiGHS model, changed in place between runs (the basis is kept).

    Args:
        A: constraint matrix (any scipy sparse format).
        cost, lower, upper: cost and bounds per column (``+-inf`` allowed).
        row_lower, row_upper: bounds per row.
        algorithm: ``"ipm"`` (IPX, no crossover) or ``"simplex"`` (dual
            simplex, :data:`SIMPLEX_TOLERANCE`).

    Raises:
        ValueError: an unknown algorithm.
        RuntimeError: HiGHS rejected the model.
    """

    #: HiGHS model status name -> shared status (anything else: ``solver_error``).
    STATUS_MAP = {
        "kOptimal": Status.OPTIMAL,
        "kInfeasible": Status.INFEASIBLE,
        "kUnbounded": Status.UNBOUNDED,
        "kTimeLimit": Status.TIME_LIMIT,
        "kIterationLimit": Status.ITERATION_LIMIT,
        "kUnboundedOrInfeasible": Status.INFEASIBLE_OR_UNBOUNDED,
    }

    def __init__(self, A: sp.spmatrix, cost: FloatArray, lower: FloatArray, upper: FloatArray,
                 row_lower: FloatArray, row_upper: FloatArray, *, algorithm: str = "ipm") -> None:
        import highspy

        _check_algorithm(algorithm)
        self._hs = highspy
        self._inf = float(highspy.kHighsInf)
        A = sp.csc_matrix(A)
        h = quiet_highs()
        h.setOptionValue("solver", algorithm)
        if algorithm == "ipm":
            # Crossover was both the slow part (minutes on 7,575 blocks) and
            # the inaccurate one: after it HiGHS reported "Optimal" with
            # unscaled equilibrium residuals of 8e-4 on the three-storey scene.
            # Without it the IPX solution has residuals ~1e-12.
            h.setOptionValue("run_crossover", "off")
        else:
            self._simplex_tolerances(h)
        m = highspy.HighsLp()
        m.num_col_ = int(A.shape[1])
        m.num_row_ = int(A.shape[0])
        m.col_cost_ = np.asarray(cost, dtype=np.float64)
        m.col_lower_ = _highs_inf(lower, self._inf)
        m.col_upper_ = _highs_inf(upper, self._inf)
        m.row_lower_ = _highs_inf(row_lower, self._inf)
        m.row_upper_ = _highs_inf(row_upper, self._inf)
        m.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        m.a_matrix_.num_col_ = int(A.shape[1])
        m.a_matrix_.num_row_ = int(A.shape[0])
        m.a_matrix_.start_ = A.indptr.astype(np.int32)
        m.a_matrix_.index_ = A.indices.astype(np.int32)
        m.a_matrix_.value_ = A.data.astype(np.float64)
        self._passed(h, h.passModel(m))
        self._highs = h
        self._callback = self._listen(h)
        self.algorithm = algorithm

    def _listen(self, h: Any) -> RunCallback:
        """Give ``h`` its :class:`RunCallback` on the simplex and interior-point interrupts."""
        kinds = self._hs.cb.HighsCallbackType
        callback = RunCallback(int(kinds.kCallbackSimplexInterrupt))
        h.setCallback(callback, None)
        h.startCallback(kinds.kCallbackSimplexInterrupt)
        h.startCallback(kinds.kCallbackIpmInterrupt)
        return callback

    @property
    def stall_guard(self) -> StallGuard | None:
        """The guard of :meth:`guard_stalls` (``None``: none)."""
        return self._callback.guard

    def guard_stalls(self, calls: int = STALL_CALLS) -> None:
        """Interrupt every later simplex run that stalls (:data:`~micro.backends.highs_runs.STALL_CALLS`);
        such a run ends ``solver_error`` with ``info["stalled"]``."""
        self._callback.guard = StallGuard(calls)

    def limit_excess_calls(self, excess: int | None) -> None:
        """Interrupt the next runs once their simplex callbacks beyond one per iteration add up to
        ``excess`` (``None``: no limit; the model must be guarded, :meth:`guard_stalls`)."""
        guard = self._callback.guard
        if guard is None:
            raise ValueError("limit_excess_calls needs a guarded model (guard_stalls)")
        guard.excess = excess

    @classmethod
    def of(cls, lp: LimitLP, direction: int, *, algorithm: str = "ipm") -> PersistentHighsModel:
        """The generator-form LP of ``lp`` with the cost of live load ``direction``."""
        return cls(lp.A, lp.cost(direction), lp.col_lower, lp.col_upper, lp.rhs, lp.rhs, algorithm=algorithm)

    def _passed(self, h: Any, status: Any) -> None:
        if status == self._hs.HighsStatus.kError:
            raise RuntimeError("HiGHS rejected the model (passModel returned kError)")

    @staticmethod
    def _simplex_tolerances(h: Any) -> None:
        h.setOptionValue("primal_feasibility_tolerance", SIMPLEX_TOLERANCE)
        h.setOptionValue("dual_feasibility_tolerance", SIMPLEX_TOLERANCE)

    # ------------------------------------------------------------ changes
    def set_col_bounds(self, cols: NDArray[Any], lower: FloatArray, upper: FloatArray) -> None:
        """Change column bounds in place (the basis is kept)."""
        cols = np.asarray(cols, dtype=np.int32)
        self._highs.changeColsBounds(cols.size, cols, _highs_inf(lower, self._inf), _highs_inf(upper, self._inf))

    def set_row_bounds(self, rows: NDArray[Any], lower: FloatArray, upper: FloatArray) -> None:
        """Change row bounds in place (the basis is kept)."""
        rows = np.asarray(rows, dtype=np.int32)
        self._highs.changeRowsBounds(  # type: ignore[attr-defined]  # missing from the stubs
            rows.size, rows, _highs_inf(lower, self._inf), _highs_inf(upper, self._inf))

    def add_rows(self, rows: sp.spmatrix, lower: FloatArray, upper: FloatArray) -> None:
        """Append rows ``lower <= rows @ x <= upper``."""
        rows = sp.csr_matrix(rows)
        rows.sort_indices()
        self._highs.addRows(
            rows.shape[0], _highs_inf(lower, self._inf), _highs_inf(upper, self._inf), int(rows.nnz),
            rows.indptr[:-1].astype(np.int32), rows.indices.astype(np.int32), rows.data.astype(np.float64),
        )

    def change_coeffs(self, rows: NDArray[Any], cols: NDArray[Any], values: FloatArray) -> None:
        """Change matrix entries one by one (the basis is kept)."""
        h = self._highs
        for r, c, v in zip(np.asarray(rows).tolist(), np.asarray(cols).tolist(), np.asarray(values).tolist(),
                           strict=True):
            h.changeCoeff(r, c, v)

    def set_cost(self, col: int, value: float) -> None:
        """Change the cost of one column."""
        self._highs.changeColCost(col, value)

    def set_costs(self, cols: NDArray[Any], values: FloatArray) -> None:
        """Change the costs of many columns at once (the basis is kept)."""
        cols = np.asarray(cols, dtype=np.int32)
        self._highs.changeColsCost(cols.size, cols, np.asarray(values, dtype=np.float64))

    @property
    def n_rows(self) -> int:
        """Rows of the model."""
        return int(self._highs.getNumRow())

    def get_basis(self) -> Any:
        """The current basis (an opaque object for :meth:`set_basis`)."""
        return self._highs.getBasis()

    def set_basis(self, basis: Any) -> None:
        """Restore a basis from :meth:`get_basis`."""
        self._highs.setBasis(basis)

    def clear_solver(self) -> None:
        """Forget the basis and any solution: the next run starts cold."""
        self._highs.clearSolver()

    def basis_arrays(self) -> tuple[NDArray[np.int8], NDArray[np.int8]]:
        """The current basis as ``HighsBasisStatus`` codes (:data:`LOWER`, :data:`BASIC`, :data:`UPPER`,
        ...) of the columns and of the rows: arrays another model's basis can be built from."""
        b = self._highs.getBasis()
        return (np.fromiter((int(c) for c in b.col_status), dtype=np.int8, count=len(b.col_status)),
                np.fromiter((int(r) for r in b.row_status), dtype=np.int8, count=len(b.row_status)))

    def set_basis_arrays(self, cols: NDArray[np.int8], rows: NDArray[np.int8]) -> None:
        """Start the next run from the basis of these status codes (one per column and row, as
        :meth:`basis_arrays` gives them); HiGHS repairs a singular one with slack columns."""
        status = self._hs.HighsBasisStatus
        codes = {int(c): c for c in (status.kLower, status.kBasic, status.kUpper, status.kZero, status.kNonbasic)}
        b = self._hs.HighsBasis()
        b.col_status = [codes[c] for c in np.asarray(cols).tolist()]
        b.row_status = [codes[r] for r in np.asarray(rows).tolist()]
        b.valid = True
        self._highs.setBasis(b)

    def set_algorithm(self, algorithm: str, *, crossover: bool = False, primal: bool = False) -> None:
        """Switch between ``"ipm"`` (with or without crossover) and ``"simplex"``
        (the dual simplex, or with ``primal`` the primal one) for the next
        runs; the model and any basis are kept."""
        _check_algorithm(algorithm)
        h = self._highs
        h.setOptionValue("solver", algorithm)
        h.setOptionValue("run_crossover", "on" if crossover else "off")
        h.setOptionValue("simplex_strategy", PRIMAL_STRATEGY if primal else DUAL_STRATEGY)
        if algorithm == "simplex":
            self._simplex_tolerances(h)
        self.algorithm = algorithm

    def limit_next_run(self, seconds: float | None, *, simplex_iterations: int | None = None,
                       ipm_iterations: int | None = None) -> None:
        """Limit the NEXT run to ``seconds`` and to the given simplex and
        interior-point iteration counts (``None`` or ``inf``: no limit).

        HiGHS compares ``time_limit`` with the run time accumulated over
        all runs of the object (a warm run after earlier runs stops at once,
        long before its own ``time_limit``: docs/speed.md), so the limit is
        set from the run time so far; the iteration limits count per run. A
        run stopped by an iteration limit reports ``iteration_limit``.
        """
        h = self._highs
        if seconds is not None and np.isfinite(seconds):
            h.setOptionValue("time_limit", float(h.getRunTime()) + float(seconds))
        else:
            h.setOptionValue("time_limit", float("inf"))
        h.setOptionValue("simplex_iteration_limit", _ITERATIONS_MAX if simplex_iterations is None
                         else int(simplex_iterations))
        h.setOptionValue("ipm_iteration_limit", _ITERATIONS_MAX if ipm_iterations is None else int(ipm_iterations))

    def limit_iterations(self, iterations: int | None) -> None:
        """Cap the simplex iterations of the next runs (``None``: no cap).
        Unlike a time limit, the cap stops a run at the same point on every
        machine."""
        cap = 2**31 - 1 if iterations is None else max(int(iterations), 1)
        self._highs.setOptionValue("simplex_iteration_limit", cap)

    def cold_copy(self, algorithm: str = "ipm") -> PersistentHighsModel:
        """A new model holding a copy of the CURRENT one (columns, rows,
        bounds, cost) and no basis, with HiGHS's default options but for
        ``algorithm``: for re-solving an iterate cold."""
        clone = object.__new__(PersistentHighsModel)
        clone._hs, clone._inf = self._hs, self._inf
        h = quiet_highs()
        clone._passed(h, h.passModel(self._highs.getLp()))
        clone._highs = h
        clone._callback = clone._listen(h)
        clone.set_algorithm(algorithm)
        return clone

    # ---------------------------------------------------------------- run
    def run(self, *, presolve: bool = True) -> Outcome:
        """Run HiGHS on the model as it is (cost, bounds and basis kept).

        Args:
            presolve: ``False``: run once without presolve and from no basis
                (to tell infeasible from unbounded when presolve could not).

        Returns:
            The :class:`~micro.backends.base.Outcome` with the column values
            ``x`` and the row ``duals`` in the shared sign (``None`` unless
            optimal) and ``info`` with HiGHS's largest primal and dual
            infeasibilities.
        """
        h = self._highs
        if not presolve:
            h.setOptionValue("presolve", "off")
            h.clearSolver()
        if self.stall_guard is not None:
            self.stall_guard.reset()
        t0 = time.perf_counter()
        try:
            with deferred_signals(self._callback.stop):  # Ctrl-C stops HiGHS through the callback, then raises
                h.run()
        finally:
            if not presolve:
                h.setOptionValue("presolve", "choose")
        self._callback.stop.raise_kept()
        secs = time.perf_counter() - t0
        ms = h.getModelStatus()
        info = h.getInfo()
        status = self.STATUS_MAP.get(ms.name, Status.SOLVER_ERROR)
        x = duals = None
        if status is Status.OPTIMAL:
            sol = h.getSolution()
            x = np.asarray(sol.col_value, dtype=float)
            duals = DUAL_SIGN * np.asarray(sol.row_dual, dtype=float)
        native, guard = h.modelStatusToString(ms), self.stall_guard
        stalled = guard is not None and guard.fired
        if stalled and guard is not None:
            native = f"stalled at simplex iteration {guard.iteration}, interrupted ({native})"
        return Outcome(
            status, native, x=x, duals=duals,
            simplex_iterations=int(info.simplex_iteration_count), ipm_iterations=int(info.ipm_iteration_count),
            crossover_iterations=int(info.crossover_iteration_count), seconds=secs,
            info={"max_primal_infeasibility": float(info.max_primal_infeasibility),
                  "max_dual_infeasibility": float(info.max_dual_infeasibility),
                  "stalled": stalled},
        )


class HighsBackend:
    """The one-shot HiGHS back end: the generator-form LP in a persistent model,
    one cost change per direction (:meth:`solve`).

    Args:
        lp: the assembled LP.
        algorithm: ``"ipm"`` (IPX, no crossover) or ``"simplex"`` (dual simplex).
        time_limit: seconds per solve (``None``: unlimited).
    """

    STATUS_MAP = PersistentHighsModel.STATUS_MAP

    def __init__(self, lp: LimitLP, *, algorithm: str = "ipm", time_limit: float | None = None) -> None:
        self.lp = lp
        self.name = f"highs-{algorithm}"
        self.time_limit = time_limit
        self.model = PersistentHighsModel.of(lp, +1, algorithm=algorithm)

    def solve(self, direction: int) -> Outcome:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``)."""
        lp, model = self.lp, self.model
        model.set_cost(lp.lam_col, -float(direction))
        if self.time_limit is not None:
            model.limit_next_run(self.time_limit)
        out = model.run()
        if out.status is Status.INFEASIBLE_OR_UNBOUNDED:
            # presolve could not tell which: ask again without presolve
            again = model.run(presolve=False)
            out = again.plus_seconds(out.seconds)
        info = {**out.info, "algorithm": model.algorithm, "simplex_iterations": out.simplex_iterations,
                "ipm_iterations": out.ipm_iterations, "crossover_iterations": out.crossover_iterations}
        if out.x is None or out.duals is None:
            return Outcome(out.status, out.native_status, simplex_iterations=out.simplex_iterations,
                           ipm_iterations=out.ipm_iterations, crossover_iterations=out.crossover_iterations,
                           seconds=out.seconds, info=info)
        n, s = lp.forces(out.x[: 2 * lp.n_points])
        lam = float(out.x[lp.lam_col])
        checked = Outcome(out.status, out.native_status, float(direction) * lam, n=n, s=s,
                          duals=out.duals[: lp.n_eq], simplex_iterations=out.simplex_iterations,
                          ipm_iterations=out.ipm_iterations, crossover_iterations=out.crossover_iterations,
                          seconds=out.seconds, info=info)
        return recheck(lp, direction, checked)
