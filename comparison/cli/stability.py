"""``xcheck stability``: convergence study of the iterated non-associative LP.

Example::

    xcheck stability --out reports --workers 2
    xcheck stability --lowest --out reports
"""

from __future__ import annotations

import argparse
import warnings

from comparison.cli.options import UsageError, add_command, output_directory, workers_from_args

#: Worker processes of the studies unless ``--workers`` says otherwise.
STUDY_WORKERS = 2


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``stability`` subcommand."""
    p = add_command(
        subparsers,
        "stability",
        help="convergence study of the non-associative iterated LP on a grid of small walls",
        description="Runs the non-associative iterated LP (schemes a and b, several relaxations) on a grid "
        "of 120 small walls and writes stability.md, stability.csv and stability.png.",
    )
    p.add_argument("--out", default="reports", metavar="DIR", help="output folder (default reports)")
    p.add_argument("--workers", default=None, metavar="N", help="local worker processes (default 2)")
    # the option's old name, unlike report's and sweep's --workers: still read, with a warning
    p.add_argument("--processes", default=None, help=argparse.SUPPRESS)
    p.add_argument("--quick", action="store_true", help="12 walls only (smoke test)")
    p.add_argument(
        "--table7",
        action="store_true",
        help="instead: Table 7 (sets 11-14) per scheme, bond phase and head-joint friction (table7_nonassoc.md)",
    )
    p.add_argument(
        "--lowest",
        action="store_true",
        help="instead: the iterated LP against the lowest certified state and the global minimum on Table 7's "
        "walls, the grid and tiny walls (lowest.md, lowest.csv, lowest.png)",
    )
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck stability``."""
    from comparison.stability import main_lowest, main_study, table7_variants

    if args.processes is not None:
        if args.workers is not None:
            raise UsageError("--processes is the old name of --workers; give --workers alone")
        warnings.warn("--processes is deprecated: use --workers", FutureWarning, stacklevel=1)
        args.workers = args.processes
    if args.table7:  # one study per run: --table7 ran alone, ignoring these
        extra = [o for o, given in (("--lowest", args.lowest), ("--quick", args.quick),
                                    ("--workers", args.workers is not None)) if given]
        if extra:
            raise UsageError(f"--table7 runs its four walls alone in this process; drop {', '.join(extra)}")
    processes = workers_from_args(args) or STUDY_WORKERS
    output_directory("--out", args.out)
    try:
        if args.table7:
            print(f"md: {table7_variants(args.out)}")
            return 0
        if args.lowest:
            paths = main_lowest(args.out, processes=processes, quick=args.quick)
        else:
            paths = main_study(args.out, processes=processes, quick=args.quick, verbosity=args.verbosity)
    except OSError as exc:
        raise UsageError(f"--out: cannot write to {args.out!r} ({exc.strerror})") from None
    for kind, path in paths.items():
        print(f"{kind}: {path}")
    return 0
