"""The ``xcheck`` parser and entry point.

Only input validation maps to exit code 2: the parser's own errors and the
:class:`~comparison.cli.options.UsageError` the option helpers raise. Any other
exception is a bug and ends with its traceback. Bare ``xcheck`` prints the
usage (exit 2); ``xcheck --version`` the version. A reader that closes the
output early (``xcheck macro --json | head``) ends the run quietly with
:data:`~comparison.cli.options.EXIT_BROKEN_PIPE` (141); Ctrl-C with 130; an output that cannot be
written (a full disk: ``> /dev/full``) with one line ``xcheck: error: cannot write ...`` and exit code 1.
Warnings (e.g. an unreadable cache entry) are one line each, ``xcheck: warning: ...``.

Standard error carries the plan, the progress, warnings and errors, never a result: a standard error that
cannot be written (a full device, a descriptor closed under the command) is given up quietly and the
command goes on to its results and its exit code; one closed at the start (``2>&-``) is a stream that
drops what is written, so that nothing meant for it reaches standard output (``print(file=None)``).
"""

from __future__ import annotations

import argparse
import io
import os
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from importlib import metadata
from typing import Any

from comparison.cli import compare, macro, micro, references, report, stability, sweep, verify
from comparison.cli.options import (
    DISK_FULL,
    EXIT_BROKEN_PIPE,
    EXIT_CODES,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    EXIT_USAGE,
    UsageError,
)


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line and exit with code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(message)


def version() -> str:
    """The installed version of the suite."""
    try:
        return metadata.version("xcheck-masonry")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a source tree
        return "unknown"


def build_parser() -> argparse.ArgumentParser:
    """The full ``xcheck`` parser with every subcommand registered."""
    parser = Parser(
        prog="xcheck",
        description="Macro-block model vs rigid-block limit analysis of dry-joint masonry walls.",
        epilog=EXIT_CODES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"xcheck {version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for module in (compare, macro, micro, report, stability, sweep, references, verify):
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``xcheck`` console script."""
    args_given = sys.argv[1:] if argv is None else list(argv)
    if sys.stdout is None:  # started with its standard output closed (``>&-``): nothing could be said
        print("xcheck: error: cannot write the output: standard output is closed", file=sys.stderr)
        return EXIT_FAILED
    with _forgiving_stderr(), _one_line_warnings():
        try:
            parser = build_parser()
            if not args_given:
                parser.print_help(sys.stderr)
                return EXIT_USAGE
            args = parser.parse_args(args_given)
            code = int(args.handler(args) or 0)
            sys.stdout.flush()  # a closed pipe shows here, not at exit
            return code
        except UsageError as exc:
            print(f"xcheck: error: {exc}", file=sys.stderr)
            return EXIT_USAGE
        except SystemExit as exc:  # --help, --version
            return exc.code if isinstance(exc.code, int) else EXIT_USAGE
        except BrokenPipeError:
            _drop_stdout()
            return EXIT_BROKEN_PIPE
        except OSError as exc:
            if exc.errno not in DISK_FULL:
                raise
            where = f" {exc.filename}" if exc.filename else " the output"
            print(f"xcheck: error: cannot write{where}: {exc.strerror}", file=sys.stderr)
            _drop_stdout()
            return EXIT_FAILED
        except KeyboardInterrupt:
            print("xcheck: interrupted", file=sys.stderr)
            return EXIT_INTERRUPTED


def _drop_stdout() -> None:
    """Point stdout at /dev/null, so that the interpreter's last flush finds no closed pipe."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # no real file descriptor (e.g. captured in tests)
        pass


class ForgivingStream(io.TextIOBase):
    """A text stream that gives up quietly: the first write or flush that fails (``OSError``, ``ValueError``
    on a closed file) ends the writing, and every later one is dropped; ``None``: drops everything."""

    def __init__(self, stream: Any) -> None:
        self.stream = stream
        self.dead = stream is None

    def write(self, text: str) -> int:
        if not self.dead:
            try:
                self.stream.write(text)
            except (OSError, ValueError):
                self.dead = True
        return len(text)

    def flush(self) -> None:
        if not self.dead:
            try:
                self.stream.flush()
            except (OSError, ValueError):
                self.dead = True

    def isatty(self) -> bool:
        try:
            return not self.dead and bool(self.stream.isatty())
        except (OSError, ValueError):
            return False

    def writable(self) -> bool:
        return True

    def fileno(self) -> int:
        if self.dead:
            raise io.UnsupportedOperation("standard error is given up")
        return int(self.stream.fileno())

    @property
    def encoding(self) -> str:  # type: ignore[override]
        return str(getattr(self.stream, "encoding", None) or "utf-8")


@contextmanager
def _forgiving_stderr() -> Iterator[None]:
    """``sys.stderr`` as a :class:`ForgivingStream` while the command runs (module docstring)."""
    given = sys.stderr
    sys.stderr = ForgivingStream(given)
    try:
        yield
    finally:
        if isinstance(sys.stderr, ForgivingStream):
            sys.stderr = given


@contextmanager
def _one_line_warnings() -> Iterator[None]:
    """Show each warning as one line ``xcheck: warning: ...`` while the command runs."""

    def show(message: Warning | str, category: type[Warning], *args: object, **kwargs: object) -> None:
        print(f"xcheck: warning: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        yield


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
