"""Speed of the proximal selection's projection QP: the normal-equations interior point against Clarabel.

Run with ``pytest -m benchmark --benchmark-enable tests/benchmarks/test_projection_bench.py``
(the fast suite deselects them). Group ``projection-1230``: the first projection of the
proximal sequence on Set 2 (1,230 blocks), from the associative normal forces at the
optimum of Gilbert's LP there, by each solver of :class:`~micro.nonassociative.proximal.Projection`. Both
answer the same unique QP: each benchmark records its objective and iterations in
``benchmark.extra_info`` and asserts the field feasible. Measured 2026-11-26 on one
core: 0.25-0.32 s against Clarabel's 0.76-1.07 s
(``docs/research/2026-11-26-proximal-projection.md``).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import micro
from comparison.domain.cases import case
from micro.nonassociative.model import IterationModel, restart
from micro.nonassociative.proximal import PROX_MARGIN, Projection


@functools.lru_cache(maxsize=1)
def _set2_first_iterate() -> tuple[micro.LimitLP, np.ndarray, float]:
    """Set 2's LP, the associative normal forces (scaled) and Gilbert's LP optimum at them."""
    w = case("2").spec().to_micro()
    lp = micro.assemble(w)
    a = micro.solve_associative(w, solver="clarabel", directions="+x")
    assert a.normal is not None
    nbar = np.maximum(a.normal / lp.force_scale, 0.0)
    m = IterationModel(lp, 1, "a", 0.3)
    m.set_capacity(nbar, 0.0, 0.0, 0.0)
    return lp, nbar, m.load_factor(restart(m.model).x)


@pytest.mark.benchmark(group="projection-1230")
@pytest.mark.parametrize("solver", ["normal-ipm", "clarabel"])
def test_bench_set2_projection(benchmark, solver: str) -> None:  # type: ignore[no-untyped-def]
    lp, nbar, lam = _set2_first_iterate()
    projection = Projection(lp, 1, solver=solver)
    out = benchmark.pedantic(projection.project, args=(nbar, lam), rounds=5, iterations=1)
    assert out.normal is not None and out.shear is not None and out.solver == solver
    objective = 0.5 * float(np.sum((out.normal - nbar) ** 2) + np.sum(out.shear**2))
    benchmark.extra_info.update(objective=objective, iterations=out.iterations, status=out.status)
    r = lp.Bn @ out.normal + lp.Bs @ out.shear + lam * (1.0 - PROX_MARGIN) * lp.live - lp.rhs
    assert float(np.max(np.abs(r))) <= 1e-8
    assert float(np.max(np.abs(out.shear) - lp.mu * nbar)) <= 1e-7
