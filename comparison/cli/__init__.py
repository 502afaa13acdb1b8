"""The ``xcheck`` command line.

:mod:`comparison.cli.app` holds the parser and the command's body;
:mod:`comparison.cli.options` the option helpers every subcommand shares; one
module per subcommand (:mod:`~comparison.cli.macro`, :mod:`~comparison.cli.micro`,
:mod:`~comparison.cli.report`, :mod:`~comparison.cli.stability`) adds itself
with ``register(subparsers)``. Bad input prints one line ``xcheck: error: ...``
naming the parameter and exits with code 2, without a traceback.

:func:`main` loads :mod:`~comparison.cli.app` (the whole suite, seconds on a
loaded machine) inside its own Ctrl-C handling: a Ctrl-C while it loads ends
the command like one later (exit 130, one line), not with a traceback.

An interrupted command exits without the interpreter's garbage collection of
what it built (:func:`_skip_collection_at_exit`): after a Ctrl-C inside
``--solver cvxpy`` the collection at exit is most of the time to exit 130 (measured:
docs/speed.md, "What the code's choices rest on").
"""

from __future__ import annotations

import gc
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import argparse

#: :data:`comparison.cli.options.EXIT_INTERRUPTED`, named here because loading that module is what was interrupted.
_EXIT_INTERRUPTED = 130


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``xcheck`` console script (:func:`comparison.cli.app.main` once loaded)."""
    try:
        from comparison.cli import app
    except KeyboardInterrupt:
        print("xcheck: interrupted", file=sys.stderr)
        code = _EXIT_INTERRUPTED
    else:
        code = app.main(argv)
    if code == _EXIT_INTERRUPTED:
        _skip_collection_at_exit()
    return code


def _skip_collection_at_exit() -> None:
    """Move every object alive now out of the garbage collector's reach (``gc.freeze``): the collections
    at interpreter exit then skip what the interrupted command built (a cvxpy problem of a large wall: hundreds
    of thousands of objects), while exit handlers still run. In a process that goes on (a test calling
    :func:`main`) those objects are only never collected as cycles."""
    gc.freeze()


def build_parser() -> argparse.ArgumentParser:
    """The full ``xcheck`` parser (:func:`comparison.cli.app.build_parser`)."""
    from comparison.cli import app

    return app.build_parser()


__all__ = ["build_parser", "main"]
