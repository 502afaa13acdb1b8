"""``xcheck sweep``: both models over a grid of walls, on local processes or a Dask cluster.

Example::

    xcheck sweep examples/sweeps/errormap.toml --out reports/sweeps --workers 2
    xcheck sweep examples/sweeps/tiny.toml --out /tmp/sweep --scheduler tcp://127.0.0.1:8786
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING
from urllib.parse import urlsplit

from comparison.cli.options import (
    EXIT_FAILED,
    UsageError,
    add_command,
    add_executor_options,
    cache_directory,
    in_range,
    output_directory,
    workers_from_args,
)

if TYPE_CHECKING:  # pragma: no cover - typing only
    from comparison.runner.executor import Executor

#: Bytes in a gigabyte (``--worker-memory`` is given in GB).
GB = 1e9
#: The largest ``--worker-memory`` (GB): a million gigabytes, beyond any machine (1e308 overflowed the
#: conversion to bytes: an OverflowError traceback).
MAX_WORKER_MEMORY_GB = 1e6
#: The transports a ``dask.distributed`` scheduler listens on (``--scheduler tcp://host:8786``).
SCHEDULER_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``sweep`` subcommand."""
    p = add_command(
        sub,
        "sweep",
        help="run the models over a grid of walls (local processes or a Dask cluster)",
        description="Reads a grid file (axes, bonds, methods; see examples/sweeps/) and writes one CSV table "
        "and its JSON metadata into --out. Micro results go through the result cache: a sweep run again "
        "computes only what is missing.",
    )
    p.add_argument("grid", metavar="GRID.toml", help="the grid file")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (GRID's name .csv and .json)")
    add_executor_options(p)
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a dask.distributed scheduler, e.g. tcp://host:8786: every micro computation becomes a Dask task",
    )
    p.add_argument(
        "--worker-memory",
        metavar="GB",
        help="memory one computation may use (default: the memory available over --workers, or the Dask "
        "workers' limit); walls whose estimate exceeds it are refused",
    )
    p.add_argument(
        "--cache",
        default=None,
        metavar="DIR",
        help="result cache directory (default: $XCHECK_CACHE, else $XDG_CACHE_HOME/xcheck, else ~/.cache/xcheck)",
    )
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck sweep``."""
    from comparison.progress import Progress
    from comparison.runner import ResultCache
    from comparison.runner.executor.cluster import ClusterError
    from comparison.sweep import GridError, load_grid, run_sweep

    try:
        grid = load_grid(args.grid)
    except GridError as exc:
        raise UsageError(str(exc)) from None
    workers = workers_from_args(args)
    if args.scheduler is not None and workers is not None:
        raise UsageError("--workers and --scheduler exclude each other (the cluster has its own workers)")
    memory = in_range("--worker-memory", args.worker_memory,
                      f"a positive number of gigabytes, at most {MAX_WORKER_MEMORY_GB:g}", MAX_WORKER_MEMORY_GB)
    out = output_directory("--out", args.out)  # before an hour of computing, not after
    cache = ResultCache(cache_directory(args.cache))
    executor = _executor(workers, args.scheduler, None if memory is None else int(memory * GB))
    try:
        with executor, Progress(args.verbosity) as progress:
            done = run_sweep(grid, out, cache=cache, executor=executor, progress=progress)
    except ClusterError as exc:  # the scheduler went away mid-sweep: what finished is in the cache
        print(f"xcheck: error: --scheduler: {exc}", file=sys.stderr)
        return EXIT_FAILED
    print(f"table: {done.table}")
    print(f"meta: {done.meta}")
    return 1 if done.counts["failed"] else 0


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


def _executor(workers: int | None, scheduler: str | None, memory: int | None) -> Executor:
    """The executor the options ask for; a scheduler that cannot be reached is bad input."""
    from comparison.runner.executor import make_executor
    from comparison.runner.executor.cluster import ClusterError

    if scheduler is not None:
        scheduler_address(scheduler)
    try:
        return make_executor(workers, scheduler, memory)
    except ImportError:  # pragma: no cover - dask is in the [dask] extra
        raise UsageError("--scheduler needs dask.distributed: pip install 'xcheck-masonry[dask]'") from None
    except ClusterError as exc:
        raise UsageError(f"--scheduler: {exc}") from None
