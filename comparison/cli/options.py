"""Option helpers shared by the ``xcheck`` subcommands.

Input validation happens here, and only here does a bad value become a
:class:`UsageError` (exit code 2): a ``ValueError`` raised later, from inside a
solver, is a bug and ends with a traceback.
"""

from __future__ import annotations

import argparse
import errno
import math
import os
import warnings
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import urlsplit

from comparison.domain.wall import ENDS, WallSpec
from comparison.utilities import numbers
from comparison.utilities.progress import NORMAL, QUIET, VERBOSE

if TYPE_CHECKING:  # pragma: no cover - typing only
    from comparison.runner.executor import Executor

#: Exit codes of ``xcheck`` (documented in docs/cli.md, "Exit codes", in the README and in ``xcheck --help``).
EXIT_OK = 0
#: A method ran but gave no load factor (a solve that is not optimal, an iterated LP that did not converge),
#: or the output could not be written (a full disk).
EXIT_FAILED = 1
#: Bad input: a malformed option, an invalid wall, a bad scene file.
EXIT_USAGE = 2
#: Interrupted by Ctrl-C (128 + SIGINT, the shell's convention).
EXIT_INTERRUPTED = 130
#: The reader of the output went away (``xcheck macro --json | head``): 128 + SIGPIPE, as a shell reports it.
EXIT_BROKEN_PIPE = 141
#: The errors of an output that cannot take more (``> /dev/full``, a full disk or quota, a file too large):
#: one line and :data:`EXIT_FAILED`, not a traceback, nor exit 2 (the input was fine).
DISK_FULL = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG})

# Values of ``args.verbosity`` (``-q``/``--quiet``, default, ``-v``/``--verbose``), defined with the
# progress display that long-running subcommands pass them down to: QUIET, NORMAL, VERBOSE.

#: The exit codes, as ``xcheck --help`` shows them (docs/cli.md and the README have the same list).
EXIT_CODES = """\
exit codes:
  0    success: every method asked for gave its load factor
  1    a method failed: a solve that is not optimal, an iterated LP that did not converge
       (the reason is printed; lambda is never printed as a number); or the output could
       not be written (a full disk)
  2    bad input: one line 'xcheck: error: ...' naming the parameter (file and line for scenes)
  130  interrupted (Ctrl-C)
  141  the reader of the output went away (a closed pipe); nothing more is printed
"""


#: Beside a time that includes compiling the macro model's kernel (numba), which its first use after an
#: install does once (``macro.kernel.compilations``): seconds of a first command, not the model's speed.
COMPILING = "compiling the macro model's kernel on its first use; later runs read it from the cache"
#: The figure formats ``--plot`` writes.
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def check_output_path(option: str, path: str | None, suffixes: tuple[str, ...] = ()) -> None:
    """Refuse an output file that cannot be written, before any work (``--plot``, ``--state``).

    Raises:
        UsageError: an empty name, a suffix not among ``suffixes`` (when given), a directory, an existing
            file that is not a regular file (a device or FIFO, directly or through a link: the writer never
            replaces one), a symbolic link to nothing, or a folder that does not exist or this process cannot
            write into (the file is written beside its name and renamed over it).
    """
    if path is None:
        return
    if not path.strip():
        raise UsageError(f"{option} must name a file, got {path!r}")
    if suffixes and not path.lower().endswith(suffixes):
        raise UsageError(f"{option} must name a {', '.join(suffixes[:-1])} or {suffixes[-1]} file, got {path!r}")
    target = Path(path)
    if target.is_dir():
        raise UsageError(f"{option}: {path!r} is a directory; name the file, e.g. {target / 'out'}")
    if target.exists() and not target.is_file():
        raise UsageError(f"{option}: {path!r} is not a regular file (a device, a FIFO or a socket)")
    if target.is_symlink() and not target.exists():
        raise UsageError(f"{option}: {path!r} is a symbolic link to nothing ({os.readlink(target)!r})")
    if not target.parent.is_dir():
        raise UsageError(f"{option}: the folder of {path!r} does not exist")
    if not os.access(target.parent, os.W_OK | os.X_OK):
        raise UsageError(f"{option}: cannot write into the folder of {path!r} (permission denied)")


def exit_after_outputs(ok: bool, *unwritten: str | None) -> int:
    """After the result is printed: one line ``xcheck: error: MESSAGE`` on stderr for each output that could
    not be written (a plot, a state file; ``None``: written or not asked for), then :data:`EXIT_FAILED`
    when there is one or the result failed, else :data:`EXIT_OK`. Not bad input: the folder was checked
    before the work, and a full disk is not the user's input."""
    import sys

    for message in unwritten:
        if message:
            print(f"xcheck: error: {message}", file=sys.stderr)
    return EXIT_OK if ok and not any(unwritten) else EXIT_FAILED


