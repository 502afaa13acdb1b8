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

* ``ratio-per-wall`` (``slow``): every wall of the full report that runs both
  methods (36 walls: Table 5 up to Set 10, Table 7's walls in their four
  bonds, the rows and sensitivity sweeps of the base wall), each pair timed
  in CPU seconds (``time.process_time``), interleaved, five rounds on walls of
  at most :data:`ROUNDS_UP_TO` blocks (their associative LP takes
  hundredths of a second, where one run's timing is noise) and one round
  above; records the median ratio per wall and the median, 90th percentile
  and largest over the walls (issue 55's per-wall target), and, with the
  report's other computations of either method timed once, the ratio of the
  sums over the report (``report_sum_ratio``).

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


#: Walls of at most this many blocks are timed in :data:`PER_WALL_ROUNDS` rounds (``ratio-per-wall``).
ROUNDS_UP_TO = 500
PER_WALL_ROUNDS = 5


@pytest.mark.slow
@pytest.mark.benchmark(group="ratio-per-wall")
def test_bench_ratio_per_wall(benchmark: Any) -> None:
    """The report's walls with both methods, each pair interleaved in CPU seconds (module docstring)."""
    import numpy as np

    from comparison.report.plan import build_plan

    pairs: dict[tuple[Any, str, str], dict[str, Any]] = {}
    for item in build_plan().items():
        m = item.method
        if item.skip:
            continue
        role = ("assoc" if m.kind == "micro-assoc" and m.solver == micro.DEFAULT_SOLVER
                else "nonassoc" if m.kind == "micro-nonassoc" and not m.tuning else None)
        if role is not None:
            pairs.setdefault((item.spec, m.first_course, m.head_joints), {})[role] = m
    walls = [(key, methods) for key, methods in pairs.items() if len(methods) == 2]
    compute(case("12").spec(), walls[0][1]["nonassoc"])  # imports and compiled kernels, untimed

    def cpu(spec: Any, method: Any) -> float:
        t0 = time.process_time()
        rec = compute(spec, method)[0]
        assert not rec.skipped and rec.result is not None, rec.message
        assert rec.result.status in {"optimal", "converged"}, (spec.name, rec.result.status)
        return time.process_time() - t0

    singles = [(key[0], m) for key, methods in pairs.items() if len(methods) == 1 for m in methods.values()]

    def all_walls() -> tuple[list[tuple[str, int, float, float]], dict[str, float]]:
        rows = []
        for (spec, first, heads), methods in walls:
            blocks = spec.to_micro(first_course=first, head_joints=heads).n_blocks
            a, n = [], []
            for _ in range(PER_WALL_ROUNDS if blocks <= ROUNDS_UP_TO else 1):
                a.append(cpu(spec, methods["assoc"]))
                n.append(cpu(spec, methods["nonassoc"]))
            rows.append((f"{spec.name} ({first}, {heads})", blocks, statistics.median(a), statistics.median(n)))
        # the report's other computations of either method (Table 9's and the speed walls' associative LPs,
        # the rows sweep's bonds' non-associative ones), once each, for the sum over the report
        alone = {"micro-assoc": 0.0, "micro-nonassoc": 0.0}
        for spec, m in singles:
            alone[m.kind] += cpu(spec, m)
        return rows, alone

    rows, alone = benchmark.pedantic(all_walls, rounds=1, iterations=1, warmup_rounds=0)
    ratios = sorted((n / a, name) for name, _, a, n in rows)
    median, p90 = np.quantile([r for r, _ in ratios], [0.5, 0.9])
    sum_a, sum_n = sum(a for *_, a, _ in rows), sum(n for *_, n in rows)
    benchmark.extra_info.update(
        walls=len(rows), median_ratio=float(median), p90_ratio=float(p90), largest=ratios[-1],
        sum_ratio=sum_n / sum_a,
        report_computations=[len(rows) + sum(m.kind == "micro-nonassoc" for _, m in singles),
                             len(rows) + sum(m.kind == "micro-assoc" for _, m in singles)],
        report_sum_ratio=(sum_n + alone["micro-nonassoc"]) / (sum_a + alone["micro-assoc"]),
        per_wall={name: {"blocks": b, "assoc_cpu": a, "nonassoc_cpu": n, "ratio": n / a} for name, b, a, n in rows},
    )
    assert len(rows) == 36 and benchmark.extra_info["report_computations"] == [51, 42], (len(rows), len(singles))
    assert all(a > 0 and n > 0 for *_, a, n in rows)
