"""Speed of the associative LP at its floor: the ``clarabel`` back end (kinematic form).

Each benchmark times ``micro.solve_associative(wall, solver="clarabel")`` (LP
assembly, back-end setup and one solve: the walls are mirror-symmetric) and
asserts the load factor it timed against the pinned reference of
``tests/micro/associative_reference.json`` to 1e-6 relative.

* ``assoc-1230``: the Table 5 reference wall (1,230 blocks), target <= 0.3 s;
* ``assoc-3630``: Set 10 (m = 1, 3,630 blocks);
* ``assoc-7575``: Set 15, the Table 9 wall (7,575 blocks), target <= 10 s;
  marked ``slow`` as well and run apart (one round).

Run on one core, as measured for the notes::

    export OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
    taskset -c 0 pytest -m "benchmark and not slow" --benchmark-enable tests/benchmarks/test_assoc_bench.py
    taskset -c 0 pytest -m slow --benchmark-enable tests/benchmarks/test_assoc_bench.py
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import micro
from comparison.wall import WallSpec

REFERENCE = json.loads((Path(__file__).parents[1] / "micro" / "associative_reference.json").read_text())["walls"]


def _bench(benchmark: Any, key: str, rounds: int) -> None:
    entry = REFERENCE[key]
    wall = WallSpec.from_paper(**entry["paper"]).to_micro()
    result = benchmark.pedantic(micro.solve_associative, args=(wall,), kwargs={"solver": "clarabel"},
                                rounds=rounds, iterations=1, warmup_rounds=0)
    d = result.directions[0]
    benchmark.extra_info.update(
        blocks=result.blocks, load_factor=result.load_factor, reference=entry["directions"]["1"]["load_factor"],
        reference_method=entry["method"], iterations=result.iterations, solve_seconds=result.solve_seconds,
        build_seconds=result.build_seconds, linear_solver=d.info.get("linear_solver"),
        fallback=d.info.get("fallback", ""),
    )
    assert result.ok and result.blocks == entry["blocks"]
    assert result.load_factor == pytest.approx(entry["directions"]["1"]["load_factor"], rel=1e-6)


@pytest.mark.benchmark(group="assoc-1230")
def test_assoc_1230(benchmark: Any) -> None:
    _bench(benchmark, "w1230 full frictional", rounds=7)


@pytest.mark.benchmark(group="assoc-3630")
def test_assoc_3630(benchmark: Any) -> None:
    _bench(benchmark, "w3630 full frictional", rounds=3)


@pytest.mark.slow
@pytest.mark.benchmark(group="assoc-7575")
def test_assoc_7575(benchmark: Any) -> None:
    _bench(benchmark, "w7575 full frictional", rounds=1)
