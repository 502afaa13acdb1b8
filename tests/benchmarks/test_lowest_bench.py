"""Cost of the descent to the lowest certified state on Table 7's walls (54, 78, 102, 150 blocks).

Run with ``pytest -m benchmark --benchmark-enable tests/benchmarks/test_lowest_bench.py``.
Per wall two benchmarks of group ``lowest-<set>``: the iterated LP alone
(``lowest=False``) and the descent from its converged state
(:func:`micro.nonassociative.descent.lowest.lowest_state`, the iterated LP solved
once outside the timed call), so that their ratio is the descent's cost in
iterated-LP runs. Each asserts the load factor it times (pinned: no decision
of the descent depends on time) and that the state is exact. The MIP's cost
on the same walls is ``tests/benchmarks/test_global_bench.py``.
"""

from __future__ import annotations

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative.descent.lowest import EXACT_TOL, lowest_state

#: Table 7 set, (t, m), blocks, the iterated LP's load factor and the lowest certified one (+x, defaults).
CASES = [
    ("set12", (1.0, 1 / 3), 54, 0.7086216, 0.6911080),
    ("set13", (1.0, 1 / 2), 78, 0.4912758, 0.4894591),
    ("set11", (0.5, 1 / 3), 102, 0.7144259, 0.7005249),
    ("set14", (1.0, 1.0), 150, 0.2683827, 0.2658313),
]
IDS = [c[0] for c in CASES]


def _wall(tm: tuple[float, float]) -> micro.BlockWall:
    return WallSpec.from_paper(t=tm[0], m=tm[1], rows=12, f=0.75).to_micro()


@pytest.mark.benchmark
@pytest.mark.parametrize("name, tm, blocks, lam, low", CASES, ids=IDS)
def test_bench_iterated(benchmark, name: str, tm: tuple[float, float], blocks: int,  # type: ignore[no-untyped-def]
                        lam: float, low: float) -> None:
    benchmark.group = f"lowest-{name}"
    w = _wall(tm)
    assert w.n_blocks == blocks
    r = benchmark.pedantic(micro.solve_nonassociative, args=(w,), kwargs={"lowest": False}, rounds=5, iterations=1)
    benchmark.extra_info.update(blocks=blocks, load_factor=r.load_factor, lps=r.total_iterations)
    assert r.converged and r.load_factor == pytest.approx(lam, rel=1e-6)


@pytest.mark.benchmark
@pytest.mark.parametrize("name, tm, blocks, lam, low", CASES, ids=IDS)
def test_bench_descent(benchmark, name: str, tm: tuple[float, float], blocks: int,  # type: ignore[no-untyped-def]
                       lam: float, low: float) -> None:
    benchmark.group = f"lowest-{name}"
    w = _wall(tm)
    lp = micro.assemble(w)
    it = micro.solve_nonassociative(w, lowest=False)
    d = benchmark.pedantic(lowest_state, args=(lp, it.directions[0], it.resolved), rounds=5, iterations=1)
    benchmark.extra_info.update(blocks=blocks, load_factor=d.load_factor, lps=d.lps, moves=len(d.moves),
                                path=list(d.path))
    assert d.found and d.load_factor == pytest.approx(low, rel=1e-6)
    assert d.load_factor <= it.load_factor * (1 + 1e-9)
    assert all(v <= EXACT_TOL for k, v in d.residuals.items() if k != "slipping_points")
