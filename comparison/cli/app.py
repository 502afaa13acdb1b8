"""The ``xcheck`` parser and entry point.

Only input validation maps to exit code 2: the parser's own errors and the
:class:`~comparison.cli.options.UsageError` the option helpers raise. Any other
exception is a bug and ends with its traceback.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from comparison.cli import macro, micro, references, report, stability, sweep
from comparison.cli.options import EXIT_CODES, EXIT_INTERRUPTED, EXIT_USAGE, UsageError


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line and exit with code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(message)


def build_parser() -> argparse.ArgumentParser:
    """The full ``xcheck`` parser with every subcommand registered."""
    parser = Parser(
        prog="xcheck",
        description="Macro-block model vs rigid-block limit analysis of dry-joint masonry walls.",
        epilog=EXIT_CODES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for module in (macro, micro, report, stability, sweep, references):
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``xcheck`` console script."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        return int(args.handler(args) or 0)
    except UsageError as exc:
        print(f"xcheck: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("xcheck: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
