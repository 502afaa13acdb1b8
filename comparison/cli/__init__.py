"""The ``xcheck`` command line.

:mod:`comparison.cli.app` holds the parser and :func:`main`;
:mod:`comparison.cli.options` the option helpers every subcommand shares; one
module per subcommand (:mod:`~comparison.cli.macro`, :mod:`~comparison.cli.micro`,
:mod:`~comparison.cli.report`, :mod:`~comparison.cli.stability`) adds itself
with ``register(subparsers)``. Bad input prints one line ``xcheck: error: ...``
naming the parameter and exits with code 2, without a traceback.
"""

from comparison.cli.app import build_parser, main

__all__ = ["build_parser", "main"]
