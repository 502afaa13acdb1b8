"""``xcheck report``: run both models on the paper's cases and write ``reports/REPORT.md``."""

from __future__ import annotations

import argparse
import sys

from comparison.cli.options import add_cache_options, cache_dir_from_args, output_directory


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``report`` subcommand."""
    p = sub.add_parser(
        "report",
        help="recompute the paper's tables with both models and write reports/REPORT.md",
        description="Tables 5, 7, 8, 9 and beyond, failure modes, sensitivity and speed-accuracy figures.",
    )
    p.add_argument("--out", default="reports", help="output directory (default: reports)")
    p.add_argument("--quick", action="store_true", help="the micro model on the small walls only (under a minute)")
    add_cache_options(p)
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Write the report and say where it is."""
    from comparison.report import build_report

    out = output_directory("--out", args.out)
    path = build_report(
        out,
        quick=args.quick,
        cache_dir=cache_dir_from_args(args),
        progress=None if args.quiet else stderr_progress,
    )
    print(f"wrote {path}")
    return 0


def stderr_progress(line: str) -> None:
    """Progress printer for long runs."""
    print(line, file=sys.stderr, flush=True)
