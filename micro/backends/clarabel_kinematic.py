"""The associative LP in kinematic (dual) form, solved by Clarabel: the ``clarabel`` back end.

The static LP (:mod:`micro.lp`) maximises ``d * lambda`` over the cone
generators ``g >= 0`` with ``A_g g + lambda f_L = r`` (``r = -f_D``). Its dual
has the block velocities ``u`` (three per block) as variables::

    minimise   r . u                       (the work of the dead load, negated)
    subject to f_L . u = d                 (the live load does unit work)
               A_g^T u >= 0                (associative flow rule: every cone
                                            generator's relative velocity opens)

and the same optimum, ``lambda = r . u`` (LP duality). Clarabel solves it as
``min c.x  s.t.  A x + s = b, s in K`` with ``x = u``, ``c = r``, the first
row ``f_L`` in the zero cone and the rows ``-A_g^T`` in the non-negative
cone. Its KKT condition ``c + A^T z = 0`` reads ``A_g z_g + (-z_0) f_L = r``:
the cone duals ARE the static solution, generators ``g = z_g`` and the load
factor column ``-z_0``. Those forces, not the kinematic objective, are what
the back end returns and what the independent re-check
(:func:`micro.backends.base.recheck`) verifies; ``info["kinematic_load_factor"]`` is
``r . u``, the upper-bound side of the same optimum.

The duals meet equilibrium only to Clarabel's tolerance times the largest
force: on heavily loaded walls (Set 17, p = 8: generators up to 1.7e5 block
weights) that is beyond the re-check's absolute 1e-6. A solve whose forces
fail the re-check is therefore polished onto exact equilibrium
(:data:`POLISH`; :func:`micro.backends.polish.checked_outcome`: the smallest relative
correction of the generators and the load factor through one sparse
factorisation) and re-checked again; the polished load factor is a lower
bound. ``info`` then keeps the load factor read from the duals
(``unpolished_load_factor``), its residual (``unpolished_residual``), the
polish's corrections (``polish_steps``) and time (``polish_seconds``, also in
``seconds``). Forces that pass the re-check are returned as Clarabel gave them
(the polish would move their load factor by ~1e-9 for 2-6 % of the solve's
CPU time; ``docs/micro/associative.md``).

Why: Clarabel's KKT system is then ``n_eq + 2P`` square instead of
``2P + n_eq + 2P`` (the static form carries the ``g >= 0`` rows as well), and
the answer is more accurate (1e-8 instead of 1e-6 relative on 1,230 blocks;
``docs/micro/associative.md``).

Scaling: the normalisation row is written ``f_L . u = d * S`` with ``S`` the
total live load (sum of ``|f_L|``), so that the velocities are of order one
like the forces are of order the block weights; without it Clarabel stopped
``AlmostSolved`` on the 3,630-block wall. The velocities are divided by ``S``
again on the way out (live work 1, the shared convention).
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any

import numpy as np
import scipy.sparse as sp

from micro.backends.base import Outcome, Status
from micro.backends.clarabel import RETRY_ON, ClarabelStaticBackend, clarabel_settings, solve_interruptibly
from micro.backends.polish import checked_outcome
from micro.lp import LimitLP

#: Clarabel settings of the kinematic back end (``docs/micro/associative.md``).
#: Every one is set explicitly, so that a later Clarabel with other defaults
#: cannot silently pick a slower or looser path (``tests/micro/backends/test_clarabel_kinematic.py``):
#:
#: * ``direct_solve_method="qdldl"``: Clarabel's ``"auto"`` picks faer above
#:   ~2,700 blocks, slower on these walls (docs/speed.md);
#: * tolerances 1e-10: at 1e-9 lambda came out 1.7e-7 low on 1,230 blocks
#:   (1.5e-8 at 1e-10);
#: * iterative refinement at Clarabel's default tolerances (1e-13 relative,
#:   1e-12 absolute, 10 steps): the static form's 1e-15 / 50 steps made small
#:   frictionless walls stop ``AlmostSolved``;
#: * static regularisation 1e-13 (as the static form).
CLARABEL_KINEMATIC: dict[str, Any] = {
    "direct_solve_method": "qdldl",
    "tol_gap_abs": 1e-10,
    "tol_gap_rel": 1e-10,
    "tol_feas": 1e-10,
    "static_regularization_constant": 1e-13,
    "iterative_refinement_enable": True,
    "iterative_refinement_reltol": 1e-13,
    "iterative_refinement_abstol": 1e-12,
    "iterative_refinement_max_iter": 10,
    "equilibrate_enable": True,
    "presolve_enable": True,
    "max_iter": 400,
}
#: What a solve that stopped short (:data:`micro.backends.clarabel.RETRY_ON`)
#: is retried with: a degenerate optimum (base sliding governing exactly,
#: lambda = mu) stalled at residuals ~2e-10 after 8-9 iterations; these
#: settings solve it.
CLARABEL_KINEMATIC_RETRY: dict[str, Any] = {
    "static_regularization_constant": 1e-8,
    "tol_gap_abs": 1e-9,
    "tol_gap_rel": 1e-9,
    "tol_feas": 1e-9,
}


#: Polish the static forces of a solve that fails the re-check
#: (:func:`micro.backends.base.recheck`) onto exact equilibrium
#: (:func:`micro.backends.polish.polish_equilibrium`). It touches no solve
#: that passes, so it cannot make one fail.
POLISH = True


class ClarabelKinematicBackend:
    """Clarabel on the kinematic form of the associative LP (module docstring).

    Velocities are returned in the shared convention (live work ``+1``).

    Args:
        lp: the assembled LP (generator columns with a zero upper bound, ``g-``
            where ``mu = 0``, give no flow-rule row: a frictionless joint
            slides freely).
        settings: Clarabel settings overriding :data:`CLARABEL_KINEMATIC`.
        time_limit: seconds per solve.
        polish: polish forces that fail the re-check (:data:`POLISH`).

    Raises:
        ValueError: an unknown Clarabel setting.
    """

    #: Clarabel's statuses of the KINEMATIC problem mapped onto the static
    #: LP's: no admissible mechanism (kinematic infeasible) is an unbounded
    #: load factor; a mechanism the dead load drives without limit (kinematic
    #: unbounded) is a wall that cannot stand.
    STATUS_MAP = {
        **ClarabelStaticBackend.STATUS_MAP,
        "PrimalInfeasible": Status.UNBOUNDED,
        "DualInfeasible": Status.INFEASIBLE,
    }

    def __init__(self, lp: LimitLP, *, settings: dict[str, Any] | None = None, time_limit: float | None = None,
                 polish: bool = POLISH) -> None:
        import clarabel

        self._cl = clarabel
        self.lp = lp
        self.name = "clarabel"
        self.time_limit = time_limit
        self.polish = polish
        self.active = lp.active_generators()
        self.work_scale = float(np.sum(np.abs(lp.live)))
        self.A_g = lp.A[:, self.active]
        self.A = sp.vstack([sp.csr_matrix(lp.live[None, :]), -self.A_g.T.tocsr()], format="csc")
        self.cones = [clarabel.ZeroConeT(1), clarabel.NonnegativeConeT(self.active.size)]
        self.P = sp.csc_matrix((lp.n_eq, lp.n_eq))
        opts = {**CLARABEL_KINEMATIC, **(settings or {})}
        if time_limit is not None:
            opts["time_limit"] = float(time_limit)
        self.settings = clarabel_settings(opts)
        self.retry_settings = clarabel_settings({**opts, **CLARABEL_KINEMATIC_RETRY})

    def solver(self, direction: int, settings: Any = None) -> Any:
        """Clarabel's solver object for ``direction``, set up (equilibrated,
        KKT system ordered and allocated) but not run."""
        b = np.zeros(self.A.shape[0])
        b[0] = float(direction) * self.work_scale
        return self._cl.DefaultSolver(self.P, self.lp.rhs, self.A, b, self.cones, settings or self.settings)

    def solve(self, direction: int) -> Outcome:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``).

        A stop short of the tolerances (:data:`micro.backends.clarabel.RETRY_ON`)
        is retried once with :data:`CLARABEL_KINEMATIC_RETRY`, and a second one
        is solved in the static form; ``info["fallback"]`` says so (seen only
        on walls where base sliding governs exactly, lambda = mu: a degenerate
        optimum).
        """
        if self.work_scale == 0.0:  # f_L = 0: the normalisation row is empty, lambda unbounded
            return Outcome(Status.UNBOUNDED, "no live load", info={"form": "kinematic"})
        t0 = time.perf_counter()
        solver = self.solver(direction)
        sol = solve_interruptibly(solver)
        native = str(sol.status).split(".")[-1]
        iters = int(sol.iterations)
        extra: dict[str, Any] = {"form": "kinematic"}
        if native in RETRY_ON:
            solver = self.solver(direction, self.retry_settings)
            sol = solve_interruptibly(solver)
            extra["fallback"] = f"{native}; re-solved with {CLARABEL_KINEMATIC_RETRY}"
            native = str(sol.status).split(".")[-1]
            iters += int(sol.iterations)
            if native in RETRY_ON:
                return self._static(direction, native, iters, time.perf_counter() - t0)
        secs = time.perf_counter() - t0
        lin = solver.get_info().linsolver
        extra.update({"linear_solver": str(lin.name), "linear_solver_threads": int(lin.threads),
                      "r_prim": float(sol.r_prim), "r_dual": float(sol.r_dual)})
        status = self.STATUS_MAP.get(native, Status.SOLVER_ERROR)
        if status is not Status.OPTIMAL:
            return Outcome(status, native, ipm_iterations=iters, seconds=secs, info=extra)
        u = np.asarray(sol.x, dtype=float) / self.work_scale
        z = np.asarray(sol.z, dtype=float)
        extra["kinematic_load_factor"] = float(self.lp.rhs @ u)
        g, lam_column = z[1:], -float(z[0])
        raw = Outcome(status, native, duals=u, ipm_iterations=iters, seconds=secs, info=extra)
        return checked_outcome(self.lp, self.A_g, self.active, direction, g, lam_column, raw, polish=self.polish)

    def _static(self, direction: int, native: str, iterations: int, seconds: float) -> Outcome:
        """The static form's answer (:class:`~micro.backends.clarabel.ClarabelStaticBackend`,
        with its own retry) after both kinematic attempts stopped short; this
        attempt's iterations and time are added."""
        out = ClarabelStaticBackend(self.lp, time_limit=self.time_limit).solve(direction)
        info = {**out.info, "form": "static", "fallback": f"{native} twice in kinematic form; solved in static form"}
        return dataclasses.replace(out, ipm_iterations=out.ipm_iterations + iterations,
                                   seconds=out.seconds + seconds, info=info)
