"""Experiment of docs/research/2026-11-26-shared-interior-point.md (issue 42): one box-constrained interior point on the normal equations with an
optional diagonal Hessian and an optional free column, for normal-ipm's LP and the proximal QP.

    min 1/2 x'Qx + c.x - d lam   s.t.  A x + f lam = b,  lower <= x <= upper   (Q = diag(q) >= 0)

Run from a checkout of the commit the page names: ``.venv/bin/python docs/research/2026-11-26-shared-interior-point.py``.
"""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp

import micro
from comparison.domain.wall import WallSpec
from micro.backends.normal_ipm import NormalIpmBackend
from micro.backends.normal_matrix import NormalMatrix, NotPositiveDefinite, one_blas_thread
from micro.nonassociative.proximal import PROX_MARGIN

try:  # the proximal QP's home moved: micro/backends/normal_qp.py, then micro/nonassociative/proximal.py, then back
    from micro.backends.normal_qp import LeastDistanceQP
except ImportError:
    from micro.nonassociative.proximal import LeastDistanceQP  # type: ignore[no-redef]


class BoxIPM:
    def __init__(self, A, f=None, *, gap_tol=1e-9, primal_tol=1e-9, dual_tol=1e-9, step_fraction=0.99,
                 regularization=1e-14, refine_steps=2, refine_tol=1e-12, max_iter=100):
        self.M = NormalMatrix(A, regularization=regularization, refine_steps=refine_steps, refine_tol=refine_tol)
        self.A, self.AT = self.M.A, self.M.AT
        self.f = None if f is None else np.asarray(f, float)
        self.gap_tol, self.primal_tol, self.dual_tol = gap_tol, primal_tol, dual_tol
        self.step_fraction, self.max_iter = step_fraction, max_iter

    def solve(self, q, c, b, lower, upper, d=0.0, start=None):
        t0 = time.perf_counter()
        with one_blas_thread(), np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            out = self._run(np.broadcast_to(np.asarray(q, float), lower.shape), c, b, lower, upper, float(d), start)
        return (*out, time.perf_counter() - t0)

    def _run(self, q, c, b, lower, upper, d, start):
        A, AT, f = self.A, self.AT, self.f
        quad = bool(np.any(q > 0))
        free = upper > lower
        up = free & np.isfinite(upper)
        n_bounds = max(int(free.sum() + up.sum()), 1)
        lo = np.where(free, lower, 0.0)
        hi = np.where(up, upper, 0.0)
        b_scale = 1.0 + float(np.max(np.abs(b), initial=0.0))
        scale = max(float(np.max(np.abs(c), initial=0.0)), 1.0) if quad else 1.0
        width = np.where(up, upper - lower, np.inf)
        if start is None:
            x = np.where(free, np.where(up, lower + 0.5 * width, lower + b_scale), lower)
        else:
            margin = np.minimum(1e-2 * scale, 0.25 * width)
            x = np.where(free, np.clip(start, lower + margin, np.where(up, upper - margin, np.inf)), lower)
        zl = np.where(free, scale, 0.0)
        zu = np.where(up, scale, 0.0)
        y = np.zeros(A.shape[0])
        lam = 0.0
        gap = primal = dual = math.inf
        for it in range(1, self.max_iter + 1):
            sl = np.where(free, x - lo, 1.0)
            su = np.where(up, hi - x, 1.0)
            grad = q * x + c
            rd = np.where(free, grad - AT @ y - zl + zu, 0.0)
            rl = (-d - float(f @ y)) if f is not None else 0.0
            rp = b - A @ x - (f * lam if f is not None else 0.0)
            products = float(np.sum((sl * zl)[free]) + np.sum((su * zu)[up]))
            p_obj = 0.5 * float(x @ (q * x)) + float(c @ x) - d * lam
            gap = products / (1.0 + abs(p_obj))
            primal = float(np.max(np.abs(rp), initial=0.0)) / b_scale
            dual = max(float(np.max(np.abs(rd), initial=0.0)), abs(rl)) / (1.0 + scale + float(np.max(np.abs(y), initial=0.0)) * (not quad))
            if not (math.isfinite(gap) and math.isfinite(primal) and math.isfinite(dual)):
                return x, lam, y, "not finite", it
            if gap <= self.gap_tol and primal <= self.primal_tol and dual <= self.dual_tol:
                return x, lam, y, "converged", it - 1
            mu = products / n_bounds
            H = np.where(free, q + zl / sl + np.where(up, zu / su, 0.0), 1.0)
            dinv = np.where(free, 1.0 / H, 0.0)
            try:
                self.M.factor_raising(dinv)
            except NotPositiveDefinite:
                return x, lam, y, "not positive definite", it
            w = self.M.solve(f) if f is not None else None
            fw = float(f @ w) if f is not None else 1.0

            def direction(rcl, rcu):
                r1 = np.where(free, rd - rcl / sl + np.where(up, rcu / su, 0.0), 0.0)
                u = self.M.solve(rp + A @ (dinv * r1))
                if f is not None:
                    dl = (float(f @ u) - rl) / fw
                    dy = u - dl * w
                else:
                    dl, dy = 0.0, u
                dx = dinv * (AT @ dy - r1)
                return dx, dl, dy, np.where(free, (rcl - zl * dx) / sl, 0.0), np.where(up, (rcu + zu * dx) / su, 0.0)

            def longest(dx, dzl, dzu):
                steps = []
                for pairs in (((sl, dx, free), (su, -dx, up)), ((zl, dzl, free), (zu, dzu, up))):
                    a = 1.0
                    for v, dv, mask in pairs:
                        neg = mask & (dv < 0.0)
                        if np.any(neg):
                            a = min(a, float(np.min(-v[neg] / dv[neg])))
                    steps.append(a)
                if quad:  # the Hessian couples primal and dual: one step
                    return min(steps), min(steps)
                return steps[0], steps[1]

            dx, dl, dy, dzl, dzu = direction(np.where(free, -sl * zl, 0.0), np.where(up, -su * zu, 0.0))
            ap, ad = longest(dx, dzl, dzu)
            mu_aff = float(np.sum(((sl + ap * dx) * (zl + ad * dzl))[free])
                           + np.sum(((su - ap * dx) * (zu + ad * dzu))[up])) / n_bounds
            sigma = min((mu_aff / mu) ** 3, 1.0) if mu > 0 else 0.0
            rcl = np.where(free, sigma * mu - sl * zl - dx * dzl, 0.0)
            rcu = np.where(up, sigma * mu - su * zu + dx * dzu, 0.0)
            dx, dl, dy, dzl, dzu = direction(rcl, rcu)
            ap, ad = longest(dx, dzl, dzu)
            ap, ad = min(1.0, self.step_fraction * ap), min(1.0, self.step_fraction * ad)
            x, lam = x + ap * dx, lam + ap * dl
            y, zl, zu = y + ad * dy, zl + ad * dzl, zu + ad * dzu
        return x, lam, y, "iteration limit", self.max_iter


