"""``xcheck verify FILE``: is the state in a file a genuine collapse state of the wall it names?

The file is a collapse state (``xcheck micro --state``, or another program's in the same format:
``docs/files.md``). :func:`micro.verify_state` checks it: against the wall it names (its ``wall``, built
again; and the wall of the paper parameters its ``source`` gives, which is how a file of version 1 names
its wall), block by block; its geometry and loads against its own outlines; and the conditions of its
friction law, each residual relative to the block or point it is at. The first line says whether it is
one and, when it is not, names the worst residual and where; then every residual against its tolerance,
then what could not be checked. Exit 0: a genuine collapse state; 1: not one; 2: a malformed file (one
line naming the file, the field and its line).

Example::

    xcheck micro --t 1 --m 1/2 --rows 12 --f 0.75 --friction nonassociative --state set13.json
    xcheck verify set13.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from comparison.cli.options import EXIT_FAILED, EXIT_OK, QUIET, UsageError, add_command

if TYPE_CHECKING:  # pragma: no cover - typing only
    from micro import BlockWall, CollapseStateData, HeldWall, StateCheck

#: The friction laws as the first line names them.
_LAW = {"associative": "associative friction", "nonassociative": "non-associative friction"}


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``verify`` subcommand."""
    p = add_command(
        subparsers,
        "verify",
        help="check that a collapse state file (xcheck micro --state, or another program's) is a genuine "
        "collapse state of the wall it names",
        description="Checks a collapse state file: against the wall it names (built again and compared block "
        "by block), its geometry (contact points on both blocks' outlines, every touching edge with its "
        "points) and loads (from the areas, the unit weight and the floor loads), and the conditions of its "
        "friction law (equilibrium, no tension, Coulomb, compatibility, the flow rule, opening only where the "
        "normal force is zero, friction against the slip, the power balance, a mechanism), each residual "
        "relative to the block or point it is at; prints every residual against its tolerance and what "
        "could not be checked. Exit 0: a genuine collapse state; 1: not one (the worst residual named "
        "first); 2: a malformed file.",
    )
    p.add_argument("file", metavar="FILE.json", help="the state file")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck verify``."""
    import micro

    try:
        state = micro.read_state(args.file)
    except micro.StateFileError as exc:
        raise UsageError(str(exc)) from None
    wall, note = paper_wall(state)
    check = micro.verify_state(state, wall=wall, wall_name=f"the wall of the paper parameters in its source ({note})")
    if wall is None and note:
        check = dataclasses.replace(check, unchecked=(*check.unchecked, note))
    if args.json:
        print(json.dumps({"file": args.file, **check.to_dict()}))
        return EXIT_OK if check.passed else EXIT_FAILED
    print(headline(args.file, check))
    if args.verbosity > QUIET:
        width = max(len(r.name) for r in check.residuals)
        for r in check.residuals:
            op = (">=" if r.passed else "<") if r.at_least else ("<=" if r.passed else ">")
            mark = f"  FAILS: {r.where}" if not r.passed and r.where else "  FAILS" if not r.passed else ""
            print(f"  {r.name:<{width}}  {r.value:9.3g} {op:>2} {r.tolerance:<8.3g} {r.meaning}{mark}")
        if check.wall:
            print(f"  wall: {check.wall}")
        for line in check.unchecked:
            print(f"  not checked: {line}")
    return EXIT_OK if check.passed else EXIT_FAILED


def paper_wall(state: CollapseStateData) -> tuple[BlockWall | HeldWall | None, str]:
    """The wall the paper parameters of the state's ``source`` describe, with its bond (and the held
    blocks and end treatment of the file's ``wall``; a version-1 file's walls were cut), and a note: what
    was built, or why nothing was (a scene named only by its name, parameters that build no wall)."""
    import micro
    from comparison.domain.wall import WallSpec

    src = state.source
    params = src.get("paper_parameters") if isinstance(src, Mapping) else None
    if not isinstance(params, Mapping):
        return None, ""
    if src.get("wall") not in (None, ""):
        return None, (f"the paper parameters in the source: they describe the scene {src.get('wall')!r} only in "
                      "ratios (its units and storeys are not in a version-1 file)") if state.wall is None else ""
    try:
        keys = {k: params[k] for k in ("t", "m", "rows", "f", "storeys")}
        p = params.get("p")
        if p is None:
            raise ValueError("the storeys' floor loads differ (no one p)")
        spec = WallSpec.from_paper(**keys, p=p)
        named = dict(state.wall.builder) if state.wall is not None else {}
        bond: dict[str, Any] = {k: named.get(k, src.get(k, default))
                                for k, default in (("first_course", "full"), ("head_joints", "frictional"))}
        bond["ends"] = named.get("ends", "cut")  # version 1 (before the choice of ends): cut ends
        wall = spec.to_micro(**bond)
        held = state.wall.held if state.wall is not None else ()
        built = micro.hold_blocks(wall, held) if held else wall
    except (KeyError, TypeError, ValueError) as exc:
        return None, f"the paper parameters in the source build no wall ({exc})"
    what = ", ".join(f"{k} {params[k]}" for k in ("t", "m", "rows", "f", "storeys")) + f", p {p}; " + \
        ", ".join(f"{v}" for v in bond.values()) + (f"; held {list(held)}" if held else "")
    return built, what


def headline(path: str, check: StateCheck) -> str:
    """The first line: whether the file holds a genuine collapse state (of the wall it names, or of the
    structure in it when it names none), and the worst residual."""
    lam = f"{check.load_factor:.6f}" if math.isfinite(check.load_factor) else "-"
    what = (f"{_LAW[check.friction]}, lambda = {lam} ({check.direction}), {check.blocks:,} blocks, "
            f"{check.points:,} contact points")
    if check.passed:
        of = "of the wall it names" if check.wall else "of the structure in the file, which names no wall"
        return f"{path}: a genuine collapse state {of} ({what}); every residual within its tolerance"
    worst = check.worst
    more = len(check.failed) - 1
    others = f"; {more} more residual{'s' if more > 1 else ''} fail{'' if more > 1 else 's'}" if more else ""
    return f"{path}: not a collapse state ({what}): {worst.describe()}{others}"
