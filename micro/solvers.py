"""Back ends for the limit-analysis LP behind one small interface.

Modelled on cvxpy's solver layer: one adapter per back end, each of which

* builds its native model ONCE from a :class:`micro.lp.LimitLP` (persistent;
  bounds and rows can be changed between solves — see :meth:`HighsBackend.set_col_bounds`);
* maps its native status onto the shared :class:`Status`;
* maps its native dual signs onto the shared convention for the duals of the
  equilibrium rows (see :class:`RawSolution`).

Back ends (names accepted by :func:`make_backend`):

``highs``          HiGHS interior point (IPX) without crossover — HiGHS's
                   fastest accurate algorithm on these LPs (default of
                   :func:`micro.solve_associative`);
``highs-ipm``      the same, named explicitly;
``highs-simplex``  HiGHS dual simplex with 1e-10 feasibility tolerances
                   (warm-startable: the one the iterated non-associative
                   scheme will need; cold, it is slow on large walls);
``clarabel``       Clarabel (interior point) on the kinematic (dual) form of
                   the LP (:mod:`micro.clarabel_kinematic`) — the fastest
                   and most accurate interior point measured on every wall
                   size (docs/micro-associative.md);
``clarabel-static`` Clarabel's direct API on the static form, with tightened
                   tolerances (see :data:`CLARABEL_TIGHT`);
``cvxpy``          the readable reference formulation in cvxpy expressions,
                   solved by Clarabel (``cvxpy`` / ``cvxpy-clarabel``) or by
                   HiGHS (``cvxpy-highs``) through cvxpy.
"""

from __future__ import annotations

import enum
import time
import warnings
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.lp import LimitLP

FloatArray = NDArray[np.float64]


class Status(str, enum.Enum):
    """Solver outcome, shared by every back end."""

    OPTIMAL = "optimal"
    INFEASIBLE = "infeasible"
    UNBOUNDED = "unbounded"
    INFEASIBLE_OR_UNBOUNDED = "infeasible_or_unbounded"
    TIME_LIMIT = "time_limit"
    ITERATION_LIMIT = "iteration_limit"
    INACCURATE = "inaccurate"
    SOLVER_ERROR = "solver_error"

    def __str__(self) -> str:  # pragma: no cover - trivial
        return self.value


@dataclass(frozen=True, eq=False)
class RawSolution:
    """What a back end returns for one direction of the live load.

    Shared dual convention: ``velocities`` are the duals of the equilibrium
    rows, signed so that they ARE the (generalised) block velocities
    ``(u, v, omega)`` per block of the collapse mechanism, scaled by the LP's
    own normalisation: the live load does work ``+1``
    (``(d * f_L) . velocities = 1``) and the dead load ``-lambda``.

    Attributes:
        status: shared status.
        native_status: the back end's own status string.
        load_factor: ``lambda`` for this direction (``NaN`` unless optimal).
        n, s: point forces (normal, shear) in scaled units, or ``None``.
        velocities: duals of the equilibrium rows (see above), or ``None``.
        iterations: solver iterations (simplex + IPM + crossover where given).
        solve_seconds: wall time of the solve call(s).
        info: extra back-end facts (residuals, algorithm, ...).
    """

    status: Status
    native_status: str
    load_factor: float
    n: FloatArray | None = field(repr=False)
    s: FloatArray | None = field(repr=False)
    velocities: FloatArray | None = field(repr=False)
    iterations: int
    solve_seconds: float
    info: dict[str, Any] = field(default_factory=dict, repr=False)


class Backend(Protocol):
    """The interface every back end implements."""

    name: str
    #: multiply the native equilibrium-row duals by this to get velocities
    dual_sign: float

    def solve(self, direction: int) -> RawSolution:
        """Solve for the live load in ``+x`` (``direction=+1``) or ``-x`` (``-1``)."""
        ...


