"""``--state FILE``: the collapse state behind a micro result, written as a file that ``xcheck verify`` checks.

The state written is the one whose load factor the command quotes (:func:`micro.collapse_state`); the
file is written whole or not at all (:func:`micro.write_state`), after the result is printed. Its folder
is checked before solving, as ``--plot``'s is. A command that adds ``--state`` calls
:func:`add_state_option`, :func:`check_state_path` before its work and :func:`write_state_file` after.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from comparison.cli.options import check_output_path

if TYPE_CHECKING:  # pragma: no cover - typing only
    from comparison.domain.wall import WallSpec
    from micro import BlockWall


def add_state_option(group: Any) -> None:
    """Add ``--state FILE`` to a parser or an argument group."""
    group.add_argument("--state", default=None, metavar="FILE.json",
                       help="write the collapse state of the value printed (wall, forces, velocities, rates, "
                       "contact states) as JSON; `xcheck verify FILE.json` checks it")


def check_state_path(args: argparse.Namespace) -> None:
    """Refuse a ``--state`` that cannot be written, before the solve
    (:func:`~comparison.cli.options.check_output_path`).

    Raises:
        UsageError: an empty name, a directory, a device or FIFO, or a folder that does not exist.
    """
    check_output_path("--state", args.state)


def write_state_file(args: argparse.Namespace, result: Any, wall: BlockWall,
                     spec: WallSpec) -> tuple[str | None, str | None]:
    """Write the state of ``result`` to ``args.state`` (when given and the result has one).

    Returns:
        ``(the path written, why it could not be)``, ``None`` where not: ``(None, None)`` without
        ``--state``. A failed result has no state (``"--state: no collapse state to write (...)"``); a
        file that cannot be written (a full disk) is not bad input: the caller prints the result, then
        this line, and exits with 1 (:func:`~comparison.cli.options.exit_after_outputs`).
    """
    if args.state is None:
        return None, None
    import micro

    if not result.ok:
        return None, f"--state: no collapse state to write ({result.status})"
    source = {"wall": spec.name or None, "paper_parameters": spec.paper_parameters(),
              **{k: getattr(args, k) for k in ("first_course", "head_joints") if hasattr(args, k)}}
    try:
        micro.write_state(result, args.state, wall=wall, source=source)
    except OSError as exc:
        return None, f"--state: cannot write {args.state!r} ({exc.strerror or exc})"
    return args.state, None
