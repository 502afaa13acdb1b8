"""``xcheck verify FILE``: is the state in a file a genuine collapse state?

The file is a collapse state (``xcheck micro --state``, or another program's in the same format:
``docs/files.md``); :func:`micro.verify_state` checks it from its own data. The first line says whether
it is one and, when it is not, names the worst residual; then every residual against its tolerance.
Exit 0: a genuine collapse state; 1: not one; 2: a malformed file (one line naming the file and the JSON
line or the field).

Example::

    xcheck micro --t 1 --m 1/2 --rows 12 --f 0.75 --friction nonassociative --state set13.json
    xcheck verify set13.json
"""

from __future__ import annotations

import argparse
import json
import math
from typing import TYPE_CHECKING

from comparison.cli.options import EXIT_FAILED, EXIT_OK, QUIET, UsageError, add_command

if TYPE_CHECKING:  # pragma: no cover - typing only
    from micro import StateCheck

#: The friction laws as the first line names them.
_LAW = {"associative": "associative friction", "nonassociative": "non-associative friction"}


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``verify`` subcommand."""
    p = add_command(
        subparsers,
        "verify",
        help="check that a collapse state file (xcheck micro --state, or another program's) is a genuine "
        "collapse state",
        description="Checks a collapse state file from its own data (equilibrium, no tension, Coulomb, "
        "compatibility, the flow rule, opening only where the normal force is zero, friction against the "
        "slip, the power balance, a mechanism) and prints every residual against its tolerance. Exit 0: "
        "a genuine collapse state; 1: not one (the worst residual named first); 2: a malformed file.",
    )
    p.add_argument("file", metavar="FILE.json", help="the state file")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck verify``."""
    import micro

    try:
        check = micro.verify_state(micro.read_state(args.file))
    except micro.StateFileError as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        print(json.dumps({"file": args.file, **check.to_dict()}))
    else:
        print(headline(args.file, check))
        if args.verbosity > QUIET:
            width = max(len(r.name) for r in check.residuals)
            for r in check.residuals:
                op = (">=" if r.passed else "<") if r.at_least else ("<=" if r.passed else ">")
                mark = "" if r.passed else "  FAILS"
                print(f"  {r.name:<{width}}  {r.value:9.3g} {op:>2} {r.tolerance:<8.3g} {r.meaning}{mark}")
    return EXIT_OK if check.passed else EXIT_FAILED


def headline(path: str, check: StateCheck) -> str:
    """The first line: whether the file holds a genuine collapse state, and the worst residual."""
    lam = f"{check.load_factor:.6f}" if math.isfinite(check.load_factor) else "-"
    what = (f"{_LAW[check.friction]}, lambda = {lam} ({check.direction}), {check.blocks:,} blocks, "
            f"{check.points:,} contact points")
    if check.passed:
        return f"{path}: a genuine collapse state ({what}); every residual within its tolerance"
    worst = check.worst
    more = len(check.failed) - 1
    others = f"; {more} more residual{'s' if more > 1 else ''} fail{'' if more > 1 else 's'}" if more else ""
    return f"{path}: not a collapse state ({what}): {worst.describe()}{others}"