#: Largest primal violation (equilibrium, ``n >= 0``, Coulomb; scaled units:
#: full-block weights) accepted from a back end that reports optimal. Beyond
#: it the status becomes ``inaccurate`` and the load factor NaN: HiGHS was seen
#: to report "Optimal" with unscaled equilibrium residuals of 1e-3.
MAX_RESIDUAL = 1e-6


def _failed(status: Status, native: str, seconds: float, iterations: int = 0, **info: Any) -> RawSolution:
    return RawSolution(status, native, float("nan"), None, None, None, iterations, seconds, dict(info))


def _finish(
    lp: LimitLP,
    direction: int,
    native: str,
    lam: float,
    n: FloatArray,
    s: FloatArray,
    velocities: FloatArray,
    iterations: int,
    seconds: float,
    info: dict[str, Any],
    *,
    coulomb: bool = True,
) -> RawSolution:
    """Check an optimal solution independently of the back end and package it."""
    res = lp.primal_residual(n, s, lam, coulomb=coulomb)
    live_work = float(direction) * float(lp.live @ velocities)
    info = {**info, "primal_residual": res, "live_work": live_work, "raw_load_factor": float(direction) * lam}
    if not np.isfinite(res) or res > MAX_RESIDUAL:
        return RawSolution(Status.INACCURATE, native, float("nan"), n, s, velocities, iterations, seconds, info)
    return RawSolution(Status.OPTIMAL, native, float(direction) * lam, n, s, velocities, iterations, seconds, info)


