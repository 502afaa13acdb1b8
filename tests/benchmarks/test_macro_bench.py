"""Macro-model speed (pytest-benchmark). Run: ``pytest -m benchmark --benchmark-enable tests/benchmarks``.

Targets: <= 1 ms per wall with all hinge storeys; >= 300,000
three-storey walls/s through :func:`macro.sweep` on one core.
Pin to one core when measuring: ``OMP_NUM_THREADS=1 taskset -c 0 pytest ...``.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray
from pytest_benchmark.fixture import BenchmarkFixture

import macro
from comparison.domain.cases import case

pytestmark = pytest.mark.benchmark

WALLS = 100_000

# Least Eq. (10) over every hinge of the first six walls of each batch, by a
# 400,001-point brute force per hinge (plus kinks and ends of Eq. 11).
# Eq. (10)'s minimum of the paper's sets (as pinned in tests/macro/test_paper_tables.py).
PAPER_SETS = {"12": 0.648067, "Ref": 0.582516, "15": 0.611827}
BRUTE_FORCE = {
    1: [0.2503138672683, 0.2502944867429, 0.2871926062186, 0.2061755130695, 0.5847033885751, 0.5547087585032],
    3: [0.2500642869084, 0.250060252234, 0.2651494567335, 0.2586303469897, 0.5738706130781, 0.5502099491342],
    5: [0.250027162821, 0.2500254437457, 0.2686992009657, 0.2728249160555, 0.5720315124822, 0.5494246838243],
}


@pytest.mark.benchmark(group="macro-one-wall")
@pytest.mark.parametrize("name", list(PAPER_SETS))
def test_one_wall_all_hinges(benchmark: BenchmarkFixture, name: str) -> None:
    wall = case(name).spec().to_macro()
    r = benchmark(macro.solve, wall)
    assert len(r.hinges) == wall.storeys and r.status == "optimal"
    assert r.rocking_load_factor == pytest.approx(PAPER_SETS[name], rel=1e-6, abs=5e-7)


def _walls(n: int, storeys: int) -> dict[str, NDArray[np.float64]]:
    rng = np.random.default_rng(2018)
    t, m = rng.uniform(0.5, 3.0, n), rng.choice([1 / 3, 0.5, 1.0], n)
    rows = storeys * rng.choice([4, 12, 20], n)
    f, p = rng.uniform(0.4, 0.9, n), rng.uniform(0.0, 8.0, n)
    # a wall at least one block long (t <= rows m, the physical bounds of
    # macro.checks): 12 % of the one-storey draws are shorter and get that length
    return dict(t=np.minimum(t, rows * m), m=m, rows=rows, f=f, p=p)


@pytest.mark.benchmark(group="macro-sweep-100k")
@pytest.mark.parametrize("storeys", [1, 3, 5])
def test_sweep_100k_walls(benchmark: BenchmarkFixture, storeys: int) -> None:
    walls = _walls(WALLS, storeys)
    macro.sweep(1.0, 1 / 3, 12 * storeys, 0.6, storeys=storeys)  # compiled code loaded before timing
    args = tuple(walls[k] for k in ("t", "m", "rows", "f", "p"))
    r = benchmark.pedantic(macro.sweep, args=args, kwargs=dict(storeys=storeys), rounds=5, iterations=1)
    if benchmark.stats is not None:  # None when benchmarks are disabled
        benchmark.extra_info["walls_per_second"] = WALLS / benchmark.stats.stats.median
    np.testing.assert_allclose(r.rocking_load_factor[:6], BRUTE_FORCE[storeys], rtol=1e-10)
    assert np.all(np.isfinite(r.load_factor))
    assert np.all(r.load_factor <= walls["f"])