def add_command(sub: argparse._SubParsersAction, name: str, *, help: str, description: str) -> argparse.ArgumentParser:
    """A subcommand's parser with the options every subcommand has (``--quiet``/``--verbose``) and the exit
    codes in its help."""
    p = sub.add_parser(
        name,
        help=help,
        description=description,
        epilog=EXIT_CODES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_verbosity_options(p)
    return p


#: The largest count an option passes to a solver (``--max-iterations``, ``--lowest N``, ``--node-limit``):
#: HiGHS' integer options are 32-bit; the library refuses more (:data:`micro.backends.base.MAX_INTEGER`, the
#: same number, not imported: ``xcheck macro`` does not load ``micro``).
SOLVER_COUNT_MAX = 2**31 - 1


class UsageError(ValueError):
    """Bad input on the command line or in a scene file (exit code :data:`EXIT_USAGE`)."""


def parse_fraction(name: str, text: str | float) -> float:
    """Parse a number that may be written as a fraction (``"1/3"``).

    Raises:
        UsageError: naming ``name`` when ``text`` is not a number.
    """
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        return float(text)
    try:
        fraction = numbers.exact(name, str(text))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    try:
        return float(fraction)
    except OverflowError:  # beyond the doubles (1e400): infinite, for the wall checks to refuse
        return math.inf if fraction > 0 else -math.inf


def int_option(name: str, text: str, minimum: int = 1, maximum: int | None = None) -> int:
    """An integer option of at least ``minimum`` (a positive integer by default) and at most ``maximum``.

    The text is read exactly by the suite's rule for numbers (:func:`comparison.utilities.numbers.exact`:
    ``12.0000000000000001`` is not 12, ``1e3`` is 1000, ``1_0`` and ``+3`` are refused), not through a float.
    A count that reaches a solver takes ``maximum=``:data:`SOLVER_COUNT_MAX`.

    Raises:
        UsageError: naming ``name`` and the rule.
    """
    rule = (f"an integer in {minimum}..{maximum:,}" if maximum is not None else
            "a positive integer" if minimum == 1 else f"an integer >= {minimum}")
    try:
        value = numbers.exact(name, str(text))
    except numbers.OutOfRange as exc:
        raise UsageError(str(exc) if maximum is None else f"{name} must be {rule}, got {text!r}") from None
    except ValueError:
        raise UsageError(f"{name} must be {rule}, got {text!r}") from None
    if value.denominator != 1 or value < minimum or (maximum is not None and value > maximum):
        raise UsageError(f"{name} must be {rule}, got {text!r}")
    return int(value)


def choice(name: str, value: str, allowed: tuple[str, ...]) -> str:
    """``value`` when it is one of ``allowed``.

    Raises:
        UsageError: naming ``name`` and the choices.
    """
    if value not in allowed:
        raise UsageError(f"{name} must be one of {', '.join(allowed)}, got {value!r}")
    return value


def in_range(option: str, text: str | None, rule: str, upper: float) -> float | None:
    """``None`` for an option not given, else a number in ``(0, upper]``, read by the suite's rule for
    numbers (:func:`comparison.utilities.numbers.exact`).

    Raises:
        UsageError: naming ``option`` and ``rule``.
    """
    if text is None:
        return None
    try:
        value = float(numbers.exact(option, text))
    except (ValueError, OverflowError):
        raise UsageError(f"{option} must be {rule}, got {text!r}") from None
    if not (0.0 < value <= upper) or value == math.inf:
        raise UsageError(f"{option} must be {rule}, got {text!r}")
    return value


#: The options that describe a wall by the paper's parameters (``--scene`` excludes them all).
WALL_OPTIONS = ("storeys", "rows", "t", "m", "f", "p")


def add_verbosity_options(parser: argparse.ArgumentParser) -> None:
    """``-q``/``--quiet`` and ``-v``/``--verbose``, stored as ``args.verbosity`` (:data:`QUIET`,
    :data:`NORMAL` by default, :data:`VERBOSE`)."""
    g = parser.add_argument_group("output")
    x = g.add_mutually_exclusive_group()
    x.add_argument(
        "-q",
        "--quiet",
        dest="verbosity",
        action="store_const",
        const=QUIET,
        help="print only the result (the load factor, or the paths written); no progress",
    )
    x.add_argument(
        "-v",
        "--verbose",
        dest="verbosity",
        action="store_const",
        const=VERBOSE,
        help="print more: the wall's parameters, per-direction and per-iteration details",
    )
    parser.set_defaults(verbosity=NORMAL)


def add_wall_options(parser: argparse.ArgumentParser) -> None:
    """Options that describe a wall, shared by every model subcommand."""
    g = parser.add_argument_group("wall (the paper's Table 4 parameters, or a scene file)")
    g.add_argument("--storeys", type=str, default=None, metavar="N", help="number of storeys (default 1)")
    g.add_argument("--rows", type=str, metavar="O", help="rows in all, split equally over the storeys")
    g.add_argument("--t", type=str, metavar="T", help="wall shape ratio H/L")
    g.add_argument("--m", type=str, metavar="M", help="unit shape ratio b/l in (0, 1]; fractions such as 1/3 accepted")
    g.add_argument("--f", type=str, metavar="F", help="friction coefficient")
    g.add_argument(
        "--p", type=str, default=None, metavar="P", help="overloading ratio q/(gamma H b) on every floor (default 0)"
    )
    g.add_argument("--scene", type=str, metavar="FILE.toml", help="a dimensional wall given storey by storey")
    g.add_argument("--ends", type=str, default=None, metavar="closers|cut",
                   help="how the block wall's courses end when its length is not a whole number of half blocks: "
                        "closers (default, or the scene's: no piece narrower than a closer, every lap half a block) "
                        "or cut (whatever remains, down to slivers)")


def wall_from_args(args: argparse.Namespace) -> WallSpec:
    """Build the :class:`WallSpec` the wall options describe.

    Raises:
        UsageError: a missing or malformed option, or an invalid wall.
    """
    ends = getattr(args, "ends", None)
    if ends is not None:
        choice("--ends", ends, ENDS)
    if args.scene:
        from comparison.domain.scene import load_scene

        clash = [f"--{k}" for k in WALL_OPTIONS if getattr(args, k) is not None]
        if clash:
            raise UsageError(f"--scene describes the whole wall; drop {', '.join(clash)}")
        try:
            spec = load_scene(args.scene)
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        return spec if ends is None else replace(spec, ends=ends)
    missing = [f"--{k}" for k in ("rows", "t", "m", "f") if getattr(args, k) is None]
    if missing:
        raise UsageError(f"missing {', '.join(missing)} (or give --scene FILE.toml)")
    given = {k: str(getattr(args, k)) for k in WALL_OPTIONS if getattr(args, k) is not None}
    texts = {"p": "0", "storeys": "1"} | given
    t, m, f, p = (parse_fraction(k, texts[k]) for k in ("t", "m", "f", "p"))
    rows, storeys = (int_option(k, texts[k]) for k in ("rows", "storeys"))
    values: dict[str, float | int] = {"t": t, "m": m, "f": f, "p": p, "rows": rows, "storeys": storeys}
    try:
        return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=p, storeys=storeys, ends=ends or ENDS[0])
    except ValueError as exc:
        raise UsageError(echo_input(str(exc), texts, values)) from None


