"""Where a sweep's user models run: a process of their own, forked from the sweep's, that no model can end
the sweep from.

A user model is Python code (:mod:`comparison.sweep.usermodel`). Run in the sweep's own process, a model
that called ``os._exit(0)`` ended the sweep with exit 0 and nothing written; one that called ``os.fork()``
returned twice, and the sweep went on in both processes; one that closed standard output (``sys.stdout.close()``,
``os.close(1)``) took the paths the sweep prints with it. Here the models run in one worker process
(:class:`ModelProcess`), forked from the sweep's once the grid is read, so that the models and their
arguments need not be importable or picklable. The worker sends back each wall's
``(λ, status, message, seconds)``. A worker that ends during a call (an ``os._exit``, a signal) gives that
cell the status ``error`` with its exit code, and a new worker takes the next cell; a process the model
forked that comes back from the call ends there, without a word; what a model does to its own process's
descriptors stays in that process.
"""

from __future__ import annotations

import contextlib
import io
import multiprocessing as mp
import os
import signal
import sys
import time
from collections.abc import Sequence
from multiprocessing.connection import Connection
from types import TracebackType

from comparison.runner.executor.processes import die_with_parent
from comparison.sweep.usermodel import UserModel

#: How long a worker whose pipe closed may take to be gone before it is killed (seconds).
EXIT_SECONDS = 1.0
#: One wall's arguments of a user model: ``(t, m, rows, f, p, storeys)``.
Arguments = tuple[float, float, int, float, float, int]
#: What :meth:`UserModel.evaluate` gives: ``(λ, status, message, seconds)``.
Evaluation = tuple[float, str, str, float]


def _serve(conn: Connection, models: Sequence[UserModel], parent: int) -> None:
    """The worker's loop: ``(model, arguments, where)`` in, :meth:`UserModel.evaluate`'s tuple out; ends at
    ``None`` or when the sweep's end of the pipe closes. Never returns: the worker is a fork of the sweep."""
    me = os.getpid()
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the sweep's to handle
        die_with_parent(parent)
        while True:
            try:
                request = conn.recv()
            except (EOFError, OSError):
                break
            if request is None:
                break
            index, args, where = request
            printed = io.StringIO()
            with contextlib.redirect_stderr(printed):  # and stdout: the model's prints go to standard error
                reply = models[index].evaluate(*args, where=where)
            if os.getpid() != me:  # a process the model forked, back from the call: not the worker
                os._exit(0)
            conn.send((reply, "" if printed.closed else printed.getvalue()))
    finally:
        os._exit(0)


class ModelProcess:
    """The worker process the user models of one sweep run in (module docstring); a context manager that
    ends it.

    Args:
        models: the sweep's user models (a cell names one by its index).
    """

    def __init__(self, models: Sequence[UserModel]) -> None:
        self.models = tuple(models)
        self._pid = 0
        self._conn: Connection | None = None

    def __enter__(self) -> ModelProcess:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self._stop(kill=exc_type is not None)

    def _start(self) -> Connection:
        mine, theirs = mp.Pipe()
        parent = os.getpid()
        pid = os.fork()
        if pid == 0:  # the worker
            mine.close()
            _serve(theirs, self.models, parent)
        theirs.close()
        self._pid, self._conn = pid, mine
        return mine

    def _stop(self, *, kill: bool = False) -> int | None:
        """End the worker: ask it to stop, or (``kill``) give it :data:`EXIT_SECONDS` to be gone (a worker
        whose end of the pipe closed is exiting, or had the pipe closed under it) and kill it; its exit code
        (``None``: there was no worker)."""
        if self._conn is None:
            return None
        conn, pid, self._conn = self._conn, self._pid, None
        if not kill:
            with contextlib.suppress(OSError):
                conn.send(None)
        conn.close()
        end = time.monotonic() + (EXIT_SECONDS if kill else 10 * EXIT_SECONDS)
        while (done := os.waitpid(pid, os.WNOHANG))[0] == 0:
            if time.monotonic() > end:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
                done = os.waitpid(pid, 0)
                break
            time.sleep(0.005)
        return os.waitstatus_to_exitcode(done[1])

    def evaluate(self, model: UserModel, args: Arguments, where: str = "") -> Evaluation:
        """``model`` on one wall, in the worker (started, or started again, as needed)."""
        conn = self._conn or self._start()
        try:
            conn.send((self.models.index(model), args, where))
            reply, printed = conn.recv()
        except (EOFError, OSError):
            code = self._stop(kill=True)
            how = f"killed by signal {-code}" if code is not None and code < 0 else f"exit code {code}"
            return (float("nan"), "error", f"the model ended its process ({how}); a model returns its load factor",
                    0.0)
        except BaseException:  # Ctrl-C while it runs: the worker goes with the sweep
            self._stop(kill=True)
            raise
        if printed:
            sys.stderr.write(printed)
        evaluation: Evaluation = reply
        return evaluation
