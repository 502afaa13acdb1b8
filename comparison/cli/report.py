"""``xcheck report``: run both models on the paper's cases and write ``reports/REPORT.md``."""

from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path

from comparison.cli.options import (
    EXIT_FAILED,
    UsageError,
    add_cache_options,
    add_command,
    add_executor_options,
    add_scheduler_option,
    cache_dir_from_args,
    executor_from_args,
    output_directory,
    workers_from_args,
)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``report`` subcommand."""
    p = add_command(
        sub,
        "report",
        help="recompute the paper's tables with both models and write reports/REPORT.md",
        description="Tables 5, 7, 8, 9 and beyond, failure modes, sensitivity and speed-accuracy figures.",
    )
    p.add_argument("--out", default="reports", help="output directory (default: reports)")
    p.add_argument(
        "--tables",
        default=None,
        metavar="DIR",
        help="where the committed tables the report reads and does not recompute are (sweeps/errormap.csv, "
        "sweeps/table9_bond.csv, lowest.csv; default: the --out directory); a missing one is a warning",
    )
    p.add_argument("--quick", action="store_true", help="the micro model on the small walls only (under a minute)")
    add_cache_options(p)
    add_executor_options(p)
    add_scheduler_option(p)
    p.set_defaults(handler=run)


def readable_directory(option: str, path: str) -> Path:
    """``path`` as an existing directory.

    Raises:
        UsageError: empty, missing or not a directory.
    """
    if not path.strip():
        raise UsageError(f"{option} must name a directory, got {path!r}")
    if not Path(path).is_dir():
        raise UsageError(f"{option}: {path!r} is not a directory")
    return Path(path)


def run(args: argparse.Namespace) -> int:
    """Write the report and say where it is.

    ``args.verbosity`` is the setting the progress display follows
    (:mod:`comparison.utilities.progress`).
    """
    from comparison.report import build_report
    from comparison.report.committed import BadTable, check_tables
    from comparison.runner.executor.cluster import ClusterError

    # every input checked (the scheduler reached) before a folder is made: bad input leaves nothing behind
    out = output_directory("--out", args.out, create=False)
    tables = None if args.tables is None else readable_directory("--tables", args.tables)
    try:
        check_tables(out if tables is None else tables)
    except BadTable as exc:
        raise UsageError(f"{'--tables' if tables is not None else '--out'}: {exc}") from None
    cache_dir, workers = cache_dir_from_args(args, create=False), workers_from_args(args)
    if args.scheduler is not None and cache_dir is None:
        raise UsageError("--scheduler and --no-cache exclude each other (the cluster's results come back "
                         "through the result cache)")
    executor = None if args.scheduler is None else executor_from_args(workers, args.scheduler, None)
    try:
        with executor if executor is not None else contextlib.nullcontext():
            output_directory("--out", out)
            if cache_dir is not None:
                output_directory("--cache", cache_dir)
            path = build_report(
                out,
                quick=args.quick,
                cache_dir=cache_dir,
                verbosity=args.verbosity,
                workers=workers,
                tables_dir=tables,
                executor=executor,
            )
    except ClusterError as exc:  # the scheduler went away: what finished is in the cache
        print(f"xcheck: error: --scheduler: {exc}", file=sys.stderr)
        return EXIT_FAILED
    print(f"wrote {path}")
    return 0
