"""Speed of one LP of the iterated LP on Set 9 (1,830 blocks): the warm dual simplex against the crossover route.

Run with ``pytest -m benchmark --benchmark-enable tests/benchmarks/test_route_bench.py``
(the fast suite deselects them). Group ``vertex-lp-1830``: Gilbert's LP at the
normal forces of the first LP's vertex (the first LP at the associative forces),
solved (a) by a warm dual simplex from the first LP's basis, as the simplex route
does, and (b) by the crossover route (``Tuning.lp_route="crossover"``: the
normal-equations interior point, HiGHS' crossover, a dual-simplex clean-up). Both
answer the same LP: each benchmark asserts its ``lambda`` against a cold HiGHS
solve's (relative ``COLD_TOL``, 1e-6: the warm run from the first LP's basis ended
1.1e-7 below it, HiGHS' hot start) and records its iterations in
``benchmark.extra_info``. First run (2026-11-26, one core, the other idle): median
3.08 s for the route against 4.00 s warm
(``docs/research/2026-11-26-crossover-route.md``).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import micro
from comparison.cases import case
from micro.nonassociative.model import IterationModel, restart
from micro.nonassociative.tuning import COLD_TOL

pytestmark = pytest.mark.slow


@functools.lru_cache(maxsize=1)
def _set9_second_lp() -> tuple[micro.LimitLP, np.ndarray, object, float]:
    """Set 9's LP, the first LP's normal forces (the second LP's ``nbar``), the first LP's
    basis and the second LP's optimum (by a cold HiGHS solve)."""
    w = case("9").spec().to_micro()
    lp = micro.assemble(w)
    a = micro.solve_associative(w, solver="clarabel", directions="+x")
    assert a.normal is not None
    m = IterationModel(lp, 1, "a", 0.0)
    m.set_capacity(np.maximum(a.normal / lp.force_scale, 0.0), 0.0, 0.0, 0.0)
    first = restart(m.model)
    assert first.x is not None
    nbar = np.maximum(m.forces(first.x)[0], 0.0)
    basis = m.model.get_basis()
    m.set_capacity(nbar, 0.0, 0.0, 0.0)
    second = restart(m.model)
    assert second.x is not None
    return lp, nbar, basis, m.load_factor(second.x)


def _model(lp: micro.LimitLP, nbar: np.ndarray) -> IterationModel:
    m = IterationModel(lp, 1, "a", 0.0)
    m.set_capacity(nbar, 0.0, 0.0, 0.0)
    return m


@pytest.mark.benchmark(group="vertex-lp-1830")
def test_bench_set9_warm_simplex(benchmark) -> None:  # type: ignore[no-untyped-def]
    lp, nbar, basis, lam = _set9_second_lp()
    m = _model(lp, nbar)

    def setup() -> None:
        m.model.set_basis(basis)

    out = benchmark.pedantic(lambda: m.warm(None, 10**9), setup=setup, rounds=3, iterations=1)
    assert out.ok and out.x is not None
    assert m.load_factor(out.x) == pytest.approx(lam, rel=COLD_TOL)
    benchmark.extra_info.update(simplex_iterations=int(out.simplex_iterations))


@pytest.mark.benchmark(group="vertex-lp-1830")
def test_bench_set9_crossover_route(benchmark) -> None:  # type: ignore[no-untyped-def]
    lp, nbar, _, lam = _set9_second_lp()
    m = _model(lp, nbar)
    out = benchmark.pedantic(lambda: m.interior_vertex(None), rounds=3, iterations=1)
    assert out is not None and out.ok and out.x is not None
    assert m.load_factor(out.x) == pytest.approx(lam, rel=COLD_TOL)
    benchmark.extra_info.update(ipm_iterations=int(out.ipm_iterations),
                                crossover_iterations=int(out.crossover_iterations),
                                simplex_iterations=int(out.simplex_iterations))
