"""Sequences of the iterated LP with each LP by a box-bounded interior point, a vertex only where the
certificate is tried (the page of the same name). It takes over ``2026-11-29-interior-proximal.py`` with
what that page left to do: an interior point that ends on the large walls, and a cheaper vertex.

    .venv/bin/python docs/research/2026-11-29-interior-sequences.py WALL MAX_LPS [BETA] [EVERY] [options]

``WALL`` is a case of the paper (``Ref``, ``2``, ``9``, ``15``); ``BETA`` the relaxation (0.6, the package's);
``EVERY``: the certificate is tried at every ``EVERY``-th LP from the 10th. Per LP:

* the scheme-(a) LP at the current ``nbar`` (``|s| <= mu nbar``) by ``BoxIPM`` of the 2026-11-26 research
  script, gap and dual tolerances 1e-8, primal tolerance :data:`PRIMAL_TOL`, at most 250 iterations from the
  last LP's point; where that does not converge, again from its own start with 500; where that fails too,
  HiGHS' interior point with crossover;
* the next ``nbar``: moved by ``BETA`` towards the package's proximal projection at the LP's ``lambda``
  (``micro/nonassociative/proximal.py``), or with ``--centre`` towards the interior point's own normal forces
  (the centre of the LP's optimal face; no projection).

A certificate try solves the same LP by HiGHS for a vertex and its mechanism and runs the package's
certificate on it: by HiGHS' interior point with crossover (a new model each try), or with ``--warm`` by
the dual simplex from the last try's basis (the first try by the interior point with crossover). Where it
certifies, the band's lower end is checked as the descent checks a state (``is_exact``).

Options: ``--warm``; ``--centre``; ``--primal-tol=T`` (:data:`PRIMAL_TOL`); ``--fallback=ipm`` (HiGHS'
interior point without crossover where the box interior point fails, as on the lead's page);
``--try-below=S`` (try only where the step ``|n - nbar|_1 / |nbar|_1`` is below ``S``); ``--save=DIR``
(each LP's ``nbar`` to ``DIR/nbar_<wall>_<beta>_<k>.npy``); ``--from=FILE`` (start from a saved ``nbar``,
at the LP its name gives). Run it with one BLAS/OpenMP thread.
"""

from __future__ import annotations

import runpy
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from comparison.domain.cases import case
from micro.backends.roles import InteriorLP
from micro.lp import LimitLP, assemble
from micro.nonassociative.certificate import Certificate
from micro.nonassociative.descent.lowest import is_exact
from micro.nonassociative.model import IterationModel
from micro.nonassociative.proximal import Projection

#: The interior point's gap and dual tolerances.
TOLERANCE = 1e-8
#: Its primal tolerance (relative to the largest right-hand side; ``--primal-tol=``): on Set 15 the primal
#: residual of the normal equations stalls at 3e-7 to 2e-6 while the gap falls to 1e-14, and the next
#: iterate is NaN.
PRIMAL_TOL = 1e-5
#: Iterations from the last LP's point, then from the interior point's own start.
MAX_ITER, MAX_ITER_COLD = 250, 500


def option(name: str) -> str | None:
    """The value of ``--name=value`` on the command line (``None`` where absent)."""
    return next((a.split("=", 1)[1] for a in sys.argv if a.startswith(f"--{name}=")), None)


WARM = "--warm" in sys.argv
CENTRE = "--centre" in sys.argv
TRY_BELOW = float(option("try-below") or "inf")
SAVE = option("save")
RESUME = option("from")
#: Where both tries of the box interior point fail: HiGHS' interior point with crossover (``crossover``), or
#: without (``ipm``, the lead's page: a λ of about 1e-6 relative accuracy).
FALLBACK = option("fallback") or "crossover"


def box_ipm() -> Any:
    """``BoxIPM`` of the 2026-11-26 research script (box bounds, the free column by a bordered solve)."""
    return runpy.run_path(str(Path(__file__).with_name("2026-11-26-shared-interior-point.py")))["BoxIPM"]


def vertex_run(lp: LimitLP, d: int, nbar: np.ndarray, model: IterationModel | None,
               crossover: bool = True) -> tuple[IterationModel, Any]:
    """The scheme-(a) LP at ``nbar`` solved for a vertex: by ``model``'s dual simplex from its last basis, or
    (``model`` ``None``) in a new model by HiGHS' interior point with crossover, then the dual simplex where
    that is not optimal (``crossover=False``: the interior point's answer as it is, no vertex). Returns (the
    model, its outcome)."""
    if model is not None:
        model.set_capacity(nbar, 0.0, 0.0, 0.0)
        return model, model.model.run()
    m = IterationModel(lp, d, "a", 0.3)
    m.set_capacity(nbar, 0.0, 0.0, 0.0)
    m.model.set_algorithm("ipm", crossover=crossover)
    out = m.model.run()
    if not crossover:
        return m, out
    m.model.set_algorithm("simplex")
    if out.x is None or getattr(out.status, "value", out.status) != "optimal":
        out = m.model.run()
    return m, out


