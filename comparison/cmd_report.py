"""``xcheck report``: recompute the paper's tables and write ``reports/REPORT.md``."""

from __future__ import annotations

import argparse
from pathlib import Path

from comparison.report import write_macro_report


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add the ``report`` subcommand."""
    p = sub.add_parser("report", help="recompute the paper's tables and write reports/REPORT.md")
    p.add_argument("--out", default="reports", help="output directory (default: reports)")
    p.add_argument("--quick", action="store_true", help="small walls only")
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Write the report and print where it is."""
    path = write_macro_report(Path(args.out), quick=args.quick)
    print(f"wrote {path}")
    print(path.read_text())
    return 0
