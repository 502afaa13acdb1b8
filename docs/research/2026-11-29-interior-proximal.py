"""The proximal sequence with each LP by a box-bounded interior point on the normal equations, a vertex only
where the certificate is tried (the page of the same name).

    .venv/bin/python docs/research/2026-11-29-interior-proximal.py WALL MAX_LPS [BETA] [EVERY] [--warm]

``WALL`` is a case of the paper (``Ref``, ``9``); ``BETA`` the relaxation (0.6, the package's); ``EVERY``: the
certificate is tried at every ``EVERY``-th LP from the 10th. Per LP: the scheme-(a) LP at the current ``nbar``
(``|s| <= mu nbar``) by ``BoxIPM`` of the 2026-11-26 research script (tolerances 1e-8; HiGHS' interior point
where it does not converge) for its ``lambda``, then the package's proximal projection, and ``nbar`` moved by
``BETA`` towards it. A certificate try solves the same LP by HiGHS' dual simplex from no basis (a vertex and
its mechanism), or with ``--warm`` by the dual simplex from the last try's basis, and runs the package's
certificate on that mechanism; where it certifies, the band's lower end is checked as the descent checks a
state (``is_exact``). Run it with one BLAS/OpenMP thread.
"""

from __future__ import annotations

import importlib.util
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

#: Certificate tries warm from the last try's basis (``--warm``), or each from no basis.
WARM = "--warm" in sys.argv
#: The interior point's tolerances: at its default 1e-9 it ended "not finite" on Ref's first LP.
TOLERANCE = 1e-8


def box_ipm() -> Any:
    """``BoxIPM`` of the 2026-11-26 research script (box bounds, the free column by a bordered solve)."""
    path = Path(__file__).with_name("2026-11-26-shared-interior-point.py")
    spec = importlib.util.spec_from_file_location("shared_interior_point", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.BoxIPM


def scheme_a_model(lp: LimitLP, d: int, nbar: np.ndarray, algorithm: str) -> tuple[Any, Any]:
    """The iterated LP's model at ``nbar`` (scheme (a)), run once by ``algorithm``: (model, outcome)."""
    m = IterationModel(lp, d, "a", 0.3)
    m.set_capacity(nbar, 0.0, 0.0, 0.0)
    m.model.set_algorithm(algorithm)
    return m, m.model.run()


def main(name: str, max_lps: int, beta: float, every: int) -> None:
    wall = case(name).spec().to_micro()
    lp, d = assemble(wall), 1
    P = lp.n_points
    t0 = time.process_time()
    nbar = np.maximum(np.asarray(InteriorLP(lp).solve(d).n), 0.0)
    box = box_ipm()(sp.hstack([lp.Bn, lp.Bs], format="csc"), d * lp.live, gap_tol=TOLERANCE,
                    primal_tol=TOLERANCE, dual_tol=TOLERANCE)
    projection = Projection(lp, d)
    x = None
    vertex_model: IterationModel | None = None  # with WARM: one model, each try warm from the last try's basis
    spent = {"lp": 0.0, "qp": 0.0, "certificate": 0.0}
    for k in range(1, max_lps + 1):
        t1 = time.process_time()
        cap = lp.mu * nbar
        x, lam, _, status, _, _ = box.solve(0.0, np.zeros(2 * P), lp.rhs, np.concatenate([np.zeros(P), -cap]),
                                            np.concatenate([np.full(P, np.inf), cap]), d=1.0, start=x)
        if status != "converged":
            m, out = scheme_a_model(lp, d, nbar, "ipm")
            lam, status, x = m.load_factor(out.x), f"HiGHS IPM ({status})", None
        t2 = time.process_time()
        step = projection.project(nbar, lam)
        t3 = time.process_time()
        spent["lp"] += t2 - t1
        spent["qp"] += t3 - t2
        print(f"LP {k}: lambda {lam!r} ({status}, {t2 - t1:.2f} s); projection step {step.step:.4f} "
              f"({t3 - t2:.2f} s)", flush=True)
        if step.normal is None:
            break
        if k >= 10 and k % every == 0:
            if WARM and vertex_model is not None:
                m = vertex_model
                m.set_capacity(nbar, 0.0, 0.0, 0.0)
                out = m.model.run()
            else:
                m, out = scheme_a_model(lp, d, nbar, "simplex")
                vertex_model = m
            vertex = m.load_factor(out.x)
            cert = Certificate(lp, d, "a").certify(out.duals[: lp.n_eq], vertex)
            spent["certificate"] += time.process_time() - t3
            print(f"  certificate at LP {k}: the vertex's lambda {vertex!r}, {out.simplex_iterations} pivots: "
                  f"{'certified, band ' + str(cert.band) if cert.forces is not None else 'no state'} "
                  f"({time.process_time() - t3:.2f} s)", flush=True)
            if cert.forces is not None:
                certificate = Certificate(lp, d, "a")
                low, _ = certificate.state_lp(out.duals[: lp.n_eq], 1.0)
                if low is not None:
                    exact = is_exact(lp, d, low[2], low[0], low[1], out.duals[: lp.n_eq])
                    print(f"  the band's lower end {low[2]!r}: "
                          f"{'passes' if exact else 'does not pass'} the descent's check (verify_collapse_state)",
                          flush=True)
                break
        nbar = nbar + beta * (step.normal - nbar)
    print(f"in all {time.process_time() - t0:.1f} s: LPs {spent['lp']:.1f} s, projections {spent['qp']:.1f} s, "
          f"certificate tries {spent['certificate']:.1f} s", flush=True)


if __name__ == "__main__":
    sys.argv = [a for a in sys.argv if a != "--warm"]
    main(sys.argv[1], int(sys.argv[2]), float(sys.argv[3]) if len(sys.argv) > 3 else 0.6,
         int(sys.argv[4]) if len(sys.argv) > 4 else 5)
