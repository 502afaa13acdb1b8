"""Build the report: plan, compute, render.

:func:`build_report` makes the :class:`~comparison.report.plan.Plan` (every
wall and method the report needs), computes the missing cache entries of the
plan in local worker processes (:class:`~comparison.runner.executor.LocalExecutor`,
with a progress bar), reads the whole plan into
:class:`~comparison.report.results.Results`, and renders the tables, figures
and text from them into ``REPORT.md``, one CSV per table, ``report.json`` (every
number shown) and the figures.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from comparison.outputs import writable_directory
from comparison.progress import NORMAL, Progress
from comparison.report import bond, errormap, figures, lowest
from comparison.report.findings import findings
from comparison.report.mechanisms import mechanism_figures
from comparison.report.plan import build_plan
from comparison.report.results import Results, compute
from comparison.report.scaling import scaling_figure
from comparison.report.tables import all_tables
from comparison.report.text import document
from comparison.report.timings import write_timings
from comparison.runner import MACRO, Prefetched, Runner, prefetch
from comparison.runner.executor import LocalExecutor


def build_report(
    out_dir: Path,
    *,
    quick: bool = False,
    cache_dir: Path | None,
    verbosity: int = NORMAL,
    workers: int | None = None,
) -> Path:
    """Compute everything and write ``REPORT.md``, CSVs, ``report.json`` and the figures.

    Args:
        out_dir: where to write.
        quick: small walls only for the micro model.
        cache_dir: the result cache (``None``: no cache; everything is computed
            in this process). The command line's default is
            :func:`comparison.runner.default_cache_dir`.
        verbosity: what the progress display shows (see :mod:`comparison.progress`).
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
    runs = [it for it in plan.items() if not it.skip]
    processes = workers or os.cpu_count() or 1
    with Progress(verbosity) as progress:
        runner = Runner(cache_dir, progress.advance)
        pending = runs if runner.cache is None else plan.pending(runner.cache)
        progress.say(
            f"plan: {len(plan.macro_specs())} macro solves and {len(runs)} micro computations: "
            f"{len(runs) - len(pending)} cached, {len(pending)} to compute"
            + ("" if runner.cache is None else f" in {processes} processes")
        )
        progress.start(len(pending), "micro")
        prefetched = Prefetched()
        if runner.cache is not None and pending:
            with LocalExecutor(processes) as executor:
                prefetched = prefetch(runner.cache, [(it.spec, it.method) for it in pending], executor, progress)
            runner.keep(prefetched.unstored)
        results = compute(plan, runner)
    meta = {"quick": quick, "methods": [m.label for m in [MACRO, *plan.methods]]}
    run = {
        "computed": prefetched.computed + runner.computed,
        "cached": len(runs) - len(pending) if cache_dir is not None else 0,
    }
    path = _write(results, out_dir, meta)
    write_timings(results, out_dir, {**run, "seconds": time.perf_counter() - start})
    return path


def _write(res: Results, out: Path, meta: Mapping[str, Any]) -> Path:
    """Render the tables, figures and text of ``res`` into ``out`` (run times: :mod:`~comparison.report.timings`)."""
    tables = all_tables(res)
    hist = figures.histories_figure(res, out / "histories.png")
    scaling = scaling_figure(res, out / "scaling.png")
    figure_list = [
        figures.sensitivity_figure(res, out / "sensitivity.png"),
        figures.speed_figure(res, out / "speed_accuracy.png"),
        *([] if hist is None else [hist]),
        *([] if scaling is None else [scaling]),
        *mechanism_figures(res, out),
    ]
    for tb in tables.values():
        tb.write_csv(out / f"{tb.name}.csv")
    error_map, error_numbers = errormap.write(out, number=len(figure_list) + 1)
    lowest_number = len(figure_list) + (2 if error_numbers else 1)
    bond_text, bond_rows = bond.section()
    tables_json = {k: v.records() for k, v in tables.items()}
    (out / "report.json").write_text(json.dumps(
        {"meta": meta, "tables": tables_json, "errormap": error_numbers, "table9_bond": bond_rows},
        indent=1, default=str,
    ))
    path = out / "REPORT.md"
    text = document(res, tables, findings(res), figure_list, meta)
    path.write_text(text + "\n" + error_map + "\n" + bond_text + "\n" + lowest.section(out=out, number_=lowest_number))
    return path
