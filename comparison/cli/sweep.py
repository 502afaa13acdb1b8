"""``xcheck sweep``: both models over a grid of walls, on local processes or a Dask cluster.

Example::

    xcheck sweep examples/sweeps/errormap.toml --out reports/sweeps --workers 2
    xcheck sweep examples/sweeps/tiny.toml --out /tmp/sweep --scheduler tcp://127.0.0.1:8786
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from comparison.cli.options import (
    EXIT_FAILED,
    UsageError,
    add_command,
    add_executor_options,
    add_scheduler_option,
    cache_directory,
    executor_from_args,
    in_range,
    output_directory,
    workers_from_args,
)

#: Bytes in a gigabyte (``--worker-memory`` is given in GB).
GB = 1e9
#: The largest ``--worker-memory`` (GB): a million gigabytes, beyond any machine (1e308 overflowed the
#: conversion to bytes: an OverflowError traceback).
MAX_WORKER_MEMORY_GB = 1e6


def _absolute(path: Path) -> Path:
    """``path`` from the root, whatever the working directory becomes later."""
    return Path(os.path.abspath(path))


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``sweep`` subcommand."""
    p = add_command(
        sub,
        "sweep",
        help="run the models over a grid of walls (local processes or a Dask cluster)",
        description="Reads a grid file (axes, bonds, methods; see examples/sweeps/) and writes into --out one "
        "CSV table, its JSON metadata and a validation page (NAME.md: summary, error map, scatter, histogram, "
        "worst walls, time against blocks, with its PNG figures). Micro results go through the result cache: "
        "a sweep run again computes only what is missing.",
    )
    p.add_argument("grid", metavar="GRID.toml", help="the grid file")
    p.add_argument("--out", required=True, metavar="DIR",
                   help="output directory (GRID's name .csv, .json, .md and its figures NAME-*.png)")
    p.add_argument("--no-report", action="store_true", help="write the table and metadata only, no page")
    add_executor_options(p)
    add_scheduler_option(p)
    p.add_argument(
        "--worker-memory",
        metavar="GB",
        help="memory one computation may use (default: the memory available over --workers, or the Dask "
        "workers' limit); walls whose estimate exceeds it are refused",
    )
    p.add_argument(
        "--cache",
        default=None,
        metavar="DIR",
        help="result cache directory (default: $XCHECK_CACHE, else $XDG_CACHE_HOME/xcheck, else ~/.cache/xcheck)",
    )
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck sweep``."""
    from comparison.runner import ResultCache
    from comparison.runner.executor.cluster import ClusterError
    from comparison.sweep import GridError, load_grid, run_sweep
    from comparison.utilities.progress import Progress

    # Every input is checked before a folder is made (bad input leaves nothing behind), and the output and
    # cache folders are absolute before the grid's user models (code that may change the working
    # directory) are imported or run.
    out = _absolute(output_directory("--out", args.out, create=False))
    cache_dir = _absolute(cache_directory(args.cache, create=False))
    try:
        grid = load_grid(args.grid)
    except GridError as exc:
        raise UsageError(str(exc)) from None
    workers = workers_from_args(args)
    memory = in_range("--worker-memory", args.worker_memory,
                      f"a positive number of gigabytes, at most {MAX_WORKER_MEMORY_GB:g}", MAX_WORKER_MEMORY_GB)
    executor = executor_from_args(workers, args.scheduler, None if memory is None else int(memory * GB))
    try:
        with executor, Progress(args.verbosity) as progress:
            output_directory("--out", out)  # made now, before an hour of computing, not after
            cache = ResultCache(cache_directory(str(cache_dir)))
            done = run_sweep(grid, out, cache=cache, executor=executor, progress=progress, page=not args.no_report)
    except ClusterError as exc:  # the scheduler went away mid-sweep: what finished is in the cache
        print(f"xcheck: error: --scheduler: {exc}", file=sys.stderr)
        return EXIT_FAILED
    print(f"table: {done.table}")
    print(f"meta: {done.meta}")
    if done.page is not None:
        print(f"page: {done.page}")
    return 1 if done.counts["failed"] else 0
