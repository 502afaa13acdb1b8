"""Clarabel's settings, and its direct API on the static form: :class:`ClarabelStaticBackend` (``clarabel-static``).

The iterated non-associative LP solves its start and certificate LPs with
:class:`ClarabelStaticBackend`; the associative ``clarabel`` back end is the
kinematic form (:mod:`micro.backends.clarabel_kinematic`).

``min c.x  s.t.  A x + s = b, s in K``. Rows: the equilibrium equalities
(zero cone), then ``-g <= 0`` for the friction-cone generators (non-negative
cone). The problem data are built once; the direction only changes ``c``
(Clarabel cannot warm-start: a new solver object is made per solve).

Clarabel dual convention (pinned by ``tests/micro/backends``): KKT
``c + A^T z = 0`` with ``z`` the cone duals; with ``c_lambda = -d``:
``(d f_L) . z_eq = +1``, so velocities are ``+z_eq``.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from typing import Any

import numpy as np
import scipy.sparse as sp

from micro.backends.base import Outcome, Status, recheck
from micro.backends.interrupt import SolverStop, deferred_signals
from micro.lp import LimitLP

#: Clarabel settings of the static form (``clarabel-static``). With Clarabel's defaults
#: (1e-8 gap and feasibility) lambda came out 1e-6 (54-150 blocks) to 2e-4
#: (1,230 blocks) too low while Clarabel reported Solved: the error is the
#: dual (kinematic) infeasibility times the contact forces, which add up to
#: ~4e4 block weights on the 1,230-block wall. Tightening only the gap and
#: feasibility tolerances (1e-11) took 200+ iterations and stalled at ~2e-6;
#: lowering the static regularisation and tightening iterative refinement as
#: well reaches 1e-8 (Table 7 walls) and ~1e-6 (1,230 blocks) in ~40 iterations.
#: QDLDL is named: Clarabel's "auto" picks faer above ~2,700 blocks, slower on
#: these walls (same lambda to 1e-10; the times: docs/speed.md); below that size
#: "auto" is QDLDL, so nothing changes there.
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
#: What a solve with :data:`CLARABEL_TIGHT` that stopped short (see
#: :data:`RETRY_ON`) is retried with: Clarabel's default static
#: regularisation and 1e-9 tolerances. The certificate LPs of the iterated
#: non-associative scheme start from these settings (the tight ones stopped
#: short on every one of them on the Table 7 walls).
CLARABEL_RETRY: dict[str, Any] = {
    "static_regularization_constant": 1e-8,
    "tol_gap_abs": 1e-9,
    "tol_gap_rel": 1e-9,
    "tol_feas": 1e-9,
}
#: Native statuses after which a solve with the tight settings is retried
#: (seen when base sliding governs exactly, a very degenerate optimum).
RETRY_ON = ("AlmostSolved", "InsufficientProgress", "NumericalError")


def solve_interruptibly(solver: Any) -> Any:
    """``solver.solve()`` with Ctrl-C stopping Clarabel through its termination
    callback (checked once per iteration) and raised once it has returned
    (:mod:`micro.backends.interrupt`): without it a Ctrl-C waits for the
    solve to end (seconds on a large wall: docs/speed.md)."""
    stop = SolverStop()
    solver.set_termination_callback(lambda info: stop.requested)
    try:
        with deferred_signals(stop):
            return solver.solve()
    finally:
        solver.unset_termination_callback()


def clarabel_settings(opts: Mapping[str, Any]) -> Any:
    """Clarabel's default settings, quiet, with ``opts`` set.

    Raises:
        ValueError: an unknown Clarabel setting.
    """
    import clarabel

    s = clarabel.DefaultSettings()
    s.verbose = False
    for k, v in opts.items():
        if not hasattr(s, k):
            raise ValueError(f"unknown Clarabel setting {k!r}")
        setattr(s, k, v)
    return s


class ClarabelStaticBackend:
    """Clarabel's direct API (module docstring).

    Args:
        lp: the assembled LP (columns with a zero upper bound are left out).
        settings: Clarabel settings overriding :data:`CLARABEL_TIGHT`.
        tight: start from :data:`CLARABEL_TIGHT` (``True``) or from Clarabel's
            defaults (``False``).
        time_limit: seconds per solve.

    Raises:
        ValueError: an unknown Clarabel setting.
    """

    #: Clarabel status name -> shared status (anything else: ``solver_error``).
    STATUS_MAP = {
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

    def __init__(self, lp: LimitLP, *, settings: dict[str, Any] | None = None, tight: bool = True,
                 time_limit: float | None = None) -> None:
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
        opts = dict(CLARABEL_TIGHT) if tight else {}
        opts.update(settings or {})
        if time_limit is not None:
            opts["time_limit"] = float(time_limit)
        self.settings = clarabel_settings(opts)
        self.retry_settings = clarabel_settings({**opts, **CLARABEL_RETRY})

    def solve(self, direction: int) -> Outcome:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``).

        With the tight settings, a stop short of them (:data:`RETRY_ON`) is
        retried once with :data:`CLARABEL_RETRY`; ``info["fallback"]`` says
        so. A second failure is reported as it is.
        """
        t0 = time.perf_counter()
        sol = self._run(direction, self.settings)
        native = str(sol.status).split(".")[-1]
        iters = int(sol.iterations)
        extra: dict[str, Any] = {}
        if self.tight and native in RETRY_ON:
            sol = self._run(direction, self.retry_settings)
            extra["fallback"] = f"{native} with the tight settings; re-solved with {CLARABEL_RETRY}"
            native = str(sol.status).split(".")[-1]
            iters += int(sol.iterations)
        secs = time.perf_counter() - t0
        status = self.STATUS_MAP.get(native, Status.SOLVER_ERROR)
        extra.update({"r_prim": float(sol.r_prim), "r_dual": float(sol.r_dual), "solver_time": float(sol.solve_time)})
        if status is not Status.OPTIMAL:
            return Outcome(status, native, ipm_iterations=iters, seconds=secs, info=extra)
        x = np.zeros(self.lp.n_cols)
        x[self.active] = np.asarray(sol.x, dtype=float)
        z = np.asarray(sol.z, dtype=float)[: self.lp.n_eq]
        n, s_ = self.lp.forces(x)
        lam = float(x[self.lp.lam_col])
        out = Outcome(status, native, float(direction) * lam, n=n, s=s_, duals=z, ipm_iterations=iters,
                      seconds=secs, info=extra)
        return recheck(self.lp, direction, out)

    def _run(self, direction: int, settings: Any) -> Any:
        c = self.lp.cost(direction)[self.active]
        solver = self._cl.DefaultSolver(self.P, c, self.A, self.b, self.cones, settings)
        return solve_interruptibly(solver)