def main(name: str, max_lps: int, beta: float, every: int) -> None:
    wall = case(name).spec().to_micro()
    lp, d = assemble(wall), 1
    P = lp.n_points
    t0 = time.process_time()
    first = 1
    if RESUME is not None:
        first = int(Path(RESUME).stem.rsplit("_", 1)[1])
        nbar = np.load(RESUME)
    else:
        nbar = np.maximum(np.asarray(InteriorLP(lp).solve(d).n), 0.0)
    box = box_ipm()(sp.hstack([lp.Bn, lp.Bs], format="csc"), d * lp.live, gap_tol=TOLERANCE,
                    primal_tol=float(option("primal-tol") or PRIMAL_TOL), dual_tol=TOLERANCE, max_iter=MAX_ITER)
    projection = Projection(lp, d)
    x = None
    vertex_model: IterationModel | None = None  # with WARM: one model, each try warm from the last try's basis
    spent = {"lp": 0.0, "qp": 0.0, "certificate": 0.0}
    for k in range(first, max_lps + 1):
        if SAVE:
            np.save(f"{SAVE}/nbar_{name}_{beta}_{k}.npy", nbar)
        t1 = time.process_time()
        cap = lp.mu * nbar
        bounds = (np.concatenate([np.zeros(P), -cap]), np.concatenate([np.full(P, np.inf), cap]))
        x, lam, _, status, its, _ = box.solve(0.0, np.zeros(2 * P), lp.rhs, *bounds, d=1.0, start=x)
        how = f"{status}, {its} it"
        if status != "converged":
            box.max_iter = MAX_ITER_COLD
            x, lam, _, status, its, _ = box.solve(0.0, np.zeros(2 * P), lp.rhs, *bounds, d=1.0, start=None)
            box.max_iter = MAX_ITER
            how += f"; from its own start: {status}, {its} it"
        if status != "converged":
            fallback, out = vertex_run(lp, d, nbar, None, crossover=FALLBACK == "crossover")
            if out.x is None:
                print(f"LP {k}: no solver solved it ({how}; HiGHS {out.status})", flush=True)
                break
            lam, x = fallback.load_factor(out.x), None
            how += f"; HiGHS' interior point, {FALLBACK} ({out.status})"
        t2 = time.process_time()
        if CENTRE:
            if x is None:
                print(f"LP {k}: no interior point to move towards ({how})", flush=True)
                break
            normal = np.maximum(x[:P], 0.0)
            step = float(np.abs(normal - nbar).sum()) / max(float(np.abs(nbar).sum()), 1e-300)
        else:
            projected = projection.project(nbar, lam)
            normal, step = projected.normal, projected.step
        t3 = time.process_time()
        spent["lp"] += t2 - t1
        spent["qp"] += t3 - t2
        print(f"LP {k}: lambda {lam!r} ({how}, {t2 - t1:.2f} s); step {step:.4f} ({t3 - t2:.2f} s)", flush=True)
        if normal is None:
            break
        if k >= 10 and k % every == 0 and step < TRY_BELOW:
            m, out = vertex_run(lp, d, nbar, vertex_model if WARM else None)
            vertex_model = m
            vertex = m.load_factor(out.x)
            cert = Certificate(lp, d, "a").certify(out.duals[: lp.n_eq], vertex)
            spent["certificate"] += time.process_time() - t3
            print(f"  certificate at LP {k}: the vertex's lambda {vertex!r}, {out.simplex_iterations} pivots: "
                  f"{'certified, band ' + str(cert.band) if cert.forces is not None else 'no state'} "
                  f"({time.process_time() - t3:.2f} s)", flush=True)
            if cert.forces is not None:
                low, _ = Certificate(lp, d, "a").state_lp(out.duals[: lp.n_eq], 1.0)
                if low is not None:
                    exact = is_exact(lp, d, low[2], low[0], low[1], out.duals[: lp.n_eq])
                    print(f"  the band's lower end {low[2]!r}: "
                          f"{'passes' if exact else 'does not pass'} the descent's check (verify_collapse_state)",
                          flush=True)
                break
        nbar = nbar + beta * (normal - nbar)
    print(f"in all {time.process_time() - t0:.1f} s: LPs {spent['lp']:.1f} s, steps {spent['qp']:.1f} s, "
          f"certificate tries {spent['certificate']:.1f} s", flush=True)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(args[0], int(args[1]), float(args[2]) if len(args) > 2 else 0.6, int(args[3]) if len(args) > 3 else 5)
