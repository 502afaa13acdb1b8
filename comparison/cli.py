"""The ``xcheck`` command line.

Every subcommand lives in its own ``comparison.cmd_*`` module with a
``register(subparsers)`` function. Bad input prints one line
``xcheck: error: ...`` naming the parameter and exits with code 2, without a
traceback.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from comparison.spec import WallSpec, parse_fraction

EXIT_USAGE = 2


class UsageError(ValueError):
    """Bad input on the command line or in a scene file."""


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line and exit with code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(message)


def add_wall_options(parser: argparse.ArgumentParser) -> None:
    """Options that describe a wall, shared by every model subcommand."""
    g = parser.add_argument_group("wall (the paper's Table 4 parameters, or a scene file)")
    g.add_argument("--storeys", type=str, default="1", metavar="N", help="number of storeys (default 1)")
    g.add_argument("--rows", type=str, metavar="O", help="rows in all, split equally over the storeys")
    g.add_argument("--t", type=str, metavar="T", help="wall shape ratio H/L")
    g.add_argument("--m", type=str, metavar="M", help="unit shape ratio b/l in (0, 1]; fractions such as 1/3 accepted")
    g.add_argument("--f", type=str, metavar="F", help="friction coefficient")
    g.add_argument("--p", type=str, default="0", metavar="P", help="overloading ratio q/(gamma H b) on every floor (default 0)")
    g.add_argument("--scene", type=str, metavar="FILE.toml", help="a dimensional wall given storey by storey")


def int_option(name: str, text: str, minimum: int = 1) -> int:
    """An integer option of at least ``minimum`` (a positive integer by default).

    Raises:
        UsageError: naming ``name`` and the rule.
    """
    rule = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
    try:
        value = parse_fraction(name, text)
    except ValueError:
        raise UsageError(f"{name} must be {rule}, got {text!r}") from None
    if not value.is_integer() or value < minimum:
        raise UsageError(f"{name} must be {rule}, got {text!r}")
    return int(value)


def wall_from_args(args: argparse.Namespace) -> WallSpec:
    """Build the :class:`WallSpec` the wall options describe.

    Raises:
        UsageError: a missing or malformed option, or an invalid wall.
    """
    if args.scene:
        from comparison.scene import load_scene

        clash = [f"--{k}" for k in ("rows", "t", "m", "f") if getattr(args, k) is not None]
        if clash:
            raise UsageError(f"--scene describes the whole wall; drop {', '.join(clash)}")
        return load_scene(args.scene)
    missing = [f"--{k}" for k in ("rows", "t", "m", "f") if getattr(args, k) is None]
    if missing:
        raise UsageError(f"missing {', '.join(missing)} (or give --scene FILE.toml)")
    try:
        return WallSpec.from_paper(
            t=parse_fraction("t", args.t),
            m=parse_fraction("m", args.m),
            rows=int_option("rows", args.rows),
            f=parse_fraction("f", args.f),
            p=parse_fraction("p", args.p),
            storeys=int_option("storeys", args.storeys),
        )
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def build_parser() -> argparse.ArgumentParser:
    """The full ``xcheck`` parser with every subcommand registered."""
    from comparison import cmd_macro, cmd_micro, cmd_report, cmd_stability

    parser = _Parser(
        prog="xcheck",
        description="Macro-block model vs rigid-block limit analysis of dry-joint masonry walls.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for module in (cmd_macro, cmd_micro, cmd_report, cmd_stability):
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
    except ValueError as exc:
        print(f"xcheck: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("xcheck: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