def echo_input(message: str, texts: dict[str, str], values: dict[str, float | int]) -> str:
    """A wall check's message about the parameter it names, quoting the value as the user wrote it.

    The checks word the parsed number (``got inf`` for ``1e400``, 301 digits for ``1e300``); the command
    line echoes the text instead (``t must be a positive number, got 1e400``).
    """
    name = message.split(" ", 1)[0].rstrip(":")
    if name not in texts:
        return message
    return message.replace(f"got {values[name]!r}", f"got {texts[name].strip()}", 1)


def add_cache_options(parser: argparse.ArgumentParser) -> None:
    """``--cache DIR`` and ``--no-cache`` (see :func:`comparison.runner.cache.default_cache_dir`)."""
    parser.add_argument(
        "--cache",
        default=None,
        metavar="DIR",
        help="result cache directory (default: $XCHECK_CACHE, else $XDG_CACHE_HOME/xcheck, else ~/.cache/xcheck)",
    )
    parser.add_argument("--no-cache", action="store_true", help="recompute everything, cache nothing")


def cache_dir_from_args(args: argparse.Namespace, *, create: bool = True) -> Path | None:
    """The cache directory the options name (``None`` for ``--no-cache``; ``create``: see
    :func:`output_directory`).

    Raises:
        UsageError: ``--cache`` together with ``--no-cache``, or a cache
            directory that cannot be written (a file, no permission).
    """
    if args.no_cache:
        if args.cache is not None:
            raise UsageError("--cache and --no-cache exclude each other")
        return None
    return cache_directory(args.cache, create=create)


