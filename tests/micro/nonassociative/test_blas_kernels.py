"""The non-associative method's path does not depend on the BLAS kernel.

numpy, scipy and cvxopt bundle OpenBLAS built for every x86 CPU (DYNAMIC_ARCH), and
``OPENBLAS_CORETYPE`` makes it run another CPU's kernels: the way to see, on one machine, what
another machine would compute. Each run below is a fresh process under one kernel; the results
must be the same floats (not merely close): the load factors, the stop, and every force and
velocity of the states returned. A dot product or a factorisation by BLAS that decides a step
(``micro/exact.py``) makes them differ in the last bits, and on a chaotic path (Set 9) in the
state reached.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from micro.exact import exact_dot

ROOT = Path(__file__).resolve().parents[3]
#: The kernels compared: two named ones (an old SSE kernel and an AVX2 one) and the machine's own.
KERNELS = ("Prescott", "Haswell", "")

#: One solve in a fresh process: the kernels in use, the values and a digest of every state's arrays.
CHILD = """
import hashlib, json, sys
import numpy as np
from threadpoolctl import threadpool_info
import micro
from comparison.domain.cases import case
from micro.nonassociative import Tuning

name, knobs = sys.argv[1], json.loads(sys.argv[2])
tuning = Tuning(**knobs) if knobs else None
r = micro.solve_nonassociative(case(name).spec().to_micro(), tuning=tuning)
h = hashlib.sha1()
for d in [*r.directions, *(low.state for low in r.lowest)]:
    for a in (d.normal, d.shear, None if d.mechanism is None else d.mechanism.velocities):
        h.update(b"-" if a is None else np.ascontiguousarray(a, dtype=float).tobytes())
rec = r.to_record()
print(json.dumps({
    "kernels": sorted({str(i.get("architecture")) for i in threadpool_info() if i["internal_api"] == "openblas"}),
    "load_factor": repr(r.load_factor), "iterated_load_factor": repr(r.iterated_load_factor),
    "status": r.status, "lowest_stop": rec["lowest_stop"], "states": h.hexdigest(),
}))
"""


def solve_under(kernel: str, name: str, knobs: dict[str, object] | None = None) -> dict[str, object]:
    """:data:`CHILD` on the paper's case ``name`` with the tuning ``knobs`` in a process under ``kernel`` (``""``:
    the machine's)."""
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    if kernel:
        env["OPENBLAS_CORETYPE"] = kernel
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])
    out = subprocess.run([sys.executable, "-c", CHILD, name, json.dumps(knobs or {})], env=env, cwd=ROOT,
                         capture_output=True, text=True, check=True)
    result: dict[str, object] = json.loads(out.stdout.strip().splitlines()[-1])
    return result


def same_under_every_kernel(name: str, knobs: dict[str, object] | None = None) -> dict[str, object]:
    """The runs under :data:`KERNELS` agree; at least two of them ran other kernels. Returns one."""
    runs = [solve_under(k, name, knobs) for k in KERNELS]
    assert len({tuple(r.pop("kernels")) for r in runs}) >= 2, "OPENBLAS_CORETYPE changed no kernel"  # type: ignore[arg-type]
    for kernel, run in zip(KERNELS[1:], runs[1:], strict=True):
        assert run == runs[0], f"{kernel or 'default'} against {KERNELS[0]}"
    return runs[0]


def test_exact_dot_is_the_exactly_rounded_sum() -> None:
    """The products' sum rounded once, in any order (summed in order these give 1.5)."""
    a, b = [1e16, 1.0, -1e16, 3.0], [1.0, 1.0, 1.0, 0.5]
    assert exact_dot(a, b) == 2.5 == exact_dot(a[::-1], b[::-1])


@pytest.mark.processes
def test_the_proximal_sequence_and_descent_are_the_same_under_three_kernels() -> None:
    """Set 14 (150 blocks) by the proximal sequence (the default's second sequence) and the
    descent: the same load factors, stop and states, to the last bit, under Prescott's, Haswell's
    and the machine's kernels. The projection's factorisation and the mechanisms' normalisation
    are where they differed (CHOLMOD's supernodal kernels, ``ddot``)."""
    run = same_under_every_kernel("14", {"selection": "proximal"})
    assert run["status"] == "converged" and run["lowest_stop"] == "finished"


@pytest.mark.processes
def test_the_reduced_wall_is_the_same_under_three_kernels() -> None:
    """Set 13 (78 blocks) on the reduced wall (its models, their descents, the lifts and the exact field):
    the same state to the last bit under the three kernels."""
    run = same_under_every_kernel("13", {"reduce": True})
    assert run["status"] == "converged" and run["lowest_stop"] == "finished"


@pytest.mark.slow
@pytest.mark.benchmark
def test_set9_is_the_same_under_three_kernels() -> None:
    """Set 9 (1,830 blocks), the report's non-associative default (vertex sequence, proximal
    retry, descent), in three processes one after the other: the same value and stop under
    every kernel. Minutes each; run apart: ``pytest -m slow tests/micro/nonassociative/test_blas_kernels.py``."""
    run = same_under_every_kernel("9")
    assert run["status"] == "converged" and run["lowest_stop"] == "finished"


@pytest.mark.slow
@pytest.mark.benchmark
def test_set10_is_the_same_under_three_kernels() -> None:
    """Set 10 (3,630 blocks), the report's default (the reduced wall), in three processes: the same value, stop
    and states under every kernel."""
    run = same_under_every_kernel("10")
    assert run["status"] == "converged" and run["lowest_stop"] == "finished"
