"""Macro-model speed (pytest-benchmark). Run: ``pytest -m benchmark --benchmark-enable tests/benchmarks``.

Targets (issue 2): <= 1 ms per wall with all hinge storeys; >= 100,000 walls/s
through the vectorised path on one core.
"""

from __future__ import annotations

import numpy as np
import pytest

import macro
from comparison.cases import case

pytestmark = pytest.mark.benchmark


@pytest.mark.benchmark(group="macro-one-wall")
@pytest.mark.parametrize("name", ["12", "Ref", "15"])
def test_one_wall_all_hinges(benchmark, name: str) -> None:  # type: ignore[no-untyped-def]
    wall = case(name).spec().to_macro()
    r = benchmark(macro.solve, wall)
    assert len(r.hinges) == wall.storeys and r.status == "optimal"


def _walls(n: int, storeys: int) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(2018)
    return dict(
        t=rng.uniform(0.5, 3.0, n),
        m=rng.choice([1 / 3, 0.5, 1.0], n),
        rows=storeys * rng.choice([4, 12, 20], n),
        f=rng.uniform(0.4, 0.9, n),
        p=rng.uniform(0.0, 8.0, n),
    )


@pytest.mark.benchmark(group="macro-sweep-100k")
@pytest.mark.parametrize("storeys", [1, 3])
def test_sweep_100k_walls(benchmark, storeys: int) -> None:  # type: ignore[no-untyped-def]
    walls = _walls(100_000, storeys)
    r = benchmark.pedantic(macro.sweep, kwargs=dict(storeys=storeys, **walls), rounds=3, iterations=1)
    assert np.all(np.isfinite(r.load_factor))
    assert np.all(r.load_factor <= walls["f"])
