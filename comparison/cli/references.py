"""``xcheck references``: regenerate the pytest plugin's reference values (``references.json``)."""

from __future__ import annotations

import argparse
from pathlib import Path

from comparison.cli.options import (
    DISK_FULL,
    UsageError,
    add_cache_options,
    add_command,
    cache_dir_from_args,
    output_directory,
)

#: Where ``xcheck references`` writes unless told: the working directory, never the installed package's own
#: data file (the plugin's ``comparison/pytest_plugin/references.json`` is rewritten only when named).
DEFAULT_OUT = "references.json"


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``references`` subcommand."""
    p = add_command(
        sub,
        "references",
        help="regenerate the pytest plugin's reference values from the paper and this package's results",
        description="Runs the report's methods on the paper's cases (through the result cache: after "
        "`xcheck report` it only reads) and writes the reference cells, with tolerances and sources, "
        "that the pytest plugin ships.",
    )
    p.add_argument(
        "--out",
        default=DEFAULT_OUT,
        metavar="FILE.json",
        help=f"where to write (default: {DEFAULT_OUT} in the working directory; the plugin ships "
        "comparison/pytest_plugin/references.json of the source tree, written by naming it)",
    )
    p.add_argument("--quick", action="store_true", help="the micro model on Table 7's walls only")
    add_cache_options(p)
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Write the references and say how many cells."""
    from comparison.pytest_plugin import generate

    if not args.out.strip():
        raise UsageError(f"--out must name a file, got {args.out!r}")
    out = Path(args.out)
    if out.is_dir():
        raise UsageError(f"--out: {args.out!r} is a directory; name the file, e.g. {out / DEFAULT_OUT}")
    output_directory("--out", out.parent)  # before the run, not after
    try:
        refs = generate.generate(
            out,
            cache_dir=cache_dir_from_args(args),
            quick=args.quick,
            verbosity=args.verbosity,
        )
    except OSError as exc:
        if exc.errno in DISK_FULL:  # not the input's fault: one line and exit 1 (comparison.cli.app)
            raise OSError(exc.errno, exc.strerror, str(out)) from None
        raise UsageError(f"--out: cannot write {str(out)!r} ({exc.strerror})") from None
    valued = sum(c.value is not None for c in refs)
    print(f"wrote {out}: {len(refs)} cells, {valued} with a value")
    return 0
