"""The suite's own interior point on the normal equations: the ``normal-ipm`` back end.

The static LP (:mod:`micro.lp`) is a standard-form LP with one free column::

    minimise  -d lambda   subject to   A_g g + lambda f_L = r,   g >= 0

(``A_g`` the generator columns, ``r = -f_D``, ``d = +1`` or ``-1``) and its dual
has the block velocities: ``max r . y`` with ``A_g^T y + z = 0``, ``z >= 0``,
``f_L . y = -d`` (``u = -y`` is the mechanism, ``A_g^T u = z >= 0`` its
associative flow rule). Mehrotra's predictor-corrector solves both. Eliminating
``dg`` and ``dz`` from each Newton system leaves::

    M dy + f_L dlambda = h,   f_L . dy = r_f,   M = A_g diag(g / z) A_g^T,

``M`` of order ``3 n_blocks``, positive definite (a wall has no mechanism that
opens no generator). The free column never enters ``M`` (it would be a dense
row and column: the live load acts on every block): with ``w = M^{-1} f_L``,
``dlambda = (f_L . M^{-1} h - r_f) / (f_L . w)`` and ``dy = M^{-1} h - dlambda w``.
Each iteration is one numeric Cholesky factorisation of ``M``
(:class:`~micro.backends.normal_matrix.NormalMatrix`, CHOLMOD) and three solves.

Why: Clarabel (the ``clarabel`` back end) factorises a quasi-definite KKT
system with a row per generator as well (~32,000 rows on the 1,230-block
wall against ``M``'s 3,690), by QDLDL, which has no supernodes: ``normal-ipm``
is faster on 1,230-7,575 blocks, as accurate (``docs/micro/associative.md``;
the ratios: docs/speed.md).

The answer's forces are the primal iterate, checked and if need be polished
exactly as the kinematic back end's (:func:`micro.backends.polish.checked_outcome`);
the velocities ``u = -y``, divided so the live load does unit work, are the
mechanism. A run that does not reach the tolerances (an infeasible or
unbounded LP, a factorisation that fails with its shift raised 10^4 times, the
iteration limit) or whose forces fail the re-check even polished is not
guessed at: the wall is solved again by the ``clarabel`` back end, whose
statuses tell infeasible from unbounded, and ``info["fallback"]`` says why.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from micro.backends.base import FloatArray, Outcome, Status
from micro.backends.clarabel_kinematic import ClarabelKinematicBackend
from micro.backends.normal_matrix import (
    InteriorPointSettings,
    InteriorPointStop,
    NormalMatrix,
    NotPositiveDefinite,
    one_blas_thread,
)
from micro.backends.polish import checked_outcome
from micro.lp import LimitLP


@dataclass(frozen=True)
class NormalIpmSettings(InteriorPointSettings):
    """Tolerances and limits of the normal-equations interior point (the fields of
    :class:`~micro.backends.normal_matrix.InteriorPointSettings`: the gap
    ``|p - q| / (1 + |p|)``, the equilibrium residual relative to ``1 + max |r|``,
    the dual one to ``1 + max z``).

    Attributes:
        correctors: Gondzio's centrality correctors at most per iteration
            (each one solve with the factorisation of the iteration).
        projections: corrections of the converged primal onto equilibrium at
            most (:meth:`NormalIpm.run`).
        divergence: iterates larger than this (block weights or load factor)
            mean an infeasible or unbounded LP.
    """

    NUMBERS = (*InteriorPointSettings.NUMBERS, "divergence")
    INTEGERS = (*InteriorPointSettings.INTEGERS, ("correctors", 0), ("projections", 0))

    gap_tol: float = 1e-8
    primal_tol: float = 1e-7
    refine_steps: int = 1
    refine_tol: float = 1e-10
    correctors: int = 2
    projections: int = 2
    divergence: float = 1e12


#: The settings of the ``normal-ipm`` back end (why: ``docs/micro/associative.md``).
NORMAL_IPM = NormalIpmSettings()


@dataclass(frozen=True, eq=False)
class IpmResult(InteriorPointStop):
    """Where the interior point stopped (the fields of
    :class:`~micro.backends.normal_matrix.InteriorPointStop`, and the answer).

    Attributes:
        g: the generators; ``lam``: the load-factor column; ``y``: the row duals.
        factorizations, refinements: of ``M``.
    """

    g: FloatArray
    lam: float
    y: FloatArray
    factorizations: int
    refinements: int


def _max_step(v: FloatArray, dv: FloatArray) -> float:
    """The largest ``a <= 1`` with ``v + a dv >= 0``."""
    neg = dv < 0.0
    if not neg.any():
        return 1.0
    return min(1.0, float(np.min(-v[neg] / dv[neg])))


class _Newton:
    """The Newton systems of one iteration (``M`` factorised for ``d = x / z``).

    Eliminating ``dx`` and ``dz`` leaves ``M dy + f dlambda = h`` with
    ``h = r_p + A (d r_d) - A (r_c / z)`` and ``f . dy = r_f``.
    """

    def __init__(self, ipm: NormalIpm, x: FloatArray, z: FloatArray, rp: FloatArray, rd: FloatArray,
                 rf: float) -> None:
        self.ipm, self.x, self.z, self.rd, self.rf = ipm, x, z, rd, rf
        self.h0 = rp + ipm.A @ (ipm.M.d * rd)
        self.w: FloatArray | None = None

    def direction(self, rc: FloatArray) -> tuple[FloatArray, float, FloatArray, FloatArray]:
        """``(dx, dlambda, dy, dz)`` for the complementarity right-hand side ``rc``
        (the first call also solves for ``w = M^{-1} f``, in the same solve)."""
        ipm = self.ipm
        dy, dl, self.w = ipm.bordered(self.h0 - ipm.A @ (rc / self.z), self.rf, self.w)
        dz = self.rd - ipm.AT @ dy
        dx = (rc - self.x * dz) / self.z
        return dx, dl, dy, dz


class NormalIpm:
    """Mehrotra's predictor-corrector for ``min -d lambda, A x + f lambda = b, x >= 0`` (module docstring).

    Args:
        A: the ``x`` columns (sparse, full row rank).
        f: the free column.
        b: the right-hand side.
        settings: tolerances and limits.
    """

    def __init__(self, A: Any, f: FloatArray, b: FloatArray, settings: NormalIpmSettings = NORMAL_IPM) -> None:
        self.settings = settings
        self.f, self.b = f, b
        self.M = NormalMatrix(A, regularization=settings.regularization, refine_steps=settings.refine_steps,
                              refine_tol=settings.refine_tol)
        self.A, self.AT = self.M.A, self.M.AT
        self.m = int(self.A.shape[1])

    def _factor(self, d: FloatArray) -> None:
        """Factorise ``M(d)``, raising the shift up to twice if a pivot fails."""
        self.M.factor_raising(d)

    def bordered(self, h: FloatArray, rf: float, w: FloatArray | None = None) -> tuple[FloatArray, float, FloatArray]:
        """``(v, dlambda, w)`` with ``M v + f dlambda = h`` and ``f . v = rf``, through the
        factorisation of ``M``: ``w = M^{-1} f`` (solved with ``h`` unless given),
        ``dlambda = (f . M^{-1} h - rf) / (f . w)``, ``v = M^{-1} h - dlambda w``."""
        f = self.f
        if w is None:
            w, Mh = self.M.solve(np.column_stack([f, h])).T
        else:
            Mh = self.M.solve(h)
        dl = (float(f @ Mh) - rf) / float(f @ w)
        return Mh - dl * w, dl, w

    def _start(self, direction: int) -> tuple[FloatArray, float, FloatArray, FloatArray]:
        """Mehrotra's starting point: the least-norm ``(x, lambda)`` and a dual
        ``y`` along ``M^{-1} f`` with ``f . y = -d``, both shifted inside."""
        f, b = self.f, self.b
        self._factor(np.ones(self.m))
        w, v0 = self.M.solve(np.column_stack([f, b])).T
        v = v0 - float(f @ v0) / (1.0 + float(f @ w)) * w
        x = self.AT @ v
        lam = float(f @ v)
        y = -float(direction) * w / float(f @ w)
        z = -(self.AT @ y)
        x = x + max(-1.5 * float(x.min()), 0.0)
        z = z + max(-1.5 * float(z.min()), 0.0)
        xz = float(x @ z)
        return x + 0.5 * xz / float(z.sum()), lam, y, z + 0.5 * xz / float(x.sum())

    def run(self, direction: int, *, deadline: float = math.inf,
            trace: Callable[[int, float, float, float, float], None] | None = None) -> IpmResult:
        """Solve for ``direction`` with BLAS on one thread (:func:`~micro.backends.normal_matrix.one_blas_thread`).

        Args:
            direction: ``+1`` (maximise ``lambda``) or ``-1`` (minimise it).
            deadline: ``time.perf_counter()`` value at which to stop.
            trace: called every iteration with ``(iteration, lambda, gap, primal, dual)``.

        Raises:
            NotPositiveDefinite: a factorisation failed with the largest shift.
        """
        with one_blas_thread():
            return self._run(direction, deadline, trace)

    def _run(self, direction: int, deadline: float,
             trace: Callable[[int, float, float, float, float], None] | None) -> IpmResult:
        """:meth:`run`'s body."""
        st = self.settings
        A, AT, f, b, m = self.A, self.AT, self.f, self.b, self.m
        factorizations, refinements = self.M.factorizations, self.M.refinements
        x, lam, y, z = self._start(direction)
        b_scale = 1.0 + float(np.max(np.abs(b)))
        gap = primal = dual = math.inf
        reason = "iteration limit"
        it = 0
        while True:
            rp = b - A @ x - f * lam
            rd = -(AT @ y) - z
            rf = -float(direction) - float(f @ y)
            mu = float(x @ z) / m
            pobj, dobj = -float(direction) * lam, float(b @ y)
            gap = abs(pobj - dobj) / (1.0 + abs(pobj))
            primal = float(np.max(np.abs(rp))) / b_scale
            dual = max(float(np.max(np.abs(rd))), abs(rf)) / (1.0 + float(np.max(z)))
            if trace is not None:
                trace(it, lam, gap, primal, dual)
            if gap <= st.gap_tol and primal <= st.primal_tol and dual <= st.dual_tol:
                reason = "converged"
                break
            if max(float(np.max(x)), abs(lam), float(np.max(np.abs(y)))) > st.divergence:
                reason = "diverging (infeasible or unbounded)"
                break
            if time.perf_counter() > deadline:
                reason = "time limit"
                break
            if it == st.max_iter:
                break
            it += 1
            self._factor(x / z)
            sys_ = _Newton(self, x, z, rp, rd, rf)
            dxa, _, _, dza = sys_.direction(-x * z)
            ap, ad = _max_step(x, dxa), _max_step(z, dza)
            sigma = (float((x + ap * dxa) @ (z + ad * dza)) / m / mu) ** 3
            rc = sigma * mu - x * z - dxa * dza
            dx, dl, dy, dz = sys_.direction(rc)
            ap, ad = _max_step(x, dx), _max_step(z, dz)
            lo, hi = 0.1 * sigma * mu, 10.0 * sigma * mu  # the centrality box of Gondzio's correctors
            for _ in range(st.correctors):
                target_p, target_d = min(1.0, 1.5 * ap + 0.1), min(1.0, 1.5 * ad + 0.1)
                v = (x + target_p * dx) * (z + target_d * dz)
                t = np.clip(v, lo, hi) - v
                t[t < -hi] = -hi
                cx, cl, cy, cz = sys_.direction(rc + t)
                cp, cd = _max_step(x, cx), _max_step(z, cz)
                if min(cp, cd) < 1.01 * min(ap, ad) + 0.01:
                    break
                rc, dx, dl, dy, dz, ap, ad = rc + t, cx, cl, cy, cz, cp, cd
            ap, ad = st.step_fraction * ap, st.step_fraction * ad
            x, lam = x + ap * dx, lam + ap * dl
            y, z = y + ad * dy, z + ad * dz
        if reason == "converged":
            x, lam, primal = self._project(x, lam, primal * b_scale)
            primal /= b_scale
        return IpmResult(reason=reason, iterations=it, gap=gap, primal=primal, dual=dual, g=x, lam=lam, y=y,
                         factorizations=self.M.factorizations - factorizations,
                         refinements=self.M.refinements - refinements)

    def _project(self, x: FloatArray, lam: float, residual: float) -> tuple[FloatArray, float, float]:
        """The converged primal ``(x, lambda)`` moved onto equilibrium: up to
        :attr:`NormalIpmSettings.projections` corrections ``dx = d A^T v``,
        ``(M v + f dlambda = r_p, f . v = 0)``, the least change in the metric of
        the last factorisation (``d = x / z``: the generators that carry force
        take it), through that factorisation; a correction that does not lower
        the residual or turns a generator negative is not taken."""
        A, AT, f, b = self.A, self.AT, self.f, self.b
        w = None
        rp = b - A @ x - f * lam
        for _ in range(self.settings.projections):
            v, dl, w = self.bordered(rp, 0.0, w)
            x_new, lam_new = x + self.M.d * (AT @ v), lam + dl
            rp_new = b - A @ x_new - f * lam_new
            res = float(np.max(np.abs(rp_new)))
            if not res < residual or np.any(x_new < 0.0):
                break
            x, lam, residual, rp = x_new, lam_new, res, rp_new
        return x, lam, residual


