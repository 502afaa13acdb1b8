"""Speed of the associative LP at its floor: the ``normal-ipm`` back end (the suite's
interior point on the normal equations) against ``clarabel`` (Clarabel on the kinematic form).

Each benchmark times ``micro.solve_associative(wall, solver=...)`` (LP
assembly, back-end setup and one solve: the walls are mirror-symmetric) and
asserts the load factor it timed against the pinned reference of
``tests/micro/associative_reference.json`` to 1e-6 relative, and that the
``normal-ipm`` run needed no fallback.

* ``assoc-1230``: the Table 5 reference wall (1,230 blocks), target <= 0.3 s;
* ``assoc-3630``: Set 10 (m = 1, 3,630 blocks);
* ``assoc-7575``: Set 15, the Table 9 wall (7,575 blocks), target <= 10 s;
  marked ``slow`` as well and run apart (one round);
* ``assoc-set17``: Set 17, the same wall with floors p = 8: Clarabel's forces
  are polished onto equilibrium (:mod:`micro.backends.polish`), the
  ``normal-ipm``'s projected (:meth:`micro.backends.normal_ipm.NormalIpm.run`);
  no vertex reference exists: the (lower-bound) load factor is asserted
  within 1e-8 below Clarabel's kinematic objective, within 1e-7 of its own.
  ``slow``, one round;
* ``assoc-cli-7575``: the whole process of ``xcheck micro`` on Set 15 with no
  ``--solver`` (the library default, :data:`micro.DEFAULT_SOLVER`), asserting
  the back end it ran and lambda within 2e-6 of the reference (target: at
  most 20 s). ``slow``, one round.

The choice of the default back end: docs/research/2026-11-25-associative-default.md.

Run on one core, as measured for the notes::

    export OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
    taskset -c 0 pytest -m "benchmark and not slow" --benchmark-enable tests/benchmarks/test_assoc_bench.py
    taskset -c 0 pytest -m slow --benchmark-enable tests/benchmarks/test_assoc_bench.py
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

import micro
from comparison.domain.wall import WallSpec

REFERENCE = json.loads((Path(__file__).parents[1] / "micro" / "associative_reference.json").read_text())["walls"]


SOLVERS = ("normal-ipm", "clarabel")
#: Clarabel's (polished) load factor on Set 17, within 1e-8 of its kinematic objective (measured 2026-11-23).
SET17_CLARABEL = 0.4993532699


def _bench(benchmark: Any, key: str, rounds: int, solver: str) -> None:
    entry = REFERENCE[key]
    wall = WallSpec.from_paper(**entry["paper"]).to_micro()
    result = benchmark.pedantic(micro.solve_associative, args=(wall,), kwargs={"solver": solver},
                                rounds=rounds, iterations=1, warmup_rounds=0)
    d = result.directions[0]
    benchmark.extra_info.update(
        blocks=result.blocks, load_factor=result.load_factor, reference=entry["directions"]["1"]["load_factor"],
        reference_method=entry["method"], iterations=result.iterations, solve_seconds=result.solve_seconds,
        build_seconds=result.build_seconds, linear_solver=d.info.get("linear_solver"),
        fallback=d.info.get("fallback", ""),
    )
    assert result.ok and result.blocks == entry["blocks"] and "fallback" not in d.info
    assert result.load_factor == pytest.approx(entry["directions"]["1"]["load_factor"], rel=1e-6)


@pytest.mark.benchmark(group="assoc-1230")
@pytest.mark.parametrize("solver", SOLVERS)
def test_assoc_1230(benchmark: Any, solver: str) -> None:
    _bench(benchmark, "w1230 full frictional", rounds=7, solver=solver)


@pytest.mark.benchmark(group="assoc-3630")
@pytest.mark.parametrize("solver", SOLVERS)
def test_assoc_3630(benchmark: Any, solver: str) -> None:
    _bench(benchmark, "w3630 full frictional", rounds=3, solver=solver)


@pytest.mark.slow
@pytest.mark.benchmark(group="assoc-7575")
@pytest.mark.parametrize("solver", SOLVERS)
def test_assoc_7575(benchmark: Any, solver: str) -> None:
    _bench(benchmark, "w7575 full frictional", rounds=1, solver=solver)


@pytest.mark.slow
@pytest.mark.benchmark(group="assoc-set17")
@pytest.mark.parametrize("solver", SOLVERS)
def test_assoc_set17(benchmark: Any, solver: str) -> None:
    wall = WallSpec.from_paper(t=1.0, m=1 / 3, rows=150, f=0.75, p=8.0, storeys=5).to_micro()
    result = benchmark.pedantic(micro.solve_associative, args=(wall,), kwargs={"solver": solver},
                                rounds=1, iterations=1, warmup_rounds=0)
    d = result.directions[0]
    benchmark.extra_info.update(
        blocks=result.blocks, load_factor=result.load_factor, iterations=result.iterations,
        solve_seconds=result.solve_seconds, polish_seconds=d.info.get("polish_seconds"),
        unpolished_residual=d.info.get("unpolished_residual"), primal_residual=d.info.get("primal_residual"),
    )
    assert result.ok and result.blocks == 7575 and "fallback" not in d.info
    if solver == "clarabel":
        assert d.info["polish_steps"] >= 1
        upper = d.info["kinematic_load_factor"]
        assert upper * (1.0 - 1e-8) <= result.load_factor <= upper * (1.0 + 1e-12)
    else:
        assert d.info["primal_residual"] <= 1e-9
        assert result.load_factor == pytest.approx(d.info["kinematic_load_factor"], rel=1e-7)
        assert result.load_factor == pytest.approx(SET17_CLARABEL, rel=1e-6)


@pytest.mark.slow
@pytest.mark.benchmark(group="assoc-cli-7575")
def test_assoc_cli_7575(benchmark: Any) -> None:
    entry = REFERENCE["w7575 full frictional"]
    argv = [sys.executable, "-m", "comparison.cli", "micro", "--storeys", "5", "--rows", "150", "--t", "1",
            "--m", "1/3", "--f", "0.75", "--friction", "associative", "--json"]
    done = benchmark.pedantic(subprocess.run, args=(argv,), kwargs={"capture_output": True, "text": True},
                              rounds=1, iterations=1, warmup_rounds=0)
    out = json.loads(done.stdout)
    benchmark.extra_info.update(solver=out["solver"], load_factor=out["load_factor"],
                                solve_seconds=out["solve_seconds"], build_seconds=out["build_seconds"])
    assert done.returncode == 0 and out["solver"] == micro.DEFAULT_SOLVER and out["blocks"] == entry["blocks"]
    assert out["load_factor"] == pytest.approx(entry["directions"]["1"]["load_factor"], rel=2e-6)
