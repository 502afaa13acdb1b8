"""The reference formulation written with cvxpy expressions (one-shot back end).

cvxpy is an optional extra (``pip install 'xcheck-masonry[cvxpy]'``): this
module imports it when a back end is made, and says so in one line when it
is missing.

::

    maximise   d * lam
    subject to B_n @ n + B_s @ s + lam * f_L == -f_D    (equilibrium)
               s <= mu * n,  -s <= mu * n,  n >= 0       (Coulomb)

With Clarabel and the tight settings, a solve that stops short
(``optimal_inaccurate``) is retried once with
:data:`~micro.backends.clarabel.CLARABEL_RETRY`, as the direct Clarabel back
end does. Where sliding governs exactly (``lambda = f``) several mechanisms
tie: in a wall one block long every bed joint spans the wall and sliding on
any of them gives ``lambda = f``. The optimal velocities are then not unique,
the KKT systems turn singular near the optimum, and the tight static
regularisation (1e-13) cannot carry Clarabel to 1e-10: it stops
``AlmostSolved`` (6 iterations on the quick report's 3-row wall, with this
back end and with the direct one alike). Giving the bed joints a higher
friction than the base (one mechanism) lets the tight settings solve the same
wall in 8 iterations. On 264 walls of 3-12 rows (both bond phases and
head-joint frictions) the tight settings stopped short on 33 of 312 solves,
32 of them with ``lambda = f``; the retry solved all 33, within 1e-6 of the
dual simplex.

The direction ``d`` is a cvxpy Parameter, so the problem is compiled once
(DPP) and re-solved for the other direction.

Clarabel is called through cvxpy's own interface with one change (:func:`_interruptible_clarabel`): the
solver object cvxpy builds solves through
:func:`~micro.backends.clarabel.solve_interruptibly`, so a Ctrl-C stops it within an
iteration, as it stops the direct back ends; through cvxpy's ``CLARABEL`` it
would wait for the solve to end (docs/speed.md).

cvxpy dual convention (pinned by ``tests/micro/backends``): for this
``Maximize`` problem, the dual of the equality ``B x + lam f_L == -f_D``
satisfies ``(d f_L) . y = +1``, so velocities are ``+y``.
"""

from __future__ import annotations

import time
import warnings
from typing import Any

import numpy as np

from micro.backends.base import Outcome, Status, recheck
from micro.backends.clarabel import CLARABEL_RETRY, CLARABEL_TIGHT, solve_interruptibly
from micro.lp import LimitLP

#: The one line said when cvxpy is not installed (it is the optional extra ``cvxpy``).
MISSING = "the cvxpy back end needs cvxpy: pip install 'xcheck-masonry[cvxpy]'"


