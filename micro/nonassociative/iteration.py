"""The iterated LP for one load direction: the start, the loop, the finish.

Iterate 0 is the associative LP (:meth:`LPSequence._start`); its normal forces
give the first ``nbar``. Iterate ``k >= 1`` rebuilds every point's yield
condition from ``nbar = beta n_(k-1) + (1 - beta) n_(k-2)`` (the proximal
selection: ``nbar`` moved by ``beta`` towards its projection,
:mod:`micro.nonassociative.proximal`) in the persistent
:class:`~micro.nonassociative.model.IterationModel` and solves it: the first
by interior point + crossover + dual simplex, the later ones by a warm dual
simplex from the previous basis, or cold again while warm runs take many
simplex iterations: when is the warm/cold policy's
(:class:`~micro.nonassociative.warm_cold.WarmColdPolicy`), which this loop
asks and tells of every run; the loop's own state (the iterates, the last
good state, the work spent) stays here.
Every decision counts work (iterations, LPs), never seconds: the path and its
numbers are the same on a loaded or slower machine; only the optional user
stops ``max_seconds`` and ``time_limit`` read the clock, and a sequence they
stop has status ``time_limit``. A failed run is
recovered (:meth:`LPSequence._recover`); each iterate is then tested for the
stops of :mod:`micro.nonassociative.selections`. The final iterate is
checked (:mod:`micro.nonassociative.final_checks`). How an iterate goes on (the
next ``nbar`` and slope, whether it may go cold, when the certificate is due,
which no-progress test applies) is its selection's
(:mod:`micro.nonassociative.selections`: vertex, proximal, continuation); which sequences run on a direction is
:mod:`micro.nonassociative.pipeline`'s.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from numpy.typing import NDArray

from micro.backends.base import Outcome, Status
from micro.backends.roles import ANY_FAILURE, PersistentLP, solve_interior
from micro.limit_result import DIR_NAME, DirectionResult
from micro.lp import LimitLP
from micro.nonassociative import final_checks
from micro.nonassociative.certificate import Certificate
from micro.nonassociative.config import EQUILIBRIUM_RESIDUAL, TINY, LPProgress, Resolved
from micro.nonassociative.model import IterationModel, restart
from micro.nonassociative.nonassociative_result import (
    CONVERGED,
    CONVERGED_STOPS,
    CYCLING,
    MAX_ITERATIONS,
    SOLVER_FAILURE,
    TIME_LIMIT,
    Band,
    IterationRecord,
    SequenceDiagnostics,
)
from micro.nonassociative.selections import exact_stop, selection_for, window_band
from micro.nonassociative.warm_cold import COLD, WARM, WarmColdPolicy

FloatArray = NDArray[np.float64]
NAN = math.nan

#: The exact stop's ``max(|s| - mu n, 0) / max n`` accepted as "Coulomb holds".
COULOMB_TOL = 1e-6
#: Relative warm/cold difference of the final iterate beyond which the run is
#: a ``solver_failure`` (the cold re-solve always runs).
COLD_TOL = 1e-6


class LPSequence:
    """The iterated LP for one load direction (module docstring).

    Args:
        lp: the wall's LP.
        direction: ``+1`` or ``-1``.
        resolved: what the stages read (the options, their tuning, this sequence's selection and cap).
        start: scaled normal forces ``(P,)`` to start ``nbar`` from instead of
            the associative LP's (which still gives iterate 0 and the
            associative load factor); ``None``: the associative LP's.
        iterate0: the associative LP's ``(outcome, algorithm, x)`` from
            another sequence on the same LP and direction with the same
            ``tuning.start`` (its :attr:`iterate0`), reused instead of
            solved again; ``None``: solve it.
    """

    def __init__(self, lp: LimitLP, direction: int, resolved: Resolved,
                 start: FloatArray | None = None,
                 iterate0: tuple[Outcome, str, FloatArray | None] | None = None) -> None:
        self.lp, self.d, self.resolved, self.start = lp, direction, resolved, start
        self.iterate0 = iterate0
        self.certificate = Certificate(lp, direction, resolved.tuning.scheme)
        self.history: list[IterationRecord] = []
        self.fallbacks = 0
        self.c0 = 0.0
        self.mechanism_band: Band | None = None
        # the loop's state: the iterates' lambda and steps, the last good state, the work spent
        self.lams: list[float] = []
        self.dns: list[float] = []
        self.final: tuple[FloatArray, FloatArray, FloatArray, float] | None = None  # (v, n, s, lambda)
        self.pivots = 0
        self.last_try = -(10**9)
        self.model: IterationModel | None = None
        # how an iterate goes on (vertex, proximal, continuation), and whether it is solved warm or cold
        self.rule = selection_for(resolved, lp, direction)
        self.policy = WarmColdPolicy(lp.n_eq, self.rule)
        fused = lp.n_eq != 3 * lp.wall.n_blocks  # the LP of a fused wall (fewer bodies than blocks)
        self.stage = ("fused " if fused else "") + self.rule.name

    # ------------------------------------------------------------ iterate 0
    def _start(self) -> tuple[Outcome, str, FloatArray | None]:
        """The associative LP (iterate 0): ``"interior"`` by the interior-point role (Clarabel, tight
        tolerances; faster than HiGHS IPM: the research page on the re-cut of the non-associative package,
        ``docs/research/``),
        HiGHS IPM (:func:`~micro.backends.roles.solve_interior`, the certificate's fallback, with the back
        end's re-check) if Clarabel fails other than at the user's time limit; ``"vertex"`` by HiGHS IPM +
        crossover + dual simplex (a basic optimal solution).

        Returns:
            ``(outcome, algorithm, x)`` with ``x`` in the iteration model's
            layout ``[n, s, d * lambda]`` (``None`` unless optimal).
        """
        lp, P = self.lp, self.lp.n_points
        if self.resolved.tuning.start == "interior":
            limit = self.resolved.options.time_limit
            # the user's time limit is no failure to retry: it ends the run (see run)
            out, algo = solve_interior(lp, self.d, retry_on=ANY_FAILURE, time_limit=limit)
            if out.ok and out.n is not None and out.s is not None:
                return out, algo, np.concatenate([out.n, out.s, [out.load_factor * self.d]])
            return out, algo, None
        out, algo = restart(self._associative_model()), COLD
        if out.x is None:
            return out, algo, None
        n, s = lp.forces(out.x[: 2 * P])
        return out, algo, np.concatenate([n, s, [out.x[lp.lam_col]]])

    def _associative_model(self) -> PersistentLP:
        """The associative LP of this direction in generator form, for HiGHS' interior point."""
        m = PersistentLP.of(self.lp, +1, algorithm="ipm")
        m.set_cost(self.lp.lam_col, -float(self.d))
        return m

    # ----------------------------------------------------------------- run
    def run(self) -> DirectionResult:
        """Run the sequence to its stop and check the final state."""
        t_start = time.perf_counter()
        if self.iterate0 is None:
            self.iterate0 = self._start()
        out, algo0, x = self.iterate0
        if x is None:
            self._record(0, NAN, NAN, NAN, NAN, 0.0, out, algo0)
            if out.status is Status.TIME_LIMIT:
                return self._fail("time_limit", f"the associative LP hit the time limit of "
                                  f"{self.resolved.options.time_limit:g} s", t_start, NAN, None, TIME_LIMIT)
            return self._fail("associative_failed", f"the associative LP failed ({out.native_status})",
                              t_start, NAN)
        lam_assoc = float(x[2 * self.lp.n_points]) * self.d
        n0, s0 = x[: self.lp.n_points], x[self.lp.n_points : 2 * self.lp.n_points]
        n0 = assoc_n0 = np.maximum(n0, 0.0)
        self._record(0, lam_assoc, NAN, NAN, final_checks.coulomb_residual(self.lp, n0, s0), 0.0, out, algo0)
        if self.start is not None:
            n0 = np.maximum(self.start, 0.0)
        if lam_assoc < 0:
            return self._fail("associative_failed", "equilibrium needs a live load in the opposite direction",
                              t_start, lam_assoc)
        t_b = time.perf_counter()
        self.c0 = self.rule.cohesion(assoc_n0, n0)  # of the friction rows, relative to the force level
        alpha = self.rule.first_alpha()
        model = IterationModel(self.lp, self.d, "b" if self.rule.rows else "a", alpha)
        self.model = model
        model.set_capacity(n0, alpha, alpha, self.c0)
        stop, band, failed = self._loop(model, n0, lam_assoc, alpha, time.perf_counter() - t_b, t_start)
        if failed is not None and failed.status is Status.TIME_LIMIT:
            return self._fail("time_limit", f"LP {len(self.history) - 1} hit the time limit of "
                              f"{self.resolved.options.time_limit:g} s", t_start, lam_assoc, band, TIME_LIMIT)
        if failed is not None or self.final is None:
            status = failed.native_status if failed is not None else ""
            return self._fail("lp_failed", f"LP {len(self.history) - 1} failed warm and cold ({status})",
                              t_start, lam_assoc, band)
        return self._finish(model, stop, band, lam_assoc, t_start)

    def _loop(self, model: IterationModel, n0: FloatArray, lam_assoc: float, alpha: float, t_build: float,
              t_start: float) -> tuple[str, Band | None, Outcome | None]:
        """Iterates ``1 .. max_iterations``.

        Returns:
            ``(stop reason, band, the failed outcome or None)``.
        """
        r = self.resolved
        n_prev, n_prev2, lam_prev = n0, n0, lam_assoc
        for k in range(1, r.max_lps + 1):
            t_it = time.perf_counter()
            new_alpha = alpha
            if k > 1:
                nbar = self.rule.next_nbar(model.nbar, lam_prev, n_prev, n_prev2)
                new_alpha = self.rule.next_alpha(alpha)
                model.set_capacity(nbar, new_alpha, alpha, self.c0)
            alpha = new_alpha
            t_upd = time.perf_counter() - t_it + (t_build if k == 1 else 0.0)
            out, algo = self._solve(model, k, n_prev, alpha)
            out = out.plus_seconds(t_upd)
            if out.x is None or out.duals is None:
                self._record(k, NAN, NAN, NAN, NAN, alpha, out, algo)
                return "lp_failed", None, out
            self._account(model, k, out, algo)
            lam = model.load_factor(out.x)
            n, s = model.forces(out.x)
            stop = self._step(k, lam, lam_prev, n, n_prev, s, out, algo, alpha)
            n_prev2, n_prev, lam_prev = n_prev, n, lam
            if stop is not None:
                return stop
            if r.tuning.max_simplex_iterations is not None and self.pivots >= r.tuning.max_simplex_iterations:
                return "work_budget", window_band(self.lams), None
            if r.options.max_seconds is not None and time.perf_counter() - t_start > r.options.max_seconds:
                return "time_budget", window_band(self.lams), None
        return "max_iterations", window_band(self.lams), None

    # ------------------------------------------------- solving an iterate
    def _solve(self, model: IterationModel, k: int, n_prev: FloatArray, alpha: float) -> tuple[Outcome, str]:
        """Solve iterate ``k``, warm or cold as :attr:`policy` says
        (:class:`~micro.nonassociative.warm_cold.WarmColdPolicy`): cold by
        interior point + crossover + dual-simplex clean-up, warm by a dual
        simplex from the last basis, limited to the policy's ``warm_limit``
        simplex iterations. A run stopped by the user's ``time_limit`` is
        returned as it is (the sequence ends); another failure is recovered."""
        user = self.resolved.options.time_limit
        if self.policy.cold(k):
            model.model.limit_next_run(user)
            out, algo = restart(model.model), COLD
            model.model.limit_next_run(user)  # re-armed for a recovery run after it
        else:
            out, algo = model.warm(user, self.policy.warm_limit), WARM
        if out.ok or out.status is Status.TIME_LIMIT:
            return out, algo
        if algo == WARM and out.status is Status.ITERATION_LIMIT:
            self.policy.slow_warm(int(out.simplex_iterations))  # a warm run stopped at its limit was slow
        return self._recover(model, k, out, n_prev, alpha)

    def _recover(self, model: IterationModel, k: int, failed: Outcome, n_prev: FloatArray,
                 alpha: float) -> tuple[Outcome, str]:
        """A failed iterate ``k``. For ``k > 1``, scheme (b) caps every point at
        ``n <= nbar (1 + alpha) / alpha + c0 / (alpha mu)``: with ``nbar ~ 0``
        the support can only shrink until no equilibrium is left (HiGHS says
        "Infeasible", or "Unknown" when it is nearly so); one step of scheme
        (a) from the last forces replaces the iterate (bounds only), then (b)
        goes on. Otherwise an infeasible relaxed iterate is rebuilt from the
        last forces alone (no relaxation). What still fails is restarted cold
        (HiGHS "Unknown" on near-degenerate rows)."""
        out, algo = failed, ""
        user, tuning = self.resolved.options.time_limit, self.resolved.tuning
        if k > 1 and tuning.scheme == "b":
            out, algo = model.fallback_a_step(n_prev, user, self.policy.warm_limit), "fallback-a"
            self.fallbacks += 1
        elif k > 1 and failed.status is Status.INFEASIBLE and tuning.beta < 1.0:
            model.set_capacity(n_prev, alpha, alpha, self.c0)
            out, algo = model.warm(user, self.policy.warm_limit), "simplex-warm-unrelaxed"
        if not out.ok:
            out, algo = restart(model.model), "ipm-restart"
        # the failed run's work counts (the work budget, the history)
        return dataclasses.replace(
            out, seconds=out.seconds + failed.seconds,
            simplex_iterations=out.simplex_iterations + failed.simplex_iterations,
            ipm_iterations=out.ipm_iterations + failed.ipm_iterations), algo

    def _account(self, model: IterationModel, k: int, out: Outcome, algo: str) -> None:
        """Book a good iterate's work for the work budget and the warm/cold policy."""
        self.pivots += int(out.simplex_iterations)
        self.policy.account(k, int(out.simplex_iterations), warm=algo == WARM, cold=algo == COLD)
        model.keep_basis()

    # ------------------------------------------------------ one iterate
    def _step(self, k: int, lam: float, lam_prev: float, n: FloatArray, n_prev: FloatArray, s: FloatArray,
              out: Outcome, algo: str, alpha: float) -> tuple[str, Band | None, None] | None:
        """Record a good iterate and test the stops (the exact stop, the
        certificate once ``lambda`` has settled, cycles).

        Returns:
            ``(stop reason, band, None)`` or ``None`` to go on.
        """
        assert out.duals is not None
        nscale = max(float(np.max(n, initial=0.0)), TINY)
        dlam = abs(lam - lam_prev) / max(abs(lam), TINY)
        dn = float(np.max(np.abs(n - n_prev), initial=0.0)) / nscale
        coul = final_checks.coulomb_residual(self.lp, n, s)
        self._record(k, lam, dlam, dn, coul, alpha, out, algo)
        self.lams.append(lam)
        self.dns.append(dn)
        v = out.duals[: self.lp.n_eq]
        self.final = (v, n, s, lam)
        alpha_done = self.rule.alpha_done(alpha)
        coul_tol = COULOMB_TOL + (self.c0 / nscale if self.rule.rows else 0.0)
        exact = exact_stop(k, alpha_done, dlam, dn, coul, coul_tol)
        if exact is not None:
            return exact, None, None
        due = self.rule.certificate_due(self.lams, k, self.last_try)
        certify = self.resolved.tuning.certify and alpha_done and algo != "fallback-a" and due
        if certify and self._try_certificate(k, v, lam):
            return "certified", None, None
        stop = self.rule.no_progress(self.lams, self.dns, alpha_done)
        return None if stop is None else (stop[0], stop[1], None)

    def _try_certificate(self, k: int, v: FloatArray, lam: float) -> bool:
        """Try the certificate on iterate ``k``: is its mechanism an exact
        collapse state with other forces than the LP's vertex?"""
        cert = self.certificate.certify(v, lam, time_limit=self.resolved.options.user_limit)
        self.last_try = k
        rec = self.history[-1]
        coul = final_checks.coulomb_residual(self.lp, *cert.forces) if cert.forces is not None else NAN
        self.history[-1] = dataclasses.replace(
            rec, certificate="certified" if cert.forces is not None else "not found",
            certificate_seconds=float(cert.seconds), certificate_iterations=int(cert.iterations),
            coulomb_residual=coul if math.isfinite(coul) else rec.coulomb_residual,
        )
        if cert.forces is None:
            return False
        self.final = (v, cert.forces[0], cert.forces[1], lam)
        self.mechanism_band = cert.band
        return True

    def _record(self, k: int, lam: float, dlam: float, dn: float, coul: float, alpha: float, out: Outcome,
                algo: str) -> None:
        self.history.append(IterationRecord(
            iteration=k, load_factor=lam, lambda_change=dlam, max_dn=dn, coulomb_residual=coul, alpha=alpha,
            simplex_iterations=int(out.simplex_iterations), ipm_iterations=int(out.ipm_iterations),
            seconds=float(out.seconds), algorithm=algo, status=out.status.value, proximal_step=self.rule.take_step(),
        ))
        self.resolved.tell(LPProgress(DIR_NAME[self.d], self.stage, k, lam, dn, algo, float(out.seconds)))

    # ------------------------------------------------------------ finish
    def _fail(self, reason: str, msg: str, t_start: float, lam_assoc: float,
              band: Band | None = None, status: str = SOLVER_FAILURE) -> DirectionResult:
        last = [r.load_factor for r in self.history[1:] if math.isfinite(r.load_factor)]
        seq = SequenceDiagnostics(
            stop_reason=reason, last_load_factor=last[-1] if last else NAN, lambda_band=band, mechanism_band=None,
            associative_load_factor=lam_assoc, history=tuple(self.history), fallback_steps=self.fallbacks,
            selection=self.resolved.selection,
        )
        return DirectionResult(direction=DIR_NAME[self.d], status=status, load_factor=NAN,
                               iterations=max(len(self.history) - 1, 0), seconds=time.perf_counter() - t_start,
                               message=msg, sequence=seq)

    def _finish(self, model: IterationModel, stop: str, band: Band | None, lam_assoc: float,
                t_start: float) -> DirectionResult:
        """The final-state checks, the cold re-solve, the mechanism band and the message."""
        assert self.final is not None
        r, lp = self.resolved, self.lp
        v, n, s, lam = self.final
        status = (CONVERGED if stop in CONVERGED_STOPS else TIME_LIMIT if stop == "time_budget"
                  else MAX_ITERATIONS if stop in ("max_iterations", "work_budget") else CYCLING)
        state = final_checks.final_state(lp, self.d, v, n, s, lam)
        check_cold = final_checks.cold_check_due(stop)
        cold = final_checks.cold_check(model, lam, COLD_TOL) if check_cold else final_checks.ColdCheck(NAN, NAN, "", "")
        msg = cold_note = ""
        if check_cold and (not math.isfinite(cold.rel_diff) or cold.rel_diff > COLD_TOL):
            cold_note = (f"the final iterate re-solved cold gives lambda = {cold.load_factor:.9g} against "
                         f"{lam:.9g} warm (HiGHS hot start; status {cold.native_status})")
            if status == CONVERGED:
                status, stop, msg, cold_note = SOLVER_FAILURE, "cold_check_failed", cold_note, ""
        if status == CONVERGED and state.equilibrium > EQUILIBRIUM_RESIDUAL:
            status, stop = SOLVER_FAILURE, "equilibrium_residual"
            msg = f"equilibrium residual {state.equilibrium:.2e} block weights at the final iterate"
        if status == CONVERGED and r.tuning.mechanism_band and self.mechanism_band is None and r.tuning.scheme == "a":
            self.mechanism_band = self.certificate.certify(v, lam, time_limit=r.options.user_limit).band
        msg = msg or self._message(status, stop, band)
        if cold_note:
            msg += f"; also, {cold_note}"
        seq = SequenceDiagnostics(  # a failed sequence's band is no band of exact collapse states
            stop_reason=stop, last_load_factor=lam, lambda_band=None if status == CONVERGED else band,
            mechanism_band=self.mechanism_band if status == CONVERGED else None,
            associative_load_factor=lam_assoc, history=tuple(self.history),
            cold_load_factor=cold.load_factor, warm_cold_rel_diff=cold.rel_diff, cold_algorithm=cold.algorithm,
            coulomb_residual=state.coulomb, dilatancy_residual=state.dilatancy,
            equilibrium_residual=state.equilibrium, sliding_points=state.sliding_points,
            fallback_steps=self.fallbacks, selection=r.selection,
        )
        fs = lp.force_scale
        return DirectionResult(
            direction=DIR_NAME[self.d], status=status, load_factor=lam if status == CONVERGED else NAN,
            iterations=len(self.history) - 1, seconds=time.perf_counter() - t_start, normal=n * fs, shear=s * fs,
            mechanism=state.mechanism, message=msg, sequence=seq,
        )

    def _message(self, status: str, stop: str, band: Band | None) -> str:
        """Why a sequence did not converge (``""`` when it did)."""
        if status == CYCLING:
            return f"the sequence is {stop} (lambda in [{band[0]:.6g}, {band[1]:.6g}])" if band else stop
        if status in (MAX_ITERATIONS, TIME_LIMIT):
            r, lps = self.resolved, len(self.history) - 1
            msg = {"max_iterations": f"no convergence in {r.max_lps} iterations",
                   "work_budget": f"work budget of {r.tuning.max_simplex_iterations} simplex iterations spent after "
                                  f"{lps} LPs",
                   }.get(stop, f"time budget of {r.options.max_seconds} s spent after {lps} LPs")
            return msg + (f" (last window lambda in [{band[0]:.6g}, {band[1]:.6g}])" if band else "")
        return stop if status != CONVERGED else ""
