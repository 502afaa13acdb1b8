"""Build the report: plan, compute, render.

:func:`build_report` makes the :class:`~comparison.report.plan.Plan` (every
wall and method the report needs), computes the missing cache entries of the
plan in parallel processes, reads the whole plan into
:class:`~comparison.report.results.Results`, and renders the tables, figures
and text from them into ``REPORT.md``, one CSV per table, ``report.json`` (every
number shown) and the figures.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from comparison.outputs import writable_directory
from comparison.report import figures
from comparison.report.findings import findings
from comparison.report.plan import build_plan
from comparison.report.results import Results, compute
from comparison.report.tables import all_tables
from comparison.report.text import document
from comparison.report.timings import machine, write_timings
from comparison.runner import MACRO, Runner, prefetch


def build_report(
    out_dir: Path,
    *,
    quick: bool = False,
    cache_dir: Path | None,
    progress: Callable[[str], None] | None = None,
    workers: int | None = None,
) -> Path:
    """Compute everything and write ``REPORT.md``, CSVs, ``report.json`` and the figures.

    Args:
        out_dir: where to write.
        quick: small walls only for the micro model.
        cache_dir: the result cache (``None``: no cache; everything is computed
            in this process). The command line's default is
            :func:`comparison.runner.default_cache_dir`.
        progress: called with one line per computation.
        workers: processes for the missing micro computations (default: the number of CPUs).

    Returns:
        The path of ``REPORT.md``.

    Raises:
        ValueError: ``out_dir`` or ``cache_dir`` cannot be written (checked before any work).
    """
    start = time.perf_counter()
    writable_directory("out_dir", out_dir)
    if cache_dir is not None:
        writable_directory("cache_dir", cache_dir)
    plan = build_plan(quick)
    runner = Runner(cache_dir, progress)
    runs = [it for it in plan.items() if not it.skip]
    pending = [] if runner.cache is None else plan.pending(runner.cache)
    computed = 0
    if cache_dir is not None:
        computed = prefetch(
            cache_dir, [(it.spec, it.method) for it in pending], workers or os.cpu_count() or 1, progress
        )
    results = compute(plan, runner)
    meta = {"quick": quick, "methods": [m.label for m in [MACRO, *plan.methods]]}
    run = {
        **machine(),
        "computed": computed + runner.computed,
        "cached": len(runs) - len(pending) if cache_dir is not None else 0,
    }
    path = _write(results, out_dir, meta)
    write_timings(results, out_dir, {**run, "seconds": time.perf_counter() - start})
    return path


def _write(res: Results, out: Path, meta: Mapping[str, Any]) -> Path:
    """Render the tables, figures and text of ``res`` into ``out`` (run times: :mod:`~comparison.report.timings`)."""
    tables = all_tables(res)
    figure_names = [
        figures.sensitivity_figure(res, out / "sensitivity.png").name,
        figures.speed_figure(res, out / "speed_accuracy.png").name,
    ]
    hist = figures.histories_figure(res, out / "histories.png")
    if hist is not None:
        figure_names.append(hist.name)
    mechanisms = figures.mechanism_figures(res, out)
    for tb in tables.values():
        tb.write_csv(out / f"{tb.name}.csv")
    (out / "report.json").write_text(
        json.dumps({"meta": meta, "tables": {k: v.records() for k, v in tables.items()}}, indent=1, default=str)
    )
    path = out / "REPORT.md"
    path.write_text(document(res, tables, findings(res), figure_names, mechanisms, meta))
    return path