# =========================================================================== HiGHS
class HighsBackend:
    """HiGHS through ``highspy`` (persistent model).

    The model is passed once; :meth:`solve` only changes the cost of the
    ``lambda`` column and runs. With ``algorithm="simplex"`` HiGHS keeps its
    basis between runs (warm start after bound changes, as the iterated
    non-associative scheme needs).

    HiGHS dual convention (pinned by ``tests/micro/test_duals.py``): for
    ``min c.x`` it returns row duals ``y`` with ``c = A^T y + z``; with
    ``c_lambda = -d`` this gives ``(d f_L) . y = -1``, so velocities are
    ``-y`` (:attr:`dual_sign` ``= -1``).

    Args:
        lp: the assembled LP.
        algorithm: ``"ipm"`` (IPX, no crossover) or ``"simplex"`` (dual simplex).
        time_limit: seconds per solve (``None``: unlimited).
        options: extra HiGHS options (name -> value).
        columns: ``(A, cost, lower, upper)`` to pass instead of the generator
            form: any columns over the LP's equilibrium rows (the iterated
            non-associative scheme passes ``[B_n, B_s, f_L]``). :meth:`solve`
            needs the generator form; :meth:`run_raw` works on any.
    """

    dual_sign = -1.0

    def __init__(
        self,
        lp: LimitLP,
        *,
        algorithm: str = "ipm",
        time_limit: float | None = None,
        options: dict[str, Any] | None = None,
        columns: tuple[sp.csc_matrix, FloatArray, FloatArray, FloatArray] | None = None,
    ) -> None:
        import highspy

        if algorithm not in ("ipm", "simplex"):
            raise ValueError(f"algorithm must be 'ipm' or 'simplex', got {algorithm!r}")
        self.lp = lp
        self.algorithm = algorithm
        self.name = f"highs-{algorithm}"
        self._hs = highspy
        h = highspy.Highs()
        h.setOptionValue("output_flag", False)
        h.setOptionValue("solver", algorithm)
        if algorithm == "ipm":
            # Crossover was both the slow part (minutes on 7,575 blocks) and
            # the inaccurate one: after it HiGHS reported "Optimal" with
            # unscaled equilibrium residuals of 8e-4 on the three-storey scene.
            # Without it the IPX solution has residuals ~1e-12.
            h.setOptionValue("run_crossover", "off")
        self.time_limit = time_limit
        for k, v in (options or {}).items():
            h.setOptionValue(k, v)
        if algorithm == "simplex":
            # default 1e-7 tolerances gave "Optimal" with 1e-3 unscaled residuals
            h.setOptionValue("primal_feasibility_tolerance", 1e-10)
            h.setOptionValue("dual_feasibility_tolerance", 1e-10)
        if columns is None:
            A, cost, lower, upper = lp.A.tocsc(), lp.cost(+1), lp.col_lower, lp.col_upper
        else:
            A, cost, lower, upper = sp.csc_matrix(columns[0]), columns[1], columns[2], columns[3]
            if A.shape[0] != lp.n_rows or not (cost.size == lower.size == upper.size == A.shape[1]):
                raise ValueError("columns: the matrix must have the LP's equilibrium rows and one cost and "
                                 "bound per column")
        m = highspy.HighsLp()
        m.num_col_ = int(A.shape[1])
        m.num_row_ = lp.n_rows
        m.col_cost_ = np.asarray(cost, dtype=np.float64)
        m.col_lower_ = _highs_inf(lower, highspy.kHighsInf)
        m.col_upper_ = _highs_inf(upper, highspy.kHighsInf)
        m.row_lower_ = lp.rhs.copy()
        m.row_upper_ = lp.rhs.copy()
        m.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        m.a_matrix_.num_col_ = int(A.shape[1])
        m.a_matrix_.num_row_ = lp.n_rows
        m.a_matrix_.start_ = A.indptr.astype(np.int32)
        m.a_matrix_.index_ = A.indices.astype(np.int32)
        m.a_matrix_.value_ = A.data.astype(np.float64)
        status = h.passModel(m)
        if status == highspy.HighsStatus.kError:
            raise RuntimeError("HiGHS rejected the model (passModel returned kError)")
        self.highs = h

    # ---- persistent-model updates (for the iterated non-associative scheme)
    def add_columns(self, cols: sp.csc_matrix, lower: np.ndarray, upper: np.ndarray) -> None:
        """Append columns (zero cost) to the persistent model, e.g. the ``n``,
        ``s`` columns ``[B_n, B_s]`` of the non-associative scheme.

        Columns ``n_cols .. n_cols + P - 1`` are then read back as extra
        normal forces and the next ``P`` as extra shear forces.
        """
        cols = sp.csc_matrix(cols)
        inf = self._hs.kHighsInf
        k = cols.shape[1]
        self.highs.addCols(
            k,
            np.zeros(k),
            _highs_inf(lower, inf),
            _highs_inf(upper, inf),
            int(cols.nnz),
            cols.indptr[:-1].astype(np.int32),
            cols.indices.astype(np.int32),
            cols.data.astype(np.float64),
        )

    def set_col_bounds(self, cols: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> None:
        """Change column bounds in place (the basis is kept)."""
        inf = self._hs.kHighsInf
        cols = np.asarray(cols, dtype=np.int32)
        self.highs.changeColsBounds(cols.size, cols, _highs_inf(lower, inf), _highs_inf(upper, inf))

    def set_row_bounds(self, rows: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> None:
        """Change row bounds in place (the basis is kept)."""
        inf = self._hs.kHighsInf
        rows = np.asarray(rows, dtype=np.int32)
        self.highs.changeRowsBounds(rows.size, rows, _highs_inf(lower, inf), _highs_inf(upper, inf))

    def solve(self, direction: int) -> RawSolution:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``)."""
        hs = self._hs
        h = self.highs
        h.changeColCost(self.lp.lam_col, -float(direction))
        if self.time_limit is not None:
            # HiGHS measures its time limit against the run time accumulated
            # over the object's life: make it a limit per solve
            h.setOptionValue("time_limit", h.getRunTime() + float(self.time_limit))
        t0 = time.perf_counter()
        h.run()
        ms = h.getModelStatus()
        if ms == hs.HighsModelStatus.kUnboundedOrInfeasible:
            # presolve could not tell which: ask again without presolve
            h.setOptionValue("presolve", "off")
            h.clearSolver()
            h.run()
            ms = h.getModelStatus()
            h.setOptionValue("presolve", "choose")
        secs = time.perf_counter() - t0
        info = h.getInfo()
        iters = int(info.simplex_iteration_count) + int(info.ipm_iteration_count) + int(info.crossover_iteration_count)
        native = h.modelStatusToString(ms)
        extra = {
            "algorithm": self.algorithm,
            "simplex_iterations": int(info.simplex_iteration_count),
            "ipm_iterations": int(info.ipm_iteration_count),
            "crossover_iterations": int(info.crossover_iteration_count),
            "max_primal_infeasibility": float(info.max_primal_infeasibility),
            "max_dual_infeasibility": float(info.max_dual_infeasibility),
        }
        status = _HIGHS_STATUS.get(ms.name, Status.SOLVER_ERROR)
        if status is not Status.OPTIMAL:
            return _failed(status, native, secs, iters, **extra)
        sol = h.getSolution()
        x = np.asarray(sol.col_value, dtype=float)
        y = np.asarray(sol.row_dual, dtype=float)[: self.lp.n_eq]
        n, s = self.lp.forces(x[: 2 * self.lp.n_points])
        if x.size > self.lp.n_cols:  # columns added for the non-associative scheme
            P = self.lp.n_points
            n = n + x[self.lp.n_cols : self.lp.n_cols + P]
            s = s + x[self.lp.n_cols + P : self.lp.n_cols + 2 * P]
        lam = float(x[self.lp.lam_col])
        # with added columns the friction law is no longer |s| <= mu n
        return _finish(self.lp, direction, native, lam, n, s, self.dual_sign * y, iters, secs, extra,
                       coulomb=x.size == self.lp.n_cols)


    # ---- additions for the iterated non-associative scheme (micro.nonassociative)
    def add_rows(self, rows: sp.csr_matrix, lower: np.ndarray, upper: np.ndarray) -> None:
        """Append rows ``lower <= rows @ x <= upper`` to the persistent model
        (e.g. the two friction rows per point of scheme (b))."""
        rows = sp.csr_matrix(rows)
        rows.sort_indices()
        inf = self._hs.kHighsInf
        k = rows.shape[0]
        self.highs.addRows(
            k,
            _highs_inf(lower, inf),
            _highs_inf(upper, inf),
            int(rows.nnz),
            rows.indptr[:-1].astype(np.int32),
            rows.indices.astype(np.int32),
            rows.data.astype(np.float64),
        )

    def change_coeffs(self, rows: np.ndarray, cols: np.ndarray, values: np.ndarray) -> None:
        """Change matrix entries one by one (``Highs.changeCoeff``; the basis is kept)."""
        h = self.highs
        for r, c, v in zip(np.asarray(rows).tolist(), np.asarray(cols).tolist(), np.asarray(values).tolist()):
            h.changeCoeff(r, c, v)

    def set_algorithm(self, algorithm: str, *, crossover: bool = False) -> None:
        """Switch between ``"ipm"`` (with or without crossover) and ``"simplex"``
        for the next runs; the model and any basis are kept."""
        if algorithm not in ("ipm", "simplex"):
            raise ValueError(f"algorithm must be 'ipm' or 'simplex', got {algorithm!r}")
        h = self.highs
        h.setOptionValue("solver", algorithm)
        h.setOptionValue("run_crossover", "on" if crossover else "off")
        if algorithm == "simplex":
            h.setOptionValue("primal_feasibility_tolerance", 1e-10)
            h.setOptionValue("dual_feasibility_tolerance", 1e-10)
        self.algorithm = algorithm
        self.name = f"highs-{algorithm}"

    def run_raw(self) -> dict[str, Any]:
        """Run HiGHS on the current model as it is (cost, bounds and basis kept)
        and return the raw outcome without the associative residual check.

        Returns:
            ``status`` (:class:`Status`), ``native_status``, ``x`` (column
            values), ``row_dual`` (native sign), ``seconds``,
            ``simplex_iterations``, ``ipm_iterations``,
            ``crossover_iterations``; ``x`` and ``row_dual`` are ``None``
            unless optimal.
        """
        h = self.highs
        t0 = time.perf_counter()
        h.run()
        secs = time.perf_counter() - t0
        ms = h.getModelStatus()
        info = h.getInfo()
        status = _HIGHS_STATUS.get(ms.name, Status.SOLVER_ERROR)
        out: dict[str, Any] = {
            "status": status,
            "native_status": h.modelStatusToString(ms),
            "seconds": secs,
            "simplex_iterations": int(info.simplex_iteration_count),
            "ipm_iterations": int(info.ipm_iteration_count),
            "crossover_iterations": int(info.crossover_iteration_count),
            "x": None,
            "row_dual": None,
        }
        if status is Status.OPTIMAL:
            sol = h.getSolution()
            out["x"] = np.asarray(sol.col_value, dtype=float)
            out["row_dual"] = np.asarray(sol.row_dual, dtype=float)
        return out

    def cold_copy(self, algorithm: str = "ipm") -> "HighsBackend":
        """A new back end holding a copy of the CURRENT model (columns, rows,
        bounds, cost) and no basis: for re-solving an iterate cold."""
        import copy

        clone = copy.copy(self)
        h = self._hs.Highs()
        h.setOptionValue("output_flag", False)
        status = h.passModel(self.highs.getLp())
        if status == self._hs.HighsStatus.kError:
            raise RuntimeError("HiGHS rejected the copied model")
        clone.highs = h
        clone.set_algorithm(algorithm)
        return clone


_HIGHS_STATUS = {
    "kOptimal": Status.OPTIMAL,
    "kInfeasible": Status.INFEASIBLE,
    "kUnbounded": Status.UNBOUNDED,
    "kTimeLimit": Status.TIME_LIMIT,
    "kIterationLimit": Status.ITERATION_LIMIT,
    "kUnboundedOrInfeasible": Status.INFEASIBLE_OR_UNBOUNDED,  # still ambiguous after a presolve-off re-run
}


def _highs_inf(a: np.ndarray, inf: float) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True)
    a[np.isposinf(a)] = inf
    a[np.isneginf(a)] = -inf
    return a


# ======================================================================== Clarabel
#: Clarabel settings used by the ``clarabel`` back end. With Clarabel's
#: defaults (1e-8 gap and feasibility) lambda came out 1e-6 (54-150 blocks) to
#: 2e-4 (1,230 blocks) too low while Clarabel reported Solved: the error is
#: the dual (kinematic) infeasibility times the contact forces, which add up
#: to ~4e4 block weights on the 1,230-block wall. Tightening only the gap and
#: feasibility tolerances (1e-11) took 200+ iterations and stalled at ~2e-6;
#: lowering the static regularisation and tightening iterative refinement as
#: well reaches 1e-8 (Table 7 walls) and ~1e-6 (1,230 blocks) in ~40 iterations.
#: QDLDL is named: Clarabel's "auto" picks faer above ~2,700 blocks, 3x slower
#: on one core (3,630 blocks: 16.6 s against 5.6 s, same lambda to 1e-10).
CLARABEL_TIGHT: dict[str, Any] = {
    "direct_solve_method": "qdldl",
    "tol_gap_abs": 1e-10,
    "tol_gap_rel": 1e-10,
    "tol_feas": 1e-10,
    "static_regularization_constant": 1e-13,
    "iterative_refinement_reltol": 1e-15,
    "iterative_refinement_abstol": 1e-15,
    "iterative_refinement_max_iter": 50,
    "max_iter": 400,
}


class ClarabelBackend:
    """Clarabel's direct API (``min c.x  s.t.  A x + s = b, s in K``).

    Rows: the equilibrium equalities (zero cone), then ``-g <= 0`` for the
    friction-cone generators (non-negative cone). The problem data are built once; the
    direction only changes ``c`` (Clarabel cannot warm-start; a new solver
    object is made per solve).

    Clarabel dual convention (pinned by a test): KKT ``c + A^T z = 0`` with
    ``z`` the cone duals; with ``c_lambda = -d``: ``(d f_L) . z_eq = +1``, so
    velocities are ``+z_eq`` (:attr:`dual_sign` ``= +1``).

    Args:
        lp: the assembled LP.
        settings: Clarabel settings overriding :data:`CLARABEL_TIGHT`.
        tight: start from :data:`CLARABEL_TIGHT` (``True``) or from Clarabel's
            defaults (``False``).
        time_limit: seconds per solve.
    """

    dual_sign = 1.0

    def __init__(
        self,
        lp: LimitLP,
        *,
        settings: dict[str, Any] | None = None,
        tight: bool = True,
        time_limit: float | None = None,
    ) -> None:
        import clarabel

        self._cl = clarabel
        self.lp = lp
        self.tight = tight
        self.name = "clarabel-static" if tight else "clarabel-default"
        n_eq = lp.n_eq
        # columns fixed at zero (g- where mu = 0) are left out: duplicate
        # columns made Clarabel stop with NumericalError
        self.active = np.flatnonzero(lp.col_upper > 0.0)
        A = lp.A[:, self.active]
        ng = self.active.size - 1  # every active column but lambda is a generator >= 0
        neg_g = sp.csc_matrix((-np.ones(ng), (np.arange(ng), np.arange(ng))), shape=(ng, self.active.size))
        self.A = sp.vstack([A, neg_g], format="csc")
        self.b = np.concatenate([lp.rhs, np.zeros(ng)])
        self.cones = [clarabel.ZeroConeT(n_eq), clarabel.NonnegativeConeT(ng)]
        self.P = sp.csc_matrix((self.active.size, self.active.size))
        s = clarabel.DefaultSettings()
        s.verbose = False
        opts = dict(CLARABEL_TIGHT) if tight else {}
        opts.update(settings or {})
        if time_limit is not None:
            opts["time_limit"] = float(time_limit)
        for k, v in opts.items():
            if not hasattr(s, k):
                raise ValueError(f"unknown Clarabel setting {k!r}")
            setattr(s, k, v)
        self.settings = s

    def solve(self, direction: int) -> RawSolution:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``).

        With the tight settings, a stop short of them (``AlmostSolved``,
        ``InsufficientProgress``, ``NumericalError``; seen when base sliding
        governs exactly, a very degenerate optimum) is retried once with Clarabel's default
        static regularisation and 1e-9 tolerances; ``info["fallback"]`` says
        so. A second failure is reported as it is.
        """
        t0 = time.perf_counter()
        sol = self._run(direction, self.settings)
        native = str(sol.status).split(".")[-1]
        iters = int(sol.iterations)
        extra: dict[str, Any] = {}
        if self.tight and native in ("AlmostSolved", "InsufficientProgress", "NumericalError"):
            s = self._cl.DefaultSettings()
            for k in dir(self.settings):
                if not k.startswith("_") and hasattr(s, k) and not callable(getattr(s, k)):
                    setattr(s, k, getattr(self.settings, k))
            s.static_regularization_constant = 1e-8
            s.tol_gap_abs = s.tol_gap_rel = s.tol_feas = 1e-9
            sol = self._run(direction, s)
            extra["fallback"] = f"{native} with the tight settings; re-solved with static regularisation 1e-8, tol 1e-9"
            native = str(sol.status).split(".")[-1]
            iters += int(sol.iterations)
        secs = time.perf_counter() - t0
        status = _CLARABEL_STATUS.get(native, Status.SOLVER_ERROR)
        extra.update({"r_prim": float(sol.r_prim), "r_dual": float(sol.r_dual), "solver_time": float(sol.solve_time)})
        if status is not Status.OPTIMAL:
            return _failed(status, native, secs, iters, **extra)
        x = np.zeros(self.lp.n_cols)
        x[self.active] = np.asarray(sol.x, dtype=float)
        z = np.asarray(sol.z, dtype=float)[: self.lp.n_eq]
        n, s_ = self.lp.forces(x)
        lam = float(x[self.lp.lam_col])
        return _finish(self.lp, direction, native, lam, n, s_, self.dual_sign * z, iters, secs, extra)

    def _run(self, direction: int, settings: Any) -> Any:
        c = self.lp.cost(direction)[self.active]
        solver = self._cl.DefaultSolver(self.P, c, self.A, self.b, self.cones, settings)
        return solver.solve()


_CLARABEL_STATUS = {
    "Solved": Status.OPTIMAL,
    "AlmostSolved": Status.INACCURATE,
    "PrimalInfeasible": Status.INFEASIBLE,
    "AlmostPrimalInfeasible": Status.INACCURATE,
    "DualInfeasible": Status.UNBOUNDED,
    "AlmostDualInfeasible": Status.INACCURATE,
    "MaxIterations": Status.ITERATION_LIMIT,
    "MaxTime": Status.TIME_LIMIT,
    "NumericalError": Status.SOLVER_ERROR,
    "InsufficientProgress": Status.INACCURATE,
    "CallbackTerminated": Status.SOLVER_ERROR,
    "Unsolved": Status.SOLVER_ERROR,
}


# =========================================================================== cvxpy
class CvxpyBackend:
    """The reference formulation written with cvxpy expressions.

    ::

        maximise   d * lam
        subject to B_n @ n + B_s @ s + lam * f_L == -f_D    (equilibrium)
                   s <= mu * n,  -s <= mu * n,  n >= 0       (Coulomb)

    The direction ``d`` is a cvxpy Parameter, so the problem is compiled once
    (DPP) and re-solved for the other direction.

    cvxpy dual convention (pinned by a test): for this ``Maximize`` problem,
    the dual of the equality ``B x + lam f_L == -f_D`` satisfies
    ``(d f_L) . y = +1``, so velocities are ``+y`` (:attr:`dual_sign`).

    Args:
        lp: the assembled LP.
        solver: ``"CLARABEL"`` or ``"HIGHS"``.
        tight: use :data:`CLARABEL_TIGHT` tolerances with Clarabel (``False``:
            cvxpy's defaults — the "plain" baseline).
        solver_options: extra keyword arguments for ``Problem.solve``.
    """

    dual_sign = 1.0

    def __init__(
        self,
        lp: LimitLP,
        *,
        solver: str = "CLARABEL",
        tight: bool = True,
        solver_options: dict[str, Any] | None = None,
    ) -> None:
        import cvxpy as cp

        self._cp = cp
        self.lp = lp
        solver = solver.upper()
        if solver not in ("CLARABEL", "HIGHS"):
            raise ValueError(f"cvxpy solver must be CLARABEL or HIGHS, got {solver!r}")
        self.solver = solver
        self.name = f"cvxpy-{solver.lower()}" + ("" if tight or solver != "CLARABEL" else "-default")
        P = lp.n_points
        Bn, Bs = lp.equilibrium_matrix()
        mu = lp.mu
        self.n = cp.Variable(P, nonneg=True, name="n")
        self.s = cp.Variable(P, name="s")
        self.lam = cp.Variable(name="lam")
        self.d = cp.Parameter(value=1.0, name="direction")
        self.equilibrium = Bn @ self.n + Bs @ self.s + self.lam * lp.live == lp.rhs
        self.friction = [self.s - cp.multiply(mu, self.n) <= 0, -self.s - cp.multiply(mu, self.n) <= 0]
        self.problem = cp.Problem(cp.Maximize(self.d * self.lam), [self.equilibrium, *self.friction])
        opts: dict[str, Any] = {}
        if solver == "CLARABEL" and tight:
            opts.update(CLARABEL_TIGHT)
        opts.update(solver_options or {})
        self.options = opts

    def solve(self, direction: int) -> RawSolution:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``)."""
        cp = self._cp
        self.d.value = float(direction)
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings():
                # cvxpy warns "Solution may be inaccurate"; the status below says so
                warnings.filterwarnings("ignore", message="Solution may be inaccurate")
                self.problem.solve(solver=self.solver, **self.options)
        except cp.error.SolverError as exc:
            return _failed(Status.SOLVER_ERROR, f"SolverError: {exc}", time.perf_counter() - t0)
        secs = time.perf_counter() - t0
        native = str(self.problem.status)
        status = _CVXPY_STATUS.get(native, Status.SOLVER_ERROR)
        stats = self.problem.solver_stats
        iters = int(stats.num_iters or 0) if stats is not None else 0
        extra = {"solve_time_solver": float(stats.solve_time or 0.0) if stats is not None else float("nan")}
        if status is not Status.OPTIMAL:
            return _failed(status, native, secs, iters, **extra)
        y = np.asarray(self.equilibrium.dual_value, dtype=float)
        n = np.asarray(self.n.value, dtype=float)
        s = np.asarray(self.s.value, dtype=float)
        return _finish(self.lp, direction, native, float(self.lam.value), n, s, self.dual_sign * y, iters, secs, extra)


_CVXPY_STATUS = {
    "optimal": Status.OPTIMAL,
    "optimal_inaccurate": Status.INACCURATE,
    "infeasible": Status.INFEASIBLE,
    "infeasible_inaccurate": Status.INACCURATE,
    "unbounded": Status.UNBOUNDED,
    "unbounded_inaccurate": Status.INACCURATE,
    "infeasible_or_unbounded": Status.INFEASIBLE_OR_UNBOUNDED,
    "user_limit": Status.TIME_LIMIT,
    "solver_error": Status.SOLVER_ERROR,
}


# ========================================================================= factory
#: Names accepted by :func:`make_backend` (and the CLI's ``--solver``).
SOLVERS = ("highs", "highs-simplex", "highs-ipm", "clarabel", "cvxpy")
_ALL = (*SOLVERS, "clarabel-static", "cvxpy-clarabel", "cvxpy-highs", "clarabel-default", "cvxpy-clarabel-default")


def make_backend(lp: LimitLP, solver: str = "highs", *, time_limit: float | None = None) -> Backend:
    """Make the back end called ``solver`` for ``lp``.

    Raises:
        ValueError: an unknown solver name (the message lists the valid ones).
    """
    if solver in ("highs", "highs-ipm"):
        return HighsBackend(lp, algorithm="ipm", time_limit=time_limit)
    if solver == "highs-simplex":
        return HighsBackend(lp, algorithm="simplex", time_limit=time_limit)
    if solver == "clarabel":
        from micro.clarabel_kinematic import ClarabelKinematicBackend

        return ClarabelKinematicBackend(lp, time_limit=time_limit)
    if solver == "clarabel-static":
        return ClarabelBackend(lp, time_limit=time_limit)
    if solver == "clarabel-default":
        return ClarabelBackend(lp, tight=False, time_limit=time_limit)
    if solver in ("cvxpy", "cvxpy-clarabel"):
        return CvxpyBackend(lp, solver="CLARABEL")
    if solver == "cvxpy-clarabel-default":
        return CvxpyBackend(lp, solver="CLARABEL", tight=False)
    if solver == "cvxpy-highs":
        return CvxpyBackend(lp, solver="HIGHS")
    raise ValueError(f"solver must be one of {', '.join(_ALL)}; got {solver!r}")
