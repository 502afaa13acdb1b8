"""``xcheck report``: run both models on the paper's cases and write ``reports/REPORT.md``."""

from __future__ import annotations

import argparse

from comparison.cli.options import (
    add_cache_options,
    add_command,
    add_executor_options,
    cache_dir_from_args,
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
    p.add_argument("--quick", action="store_true", help="the micro model on the small walls only (under a minute)")
    add_cache_options(p)
    add_executor_options(p)
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Write the report and say where it is.

    ``args.verbosity`` is the setting the progress display follows
    (:mod:`comparison.progress`).
    """
    from comparison.report import build_report

    out = output_directory("--out", args.out)
    path = build_report(
        out,
        quick=args.quick,
        cache_dir=cache_dir_from_args(args),
        verbosity=args.verbosity,
        workers=workers_from_args(args),
    )
    print(f"wrote {path}")
    return 0