class CvxpyBackend:
    """The cvxpy formulation (module docstring).

    Args:
        lp: the assembled LP.
        solver: ``"CLARABEL"`` or ``"HIGHS"``.
        tight: use :data:`~micro.backends.clarabel.CLARABEL_TIGHT` with
            Clarabel (``False``: cvxpy's defaults, the "plain" baseline).
        solver_options: extra keyword arguments for ``Problem.solve``.

    Raises:
        ValueError: an unknown solver.
    """

    #: cvxpy status -> shared status (anything else: ``solver_error``).
    STATUS_MAP = {
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

    def __init__(self, lp: LimitLP, *, solver: str = "CLARABEL", tight: bool = True,
                 solver_options: dict[str, Any] | None = None) -> None:
        try:
            import cvxpy as cp
        except ImportError:  # an optional extra since the package stopped depending on cvxpy
            raise ModuleNotFoundError(MISSING) from None

        self._cp = cp
        self.lp = lp
        solver = solver.upper()
        if solver not in ("CLARABEL", "HIGHS"):
            raise ValueError(f"cvxpy solver must be CLARABEL or HIGHS, got {solver!r}")
        self.solver = solver
        self._solver_arg: Any = _interruptible_clarabel() if solver == "CLARABEL" else solver
        # the registry's names: cvxpy (Clarabel, tight), cvxpy-clarabel-default, cvxpy-highs
        self.name = "cvxpy-highs" if solver == "HIGHS" else "cvxpy" if tight else "cvxpy-clarabel-default"
        Bn, Bs = lp.equilibrium_matrix()
        self.n = cp.Variable(lp.n_points, nonneg=True, name="n")
        self.s = cp.Variable(lp.n_points, name="s")
        self.lam = cp.Variable(name="lam")
        self.d = cp.Parameter(value=1.0, name="direction")
        self.equilibrium = Bn @ self.n + Bs @ self.s + self.lam * lp.live == lp.rhs
        friction = [self.s - cp.multiply(lp.mu, self.n) <= 0, -self.s - cp.multiply(lp.mu, self.n) <= 0]
        self.problem = cp.Problem(cp.Maximize(self.d * self.lam), [self.equilibrium, *friction])
        opts: dict[str, Any] = {}
        if solver == "CLARABEL" and tight:
            opts.update(CLARABEL_TIGHT)
        opts.update(solver_options or {})
        self.options = opts
        self.retry = {**opts, **CLARABEL_RETRY} if solver == "CLARABEL" and tight else None

    def solve(self, direction: int) -> Outcome:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``).

        A Clarabel solve with the tight settings that stops short
        (``optimal_inaccurate``) is retried once with
        :data:`~micro.backends.clarabel.CLARABEL_RETRY`; ``info["fallback"]`` says so.
        """
        self.d.value = float(direction)
        t0 = time.perf_counter()
        native, iters = self._run(self.options)
        extra: dict[str, Any] = {}
        if self.retry is not None and native == "optimal_inaccurate":
            extra["fallback"] = f"{native} with the tight settings; re-solved with {CLARABEL_RETRY}"
            native, more = self._run(self.retry)
            iters += more
        secs = time.perf_counter() - t0
        status = self.STATUS_MAP.get(native, Status.SOLVER_ERROR)
        # the iterations as cvxpy reports them: interior point (Clarabel) or simplex (HiGHS)
        ipm, simplex = (iters, 0) if self.solver == "CLARABEL" else (0, iters)
        stats = self.problem.solver_stats
        extra["solve_time_solver"] = float(stats.solve_time or 0.0) if stats is not None else float("nan")
        if status is not Status.OPTIMAL:
            return Outcome(status, native, simplex_iterations=simplex, ipm_iterations=ipm, seconds=secs, info=extra)
        lam = float(np.asarray(self.lam.value))
        out = Outcome(status, native, float(direction) * lam, n=np.asarray(self.n.value, dtype=float),
                      s=np.asarray(self.s.value, dtype=float),
                      duals=np.asarray(self.equilibrium.dual_value, dtype=float), simplex_iterations=simplex,
                      ipm_iterations=ipm, seconds=secs, info=extra)
        return recheck(self.lp, direction, out)

    def _run(self, options: dict[str, Any]) -> tuple[str, int]:
        """One solve: cvxpy's status (``solver_error`` when the solver raised) and the iterations."""
        try:
            with warnings.catch_warnings():
                # cvxpy warns "Solution may be inaccurate"; the status says so
                warnings.filterwarnings("ignore", message="Solution may be inaccurate")
                self.problem.solve(solver=self._solver_arg, **options)
        except self._cp.error.SolverError as exc:
            return f"solver_error: {exc}", 0
        stats = self.problem.solver_stats
        return str(self.problem.status), int(stats.num_iters or 0) if stats is not None else 0


def _interruptible_clarabel() -> Any:
    """cvxpy's Clarabel interface whose solve stops on Ctrl-C (module docstring): ``solve_via_data`` as
    cvxpy's (the same data, cones and settings; no warm start, which this back end does not ask for), the
    solver solved by :func:`~micro.backends.clarabel.solve_interruptibly`. cvxpy takes a solver instance
    under a name of its own."""
    import clarabel
    import cvxpy.settings as cs
    import scipy.sparse as sp
    from cvxpy.reductions.solvers.conic_solvers.clarabel_conif import CLARABEL, dims_to_solver_cones
    from cvxpy.reductions.solvers.conic_solvers.conic_solver import ConicSolver

    class InterruptibleClarabel(CLARABEL):
        def name(self) -> str:
            return "CLARABEL (interruptible)"

        def solve_via_data(self, data: dict[str, Any], warm_start: bool, verbose: bool,
                           solver_opts: dict[str, Any], solver_cache: Any = None) -> Any:
            q = data[cs.C]
            p = data[cs.P] if cs.P in data else sp.csc_array((q.size, q.size))
            solver = clarabel.DefaultSolver(sp.triu(p).tocsc(), q, data[cs.A], data[cs.B],
                                            dims_to_solver_cones(data[ConicSolver.DIMS]),
                                            self.parse_solver_opts(verbose, solver_opts))
            return solve_interruptibly(solver)

    return InterruptibleClarabel()
