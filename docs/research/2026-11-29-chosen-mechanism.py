"""A mechanism chosen on the optimal face of the iterated LP at a saved ``nbar``, for the certificate (a probe;
the page ``2026-11-29-interior-sequences.md``, "What this leaves").

    .venv/bin/python docs/research/2026-11-29-chosen-mechanism.py WALL NBAR.npy [EPS] [METHOD]

Steps:

* the LP at ``nbar`` (scheme (a), ``|s| <= mu nbar``) by ``BoxIPM`` for ``lambda``;
* the proximal projection, for a field;
* one LP over the LP's optimal mechanisms ``u``: ``live . u = 1``, ``Bn^T u >= 0``, and the work
  ``rhs . u + sum cap |Bs^T u| <= lambda (1 + EPS)``. It minimises the opening where ``nbar`` carries force,
  and the slip where the field is below yield. It is solved by scipy's ``linprog`` (``METHOD``:
  ``highs-ipm``, with crossover, or ``highs-ds``);
* the package's certificate on that mechanism.

``NBAR.npy`` is a file that ``2026-11-29-interior-sequences.py --save=DIR`` writes.
"""

from __future__ import annotations

import runpy
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from comparison.domain.cases import case
from micro.lp import assemble
from micro.nonassociative.certificate import Certificate
from micro.nonassociative.descent.lowest import is_exact
from micro.nonassociative.proximal import Projection


def main(name: str, path: str, eps: float, method: str) -> None:
    box_ipm = runpy.run_path(str(Path(__file__).with_name("2026-11-26-shared-interior-point.py")))["BoxIPM"]
    lp = assemble(case(name).spec().to_micro())
    P, neq, d = lp.n_points, lp.n_eq, 1
    nbar = np.load(path)
    cap = lp.mu * nbar
    box = box_ipm(sp.hstack([lp.Bn, lp.Bs], format="csc"), lp.live, gap_tol=1e-8, primal_tol=1e-5,
                  dual_tol=1e-8, max_iter=250)
    t0 = time.process_time()
    _, lam, _, status, its, _ = box.solve(0.0, np.zeros(2 * P), lp.rhs, np.concatenate([np.zeros(P), -cap]),
                                          np.concatenate([np.full(P, np.inf), cap]), d=1.0)
    print(f"LP: {status}, {its} it, lambda {lam!r}, {time.process_time() - t0:.2f} s", flush=True)
    projected = Projection(lp, d).project(nbar, lam)
    shear = np.abs(projected.shear) if projected.shear is not None else 0.0
    w_open = nbar / max(float(nbar.max()), 1e-300)
    w_slip = np.maximum(cap - shear, 0.0) / max(float(cap.max()), 1e-300)
    Bn, Bs = sp.csr_matrix(lp.Bn), sp.csr_matrix(lp.Bs)
    eye, zero = sp.identity(P, format="csr"), sp.csr_matrix((P, P))
    # variables (u: neq, free; t: P, >= |Bs^T u|)
    c = np.concatenate([Bn @ w_open, w_slip]) + 1e-9 * np.concatenate([Bn @ np.ones(P), np.ones(P)])
    a_ub = sp.vstack([sp.hstack([-Bn.T, zero]), sp.hstack([Bs.T, -eye]), sp.hstack([-Bs.T, -eye]),
                      sp.hstack([sp.csr_matrix(lp.rhs.reshape(1, -1)), sp.csr_matrix(cap.reshape(1, -1))])],
                     format="csr")
    b_ub = np.concatenate([np.zeros(3 * P), [lam * (1 + eps)]])
    a_eq = sp.hstack([sp.csr_matrix(lp.live.reshape(1, -1)), sp.csr_matrix((1, P))], format="csr")
    t1 = time.process_time()
    res = linprog(c, A_ub=a_ub, b_ub=b_ub, A_eq=a_eq, b_eq=[1.0], bounds=[(None, None)] * neq + [(0, None)] * P,
                  method=method)
    print(f"the chooser LP: status {res.status}, {time.process_time() - t1:.2f} s", flush=True)
    if res.x is None:
        return
    u = res.x[:neq]
    dn, ds = lp.Bn.T @ u, lp.Bs.T @ u
    scale = max(float(dn.max()), float(np.abs(ds).max()))
    work = float(lp.rhs @ u + cap @ np.abs(ds))
    print(f"its work {work!r} against lambda {lam!r}; opening points {int((dn > 1e-6 * scale).sum())}, "
          f"slipping {int((np.abs(ds) > 1e-6 * scale).sum())} of {P}", flush=True)
    for at in (lam, work):
        t2 = time.process_time()
        cert = Certificate(lp, d, "a").certify(u, at)
        found = f"certified, band {cert.band}" if cert.forces is not None else f"no state (band {cert.band})"
        print(f"certificate at {at!r}: {found}, {time.process_time() - t2:.2f} s", flush=True)
        if cert.forces is not None:
            low, _ = Certificate(lp, d, "a").state_lp(u, 1.0)
            if low is not None:
                print(f"  lower end {low[2]!r}: is_exact {is_exact(lp, d, low[2], low[0], low[1], u)}", flush=True)
            break


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], float(sys.argv[3]) if len(sys.argv) > 3 else 1e-7,
         sys.argv[4] if len(sys.argv) > 4 else "highs-ipm")
