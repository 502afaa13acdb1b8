"""Every LP of the non-associative method on one wall: who ran it, how, and what it cost.

Run from the repository's root (seconds per small wall):

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python docs/research/2026-11-29-lp-trace.py 14 14:fl 1

A wall is a paper case's name (``Ref``, ``1`` .. ``14``), optionally followed by ``:half`` (the first
course starts with a half block), ``:fl`` (frictionless head joints) or ``:half,fl``. For each wall the
method runs twice (the first run pays the imports and is not shown); the second prints one line per
HiGHS run (CPU seconds, simplex / interior-point / crossover iterations, the model's rows, the status and
the last four frames of the method that asked for it), then the CPU seconds of the HiGHS runs, of
Clarabel's solves and of the whole method. Page: ``2026-11-29-lp-trace.md``.
"""

from __future__ import annotations

import sys
import time
import traceback
from typing import Any


def trace(spec: str) -> None:
    from comparison.domain.cases import case
    from micro.backends import clarabel, highs
    from micro.nonassociative import solve_nonassociative

    name, _, variant = spec.partition(":")
    options: dict[str, Any] = {}
    if "half" in variant:
        options["first_course"] = "half"
    if "fl" in variant:
        options["head_joints"] = "frictionless"
    wall = case(name).spec().to_micro(**options)
    runs: list[tuple[float, Any, int, str, str]] = []
    interior: list[float] = []
    highs_run, clarabel_run = highs.PersistentHighsModel.run, clarabel.ClarabelStaticBackend.solve

    def run(self: Any, *, presolve: bool = True) -> Any:
        t0 = time.process_time()
        out = highs_run(self, presolve=presolve)
        frames = [f.name for f in traceback.extract_stack()[:-1] if "nonassociative" in f.filename][-4:]
        runs.append((time.process_time() - t0, out, self._highs.getNumRow(), out.status.name, ">".join(frames)))
        return out

    def solve(self: Any, direction: int) -> Any:
        t0 = time.process_time()
        out = clarabel_run(self, direction)
        interior.append(time.process_time() - t0)
        return out

    solve_nonassociative(wall)
    highs.PersistentHighsModel.run, clarabel.ClarabelStaticBackend.solve = run, solve  # type: ignore[method-assign]
    try:
        t0 = time.process_time()
        result = solve_nonassociative(wall)
        total = time.process_time() - t0
    finally:
        highs.PersistentHighsModel.run, clarabel.ClarabelStaticBackend.solve = highs_run, clarabel_run  # type: ignore[method-assign]
    print(f"== {spec}: {wall.n_blocks} blocks, lambda {result.load_factor!r}, band {result.mechanism_band}")
    for seconds, out, rows, status, frames in runs:
        print(f"{seconds:8.4f} s  simplex {out.simplex_iterations:5d}  ipm {out.ipm_iterations:3d}  "
              f"crossover {out.crossover_iterations:4d}  rows {rows:5d}  {status:16s} {frames}")
    print(f"HiGHS: {len(runs)} runs, {sum(r[0] for r in runs):.3f} s; Clarabel: {len(interior)} solves, "
          f"{sum(interior):.3f} s; the method: {total:.3f} s CPU", flush=True)


if __name__ == "__main__":
    for spec in sys.argv[1:] or ["14"]:
        trace(spec)
