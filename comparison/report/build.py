"""Build the report: plan, compute, render.

:func:`build_report` makes the :class:`~comparison.report.plan.Plan` (every
wall and method the report needs), computes the missing cache entries of the
plan on an executor (local worker processes,
:class:`~comparison.runner.executor.LocalExecutor`, or a Dask cluster, with a progress
display whose ETA weighs each computation by its expected cost), reads the whole plan into
:class:`~comparison.report.computed.Results`, and renders the tables, figures
and text from them into ``REPORT.md``, one CSV per table, ``report.json`` (every
number shown) and the figures, section by section (:mod:`comparison.report.sections`);
the sections of the tables committed with the report read them from its tables
directory (:mod:`comparison.report.committed`).
"""

from __future__ import annotations

import contextlib
import json
import os
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from comparison.report.committed import BOND, ERRORMAP, LOWEST, check_tables, committed_table, missing
from comparison.report.computed import Results, compute
from comparison.report.plan import build_plan
from comparison.report.robustness import bond_variants_table, robustness_table
from comparison.report.sections import Body, Bond, ErrorMap, Lowest, Section, render
from comparison.report.speed_accuracy import speed_accuracy
from comparison.report.tables import (
    Table,
    all_cases,
    failure_modes,
    histories,
    sensitivity,
    table5,
    table7,
    table8,
    table9,
)
from comparison.report.timings import previous_seconds, write_timings
from comparison.runner import MACRO, Prefetched, Runner, prefetch
from comparison.runner.executor import Executor, LocalExecutor
from comparison.utilities.outputs import writable_directory, write_text
from comparison.utilities.progress import NORMAL, Progress


def build_report(
    out_dir: Path,
    *,
    quick: bool = False,
    cache_dir: Path | None,
    verbosity: int = NORMAL,
    workers: int | None = None,
    tables_dir: Path | None = None,
    executor: Executor | None = None,
) -> Path:
    """Compute everything and write ``REPORT.md``, CSVs, ``report.json`` and the figures.

    Args:
        out_dir: where to write.
        quick: small walls only for the micro model.
        cache_dir: the result cache (``None``: no cache; everything is computed
            in this process). The command line's default is
            :func:`comparison.runner.default_cache_dir`.
        verbosity: what the progress display shows (see :mod:`comparison.utilities.progress`).
        workers: processes for the missing micro computations (default: the number of CPUs).
        executor: where the missing micro computations run instead (e.g. a
            :class:`~comparison.runner.executor.cluster.DaskExecutor`; the caller opens and closes it);
            needs ``cache_dir`` (the results come back through the cache).
        tables_dir: where the committed tables the report reads and does not recompute are
            (:mod:`comparison.report.committed`; default ``out_dir``); a missing one is a warning and
            its section says so.

    Returns:
        The path of ``REPORT.md``.

    Raises:
        ValueError: ``out_dir`` or ``cache_dir`` cannot be written, a committed table of ``tables_dir``
            cannot be read whole (:class:`~comparison.report.committed.BadTable`; checked before any work), or
            an ``executor`` without ``cache_dir``.
        comparison.runner.executor.cluster.ClusterError: the executor's scheduler went away (what finished
            is in the cache).
    """
    start = time.perf_counter()
    writable_directory("out_dir", out_dir)
    check_tables(out_dir if tables_dir is None else Path(tables_dir))
    if cache_dir is not None:
        writable_directory("cache_dir", cache_dir)
    elif executor is not None:
        raise ValueError("executor: the report needs its cache_dir to take the results back")
    plan = build_plan(quick)
    runs = [it for it in plan.items() if not it.skip]
    processes = workers or os.cpu_count() or 1
    where = executor.where if executor is not None else f"{processes} processes"
    with Progress(verbosity) as progress:
        runner = Runner(cache_dir, progress.advance)
        pending = runs if runner.cache is None else plan.pending(runner.cache)
        progress.say(
            f"plan: {len(plan.macro_specs())} macro solves and {len(runs)} micro computations: "
            f"{len(runs) - len(pending)} cached, {len(pending)} to compute"
            + ("" if runner.cache is None else f" on {where}")
        )
        prefetched = Prefetched()
        if runner.cache is not None and pending:
            items = [(it.spec, it.method) for it in pending]
            known = previous_seconds(out_dir, items)
            with LocalExecutor(processes) if executor is None else contextlib.nullcontext(executor) as ex:
                prefetched = prefetch(runner.cache, items, ex, progress, cached=len(runs) - len(pending), known=known)
            runner.keep(prefetched.unstored)
        else:
            progress.start(len(pending), "micro", cached=len(runs) - len(pending))
        results = compute(plan, runner)
        progress.close()
        meta = {"quick": quick, "methods": [m.label for m in [MACRO, *plan.methods]]}
        run = {
            "computed": prefetched.computed + runner.computed,
            "cached": len(runs) - len(pending) if cache_dir is not None else 0,
        }
        written = time.time()
        path = _write(results, out_dir, meta, out_dir if tables_dir is None else Path(tables_dir))
        write_timings(results, out_dir, {**run, "seconds": time.perf_counter() - start},
                      computed={(it.spec, it.method) for it in pending})
        progress.say(written_files(out_dir, since=written))
    return path


def written_files(out: Path, since: float) -> str:
    """The line saying what a run wrote into ``out``: the files modified since ``since`` (``time.time()``)."""
    names = sorted(p.name for p in out.iterdir() if p.is_file() and p.stat().st_mtime >= since - 1.0)
    main = [n for n in ("REPORT.md", "report.json", "timings.md") if n in names]
    csv = sum(n.endswith(".csv") for n in names)
    png = sum(n.endswith(".png") for n in names)
    return f"wrote {len(names)} files into {out}: {', '.join(main)}, {csv} CSV tables, {png} figures"


def sections(res: Results, meta: Mapping[str, Any], tables_dir: Path) -> list[Section]:
    """The report's sections in their order: its body, then those of the committed tables in ``tables_dir``
    (a missing one: :func:`~comparison.report.committed.committed_table` warns and its section says so)."""
    return [
        Body(res, all_tables(res), meta),
        ErrorMap(committed_table(tables_dir, ERRORMAP), missing(tables_dir, ERRORMAP)),
        Bond(committed_table(tables_dir, BOND), missing(tables_dir, BOND)),
        Lowest(committed_table(tables_dir, LOWEST), missing(tables_dir, LOWEST)),
    ]


def _write(res: Results, out: Path, meta: Mapping[str, Any], tables_dir: Path) -> Path:
    """Render the sections of ``res`` into ``out`` (run times: :mod:`~comparison.report.timings`), those of
    the committed tables from ``tables_dir``: ``REPORT.md``, ``report.json``, the CSVs and the figures."""
    text, records = render(sections(res, meta, tables_dir), out)
    write_text(out / "report.json", json.dumps({"meta": meta, **records}, indent=1, default=str))
    path = out / "REPORT.md"
    write_text(path, text)
    return path


def all_tables(res: Results) -> dict[str, Table]:
    """Every table of the report, by name."""
    builders = (
        table5,
        table7,
        bond_variants_table,
        table8,
        table9,
        all_cases,
        failure_modes,
        sensitivity,
        speed_accuracy,
        histories,
    )
    tables = [build(res) for build in builders]
    robust = robustness_table(res)
    return {t.name: t for t in (*tables, *([robust] if robust is not None else []))}
