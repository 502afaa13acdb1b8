"""Two routes to cheaper LPs on Set 9, measured in CPU seconds of one process (the page of the same name).

    .venv/bin/python docs/research/2026-11-29-dual-edge-weights.py pricing ROUNDS WALL [WALL ...]
    .venv/bin/python docs/research/2026-11-29-dual-edge-weights.py fused-start WALL

``pricing``: the non-associative method with HiGHS' dual edge weights as the package sets them (HiGHS'
own choice, dual steepest edge) and with devex, interleaved per wall. ``fused-start``: the fused wall's
normal forces as the start of the wall's own chain, then the descent. ``WALL`` is a case of the paper
(``Ref``, ``9``, ``14``), with ``:fl`` for frictionless head joints and ``:half`` for a half block first.
Run it with one BLAS/OpenMP thread (``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1``), one process per core.
"""

from __future__ import annotations

import dataclasses
import statistics
import sys
import time
from typing import Any

import numpy as np

import micro.backends.highs as highs
from comparison.domain.cases import case
from micro.lp import assemble
from micro.nonassociative import NonAssociativeOptions, Tuning, lowest_state, resolve, solve_nonassociative
from micro.nonassociative.pipeline import run_stages

#: ``simplex_dual_edge_weight_strategy``: HiGHS' own choice (dual steepest edge; the package's) and devex.
STEEPEST, DEVEX = -1, 1
_STRATEGY = [STEEPEST]
_OPTIONS = highs.PersistentHighsModel._simplex_tolerances  # the options of every simplex run


def _with_strategy(h: Any) -> None:
    _OPTIONS(h)
    h.setOptionValue("simplex_dual_edge_weight_strategy", _STRATEGY[0])


def wall_of(spec: str) -> Any:
    """The paper's wall ``spec`` (``9``, ``14:fl``, ``14:half``)."""
    name, _, variant = spec.partition(":")
    kw = {"first_course": "half"} if "half" in variant else {}
    if "fl" in variant:
        kw["head_joints"] = "frictionless"
    return case(name).spec().to_micro(**kw)


def one(wall: Any, strategy: int) -> tuple[float, float, int]:
    """CPU seconds, the value quoted and the LPs (sequences and descent) with ``strategy``."""
    _STRATEGY[0] = strategy
    t = time.process_time()
    r = solve_nonassociative(wall)
    seconds = time.process_time() - t
    lps = sum(d.iterations for d in r.directions) + sum(low.lps for low in r.lowest)
    return seconds, r.load_factor, lps


def pricing(rounds: int, names: list[str]) -> None:
    highs.PersistentHighsModel._simplex_tolerances = staticmethod(_with_strategy)  # type: ignore[method-assign]
    for spec in names:
        wall = wall_of(spec)
        runs: dict[int, list[tuple[float, float, int]]] = {STEEPEST: [], DEVEX: []}
        for k in range(rounds):
            for strategy in (STEEPEST, DEVEX) if k % 2 == 0 else (DEVEX, STEEPEST):
                runs[strategy].append(one(wall, strategy))
        before = statistics.median(r[0] for r in runs[STEEPEST])
        now = statistics.median(r[0] for r in runs[DEVEX])
        (_, lam_b, lps_b), (_, lam_n, lps_n) = runs[STEEPEST][0], runs[DEVEX][0]
        print(f"{spec} {wall.n_blocks} blocks: steepest edge {before:.3f} s, devex {now:.3f} s "
              f"(ratio {now / before:.3f}); lambda {lam_b!r} -> {lam_n!r} ({(lam_n - lam_b) / lam_b:+.2e}); "
              f"LPs {lps_b} -> {lps_n}", flush=True)


def fused_start(spec: str) -> None:
    wall = wall_of(spec)
    t = time.process_time()
    fused = solve_nonassociative(wall, lowest=False, tuning=Tuning(fuse=True))
    print(f"the fused wall: {time.process_time() - t:.1f} s, lambda {fused.load_factor!r}", flush=True)
    resolved = dataclasses.replace(resolve(wall.n_blocks, NonAssociativeOptions(), None), fuse=False, reduce=False)
    lp = assemble(wall)
    for d in fused.directions:
        t1 = time.process_time()
        res, model = run_stages(lp, 1 if d.direction == "+x" else -1, resolved, np.asarray(d.normal) / lp.force_scale)
        t2 = time.process_time()
        print(f"the wall's chain {d.direction}: {t2 - t1:.1f} s, {res.iterations} LPs, lambda {res.load_factor!r}, "
              f"{res.status}", flush=True)
        low = lowest_state(lp, res, resolved, model, proposals=model is not None, searched=False)
        print(f"the descent: {time.process_time() - t2:.1f} s, {low.lps} LPs, lambda {low.load_factor!r}", flush=True)
    print(f"in all: {time.process_time() - t:.1f} s", flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "pricing":
        pricing(int(sys.argv[2]), sys.argv[3:])
    else:
        fused_start(sys.argv[2])
