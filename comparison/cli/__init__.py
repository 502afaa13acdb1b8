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
"""

from __future__ import annotations

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
        return _EXIT_INTERRUPTED
    return app.main(argv)


def build_parser() -> argparse.ArgumentParser:
    """The full ``xcheck`` parser (:func:`comparison.cli.app.build_parser`)."""
    from comparison.cli import app

    return app.build_parser()


__all__ = ["build_parser", "main"]