def cache_directory(cache: str | None, *, create: bool = True) -> Path:
    """The cache directory ``--cache`` names, else the default one, checked before any work (``create``:
    see :func:`output_directory`).

    Raises:
        UsageError: a cache directory that cannot be written (a file, no permission).
    """
    from comparison.runner.cache import default_cache_dir

    if cache is not None:
        return output_directory("--cache", cache, create=create)
    return output_directory("the cache directory ($XCHECK_CACHE, else the default)", default_cache_dir(),
                            create=create)


def output_directory(option: str, path: str | os.PathLike[str], *, create: bool = True) -> Path:
    """A directory the command writes into, checked before any work
    (see :func:`comparison.utilities.outputs.writable_directory`;
    ``create=False`` checks it and creates nothing).

    Raises:
        UsageError: naming ``option``.
    """
    from comparison.utilities.outputs import writable_directory

    try:
        return writable_directory(option, path, create=create)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def add_executor_options(parser: argparse.ArgumentParser, default_workers: str | None = None) -> None:
    """``--workers N``: local worker processes (default: the number of CPUs, or ``default_workers``)."""
    parser.add_argument(
        "--workers",
        default=default_workers,
        metavar="N",
        help=f"local worker processes (default: {default_workers or 'the number of CPUs'})",
    )


def workers_from_args(args: argparse.Namespace) -> int | None:
    """The ``--workers`` option as a positive integer (``None``: not given), at most the number of CPUs.

    More workers than CPUs only split the memory further (each gets the memory available over the
    workers) and run no faster: a larger number is capped at the CPU count with a warning.

    Raises:
        UsageError: not a positive integer.
    """
    if args.workers is None:
        return None
    workers = int_option("--workers", args.workers)
    cpus = os.cpu_count() or 1
    if workers > cpus:
        warnings.warn(f"--workers {args.workers}: this machine has {cpus} CPUs; using {cpus} workers", stacklevel=2)
        return cpus
    return workers


#: The transports a ``dask.distributed`` scheduler listens on (``--scheduler tcp://host:8786``).
SCHEDULER_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")


def add_scheduler_option(parser: argparse.ArgumentParser) -> None:
    """``--scheduler ADDRESS``: every micro computation a task on that ``dask.distributed`` cluster."""
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a dask.distributed scheduler, e.g. tcp://host:8786: every micro computation becomes a Dask task",
    )


def scheduler_address(text: str) -> str:
    """``text`` when it is a scheduler address ``SCHEME://HOST:PORT`` (:data:`SCHEDULER_SCHEMES`), checked
    before any connection is tried (a bad one would wait for the connection's time-out).

    Raises:
        UsageError: another scheme (``http://``), no host, or a port that is not a number in 1..65535.
    """
    rule = f"an address SCHEME://HOST:PORT such as tcp://127.0.0.1:8786 (SCHEME {', '.join(SCHEDULER_SCHEMES)})"
    parts = urlsplit(text.strip())
    try:
        port = parts.port
    except ValueError:
        port = None
    if (parts.scheme not in SCHEDULER_SCHEMES or not parts.hostname or port is None or not 0 < port < 65536
            or parts.path not in ("", "/") or parts.query or parts.fragment):
        raise UsageError(f"--scheduler must be {rule}, got {text!r}")
    return text.strip()


def executor_from_args(workers: int | None, scheduler: str | None, memory: int | None) -> Executor:
    """The executor ``--workers`` and ``--scheduler`` ask for (``memory``: bytes one computation may use);
    a scheduler that cannot be reached is bad input.

    Raises:
        UsageError: both options, a malformed address, no Dask scheduler answering there, or
            ``dask.distributed`` missing.
    """
    from comparison.runner.executor import make_executor
    from comparison.runner.executor.cluster import ClusterError

    if scheduler is not None and workers is not None:
        raise UsageError("--workers and --scheduler exclude each other (the cluster has its own workers)")
    if scheduler is not None:
        scheduler_address(scheduler)
    try:
        return make_executor(workers, scheduler, memory)
    except ImportError:  # pragma: no cover - dask is in the [dask] extra
        raise UsageError("--scheduler needs dask.distributed: pip install 'xcheck-masonry[dask]'") from None
    except ClusterError as exc:
        raise UsageError(f"--scheduler: {exc}") from None