def main() -> None:
    def table5_wall(f):
        return WallSpec.from_paper(t=1, m=1/3, rows=60, f=f, p=0, storeys=3).to_micro()

    for name, w in [("Set 12 (54 blocks)", WallSpec.from_paper(t=1, m=1/3, rows=12, f=0.75, p=0, storeys=1).to_micro()),
                    ("Ref (1,230 blocks)", table5_wall(0.6))]:
        lp = micro.assemble(w)
        be = NormalIpmBackend(lp)
        t0 = time.process_time(); ref = be.solve(1); t_ref = time.process_time() - t0
        A_g = lp.A[:, be.active]
        box = BoxIPM(A_g, lp.live, gap_tol=1e-8, primal_tol=1e-7)
        m = A_g.shape[1]
        t0 = time.process_time()
        x, lam, y, reason, its, secs = box.solve(0.0, np.zeros(m), lp.rhs, np.zeros(m), np.full(m, np.inf), d=1.0)
        t_box = time.process_time() - t0
        print(f"{name}: normal-ipm lambda {ref.load_factor!r} ({ref.ipm_iterations} it, {t_ref:.3f} s CPU); "
              f"shared loop {lam!r} ({reason}, {its} it, {t_box:.3f} s CPU); rel diff {abs(lam-ref.load_factor)/ref.load_factor:.2e}")
        # the proximal QP at the associative forces (the first projection of a proximal sequence from them)
        nbar = np.maximum(np.asarray(ref.n), 0.0)
        P = lp.n_points
        Ax = sp.hstack([lp.Bn, lp.Bs], format="csc")
        b = lp.rhs - (lam * (1 - PROX_MARGIN)) * lp.live
        cap = lp.mu * nbar
        lower, upper = np.concatenate([np.zeros(P), -cap]), np.concatenate([np.full(P, np.inf), cap])
        t = np.concatenate([nbar, np.zeros(P)])
        qp = LeastDistanceQP(Ax)
        t0 = time.process_time(); o = qp.solve(t, b, lower, upper); t_qp = time.process_time() - t0
        box2 = BoxIPM(Ax)
        t0 = time.process_time()
        x2, _, _, reason2, its2, _ = box2.solve(1.0, -t, b, lower, upper, start=t)
        t_b2 = time.process_time() - t0
        obj = lambda v: 0.5 * float(np.sum((v - t) ** 2))
        print(f"   QP: LeastDistanceQP {o.reason} {o.iterations} it {t_qp:.3f} s obj {obj(o.x)!r}; shared loop {reason2} {its2} it "
              f"{t_b2:.3f} s obj {obj(x2)!r}; max |dx| / max n {np.max(np.abs(x2 - o.x)) / max(nbar.max(), 1):.2e}; bit-identical {np.array_equal(x2, o.x)}")


if __name__ == "__main__":
    main()
