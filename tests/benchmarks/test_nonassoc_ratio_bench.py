"""The report's non-associative solve against its associative solve of the same wall, in one run.

Each benchmark runs what ``xcheck report`` computes for one Table 5 wall
(:func:`comparison.runner.runner.compute` with the report's two micro
methods, :func:`comparison.report.plan.micro_methods`): per round the
associative computation, then the non-associative one, each timed with
``time.perf_counter``; the benchmark's own figure is the round. It records in
``benchmark.extra_info`` the median seconds of each and their ratio
(``ratio``: non-associative / associative, whole computation against whole
computation), with what the iterated LP reached (status, LPs, lambda).

* ``ratio-1230``: the reference wall (1,230 blocks; the vertex sequence
  converges), three rounds;
* ``ratio-1230`` (``slow``): Set 2 (1,230 blocks, f = 0.8; the vertex
  sequence cycles, the proximal one certifies), one round;
* ``ratio-1830`` (``slow``): Set 9 (1,830 blocks, m = 1/2), one round;
* ``ratio-3630`` (``slow``): Set 10 (3,630 blocks, m = 1; the fused wall with
  the continuation), one round.

Run them apart (the fast suite deselects them)::

    pytest -m "benchmark and not slow" --benchmark-enable tests/benchmarks/test_nonassoc_ratio_bench.py
    pytest -m slow --benchmark-enable tests/benchmarks/test_nonassoc_ratio_bench.py

Every cap of the iterated LP counts LPs, never seconds: every machine runs
the same LPs. Each benchmark asserts that the iterated LP converged, that
its state passes :func:`micro.verify_collapse_state`, and that its load
factor lies at or below the associative one.
"""

from __future__ import annotations

import statistics
import time
from typing import Any

import pytest

import micro
from comparison.domain.cases import case
from comparison.report.plan import micro_methods
from comparison.runner.runner import compute

#: Residual bounds of a certified state (:func:`micro.verify_collapse_state`).
STATE_BOUNDS = {"equilibrium": 1e-6, "coulomb": 1e-9, "interpenetration": 1e-3, "dilatancy": 1e-6,
                "slip_off_yield": 1e-9, "energy": 1e-6}


def _ratio(benchmark: Any, monkeypatch: pytest.MonkeyPatch, name: str, rounds: int) -> None:
    """One round: the report's associative computation of the wall, then its
    non-associative one, each timed; the benchmark's figure is the round."""
    assoc_method, nonassoc_method = micro_methods()
    spec = case(name).spec()
    seconds: dict[str, list[float]] = {"assoc": [], "nonassoc": []}
    kept: dict[str, Any] = {}
    solve = micro.solve_nonassociative

    def keep(*args: Any, **kwargs: Any) -> micro.NonAssociativeResult:  # the result, for its state
        kept["result"] = solve(*args, **kwargs)
        return kept["result"]

    monkeypatch.setattr(micro, "solve_nonassociative", keep)

    def one_round() -> tuple[Any, Any]:
        t0 = time.perf_counter()
        assoc = compute(spec, assoc_method)[0]
        t1 = time.perf_counter()
        nonassoc = compute(spec, nonassoc_method)[0]
        seconds["assoc"].append(t1 - t0)
        seconds["nonassoc"].append(time.perf_counter() - t1)
        return assoc, nonassoc

    assoc, nonassoc = benchmark.pedantic(one_round, rounds=rounds, iterations=1, warmup_rounds=0)
    a, n = statistics.median(seconds["assoc"]), statistics.median(seconds["nonassoc"])
    r = kept["result"]
    benchmark.extra_info.update(
        wall=name, blocks=r.blocks, status=r.status, load_factor=r.load_factor, iterations=r.iterations,
        stop_reason=r.sequence.stop_reason, selection=nonassoc.result.selection,
        associative_load_factor=assoc.result.load_factor, associative_seconds=a, nonassociative_seconds=n,
        ratio=n / a,
    )
    assert r.converged, r.message
    assert r.load_factor <= assoc.result.load_factor * (1 + 1e-6)
    lp = micro.assemble(spec.to_micro())
    v = micro.verify_collapse_state(lp, r.governing)
    assert all(v[k] <= bound for k, bound in STATE_BOUNDS.items()), v


@pytest.mark.benchmark(group="ratio-1230")
def test_bench_ratio_ref(benchmark: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """The reference wall: the vertex sequence converges (9 LPs)."""
    _ratio(benchmark, monkeypatch, "Ref", 3)


@pytest.mark.slow
@pytest.mark.parametrize(
    "case",
    [
        pytest.param("2", marks=pytest.mark.benchmark(group="ratio-1230"), id="set2-vertex-cycles-proximal-certifies"),
        pytest.param("9", marks=pytest.mark.benchmark(group="ratio-1830"), id="set9-vertex-cycles-proximal-certifies"),
        pytest.param("10", marks=pytest.mark.benchmark(group="ratio-3630"), id="set10-fused-with-continuation"),
    ],
)
def test_bench_ratio_slow(benchmark: Any, monkeypatch: pytest.MonkeyPatch, case: str) -> None:
    """Sets 2 and 9 (the vertex sequence cycles, the proximal one certifies) and Set 10 (the fused
    wall with the continuation), one round each."""
    _ratio(benchmark, monkeypatch, case, 1)