class NormalIpmBackend:
    """The normal-equations interior point on the static LP of a wall (module docstring).

    Velocities are returned in the shared convention (live work ``+1``).

    Args:
        lp: the assembled LP.
        settings: tolerances and limits.
        time_limit: seconds per solve.
        polish: polish forces that fail the re-check
            (:data:`micro.backends.clarabel_kinematic.POLISH`).
    """

    STATUS_MAP = {"converged": Status.OPTIMAL, "time limit": Status.TIME_LIMIT}

    def __init__(self, lp: LimitLP, *, settings: NormalIpmSettings = NORMAL_IPM, time_limit: float | None = None,
                 polish: bool = True) -> None:
        self.lp = lp
        self.name = "normal-ipm"
        self.settings = settings
        self.time_limit = time_limit
        self.polish = polish
        self.active = lp.active_generators()
        self.A_g = lp.A[:, self.active]
        self._ipm: NormalIpm | None = None

    def solve(self, direction: int) -> Outcome:
        """Solve for live load direction ``direction`` (``+1`` or ``-1``); a run
        that stops short is solved again by the ``clarabel`` back end."""
        if not np.any(self.lp.live):
            return Outcome(Status.UNBOUNDED, "no live load", info={"form": "normal equations"})
        t0 = time.perf_counter()
        deadline = math.inf if self.time_limit is None else t0 + self.time_limit
        try:
            if self._ipm is None:
                self._ipm = NormalIpm(self.A_g, self.lp.live, self.lp.rhs, self.settings)
            res = self._ipm.run(direction, deadline=deadline)
        except NotPositiveDefinite as err:
            return self._fallback(direction, f"the normal equations lost positive definiteness ({err})", t0)
        secs = time.perf_counter() - t0
        status = self.STATUS_MAP.get(res.reason)
        if status is None:
            return self._fallback(direction, f"{res.reason} after {res.iterations} iterations", t0)
        info: dict[str, Any] = {"form": "normal equations", "factorizations": res.factorizations,
                                "refinements": res.refinements, "gap": res.gap, "r_prim": res.primal,
                                "r_dual": res.dual}
        if status is not Status.OPTIMAL:
            return Outcome(status, res.reason, ipm_iterations=res.iterations, seconds=secs, info=info)
        u = -res.y
        info["kinematic_load_factor"] = float(self.lp.rhs @ u)
        raw = Outcome(status, res.reason, duals=u, ipm_iterations=res.iterations, seconds=secs, info=info)
        out = checked_outcome(self.lp, self.A_g, self.active, direction, res.g, res.lam, raw, polish=self.polish)
        if out.ok:
            return out
        return self._fallback(direction, f"its forces failed the re-check (residual "
                              f"{out.info['primal_residual']:.1e})", t0)

    def _fallback(self, direction: int, why: str, t0: float) -> Outcome:
        """The ``clarabel`` back end's answer, this attempt's time added."""
        spent = time.perf_counter() - t0
        out = ClarabelKinematicBackend(self.lp, time_limit=self.time_limit, polish=self.polish).solve(direction)
        info = {**out.info, "fallback": f"normal-ipm: {why}; solved by clarabel"}
        return dataclasses.replace(out, seconds=out.seconds + spent, info=info)
