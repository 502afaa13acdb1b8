"""The embedded executor: a few worker processes on this machine.

Each worker is a process with its own pipe: the parent sends it one task at a
time, largest first, and waits on every pipe and every process at once, so it
knows which task a worker was running when that worker died (the task is then
``lost``; a new worker takes its place). The workers

* ignore Ctrl-C (SIGINT, from birth): the parent alone handles it, ends them
  and re-raises, so an interrupted run stops within a moment with nothing
  left behind;
* die with the parent: the kernel kills a worker whose parent dies (Linux
  ``PR_SET_PDEATHSIG``) and a watchdog thread exits when the parent is gone
  (elsewhere), so no orphan outlives a killed parent;
* are spawned (fresh interpreters, about a second to start), not forked from a
  parent that may run threads, and not started from a fork server: a fork
  server's children keep it alive and are not this process's children, so
  they would outlive a killed parent.
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing as mp
import os
import signal
import sys
import threading
import time
from collections import deque
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from typing import Any

from comparison.runner.executor.base import Task, TaskOutcome, call, describe, ordered

#: How often a worker's watchdog looks whether its parent is still there (seconds).
PARENT_POLL_SECONDS = 0.5
#: How long ending a worker may wait for it to exit after SIGKILL (seconds).
JOIN_SECONDS = 5.0
#: ``prctl`` option that asks the kernel for a signal when the parent dies (Linux).
_PR_SET_PDEATHSIG = 1


def die_with_parent(parent: int) -> None:
    """End this worker when its parent process does: a kernel signal (Linux) and a watchdog thread.

    The kernel's signal works while the worker runs C code that holds the
    interpreter lock; the watchdog works everywhere else. A parent that died
    while this worker was starting is caught by the first look.
    """
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL))

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_POLL_SECONDS)
        os._exit(1)

    if os.getppid() != parent:
        os._exit(1)
    threading.Thread(target=watch, name="xcheck-parent-watch", daemon=True).start()


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """SIGINT ignored in this process meanwhile (main thread only; elsewhere nothing changes).

    A process started meanwhile is born ignoring it: an ignored signal stays
    ignored across exec, and Python then installs no handler of its own (a
    blocked one would not do: the spawn unblocks every signal). A Ctrl-C in
    these few milliseconds is lost.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _worker(conn: Connection, parent: int) -> None:
    """A worker's loop: receive ``(fn, args)``, send back :func:`call`'s tuple; ``None`` ends it."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent(parent)
    while True:
        try:
            item = conn.recv()
        except EOFError:
            return
        except Exception as exc:  # noqa: BLE001 - e.g. a function this worker cannot import
            conn.send((False, None, f"cannot receive the task: {describe(exc)}", 0.0))
            continue
        if item is None:
            return
        reply = call(*item)
        try:
            conn.send(reply)
        except Exception as exc:  # noqa: BLE001 - e.g. a value that cannot be pickled
            conn.send((False, None, f"cannot send the result back: {type(exc).__name__}: {exc}", reply[3]))


@dataclass
class _Worker:
    process: BaseProcess
    conn: Connection
    task: Task | None = None


def _context() -> Any:
    """Spawned workers: fresh interpreters, children of this process (see the module docstring)."""
    return mp.get_context("spawn")


class LocalExecutor:
    """Tasks in ``workers`` local processes, largest first.

    Use it as a context manager: on a normal exit the workers are told to stop;
    on an exception (Ctrl-C included) they are killed at once.

    Args:
        workers: processes (at least 1).
        memory_per_worker: bytes one task may use (default: the memory
            available now, shared equally by the workers).

    Attributes:
        workers: processes.
        memory_per_worker: bytes one task may use (``None``: unknown).
        where: ``"local, N processes"``.
    """

    def __init__(self, workers: int, memory_per_worker: int | None = None) -> None:
        if workers < 1:
            raise ValueError(f"workers must be a positive integer, got {workers!r}")
        self.workers = workers
        if memory_per_worker is None:
            from micro.memory import available_memory_bytes

            available = available_memory_bytes()
            memory_per_worker = None if available is None else available // workers
        self.memory_per_worker = memory_per_worker
        self.where = f"local, {workers} process{'es' if workers > 1 else ''}"
        self._ctx = _context()
        self._pool: list[_Worker] = []

    def __enter__(self) -> LocalExecutor:
        return self

    def __exit__(self, exc_type: object, *rest: object) -> None:
        self.close(kill=exc_type is not None)

    def _start(self) -> _Worker:
        parent_end, child_end = self._ctx.Pipe()
        process = self._ctx.Process(target=_worker, args=(child_end, os.getpid()), name="xcheck-worker", daemon=True)
        with _sigint_ignored():  # inherited through exec: a Ctrl-C cannot interrupt the worker's start-up
            process.start()
        child_end.close()
        worker = _Worker(process, parent_end)
        self._pool.append(worker)
        return worker

    def _retire(self, worker: _Worker) -> None:
        worker.conn.close()
        worker.process.join(JOIN_SECONDS)
        self._pool.remove(worker)

    def run(self, tasks: Sequence[Task]) -> Iterator[TaskOutcome]:
        """Run ``tasks``; yield each outcome as it finishes (refused tasks first)."""
        runnable, refused = ordered(tasks, self.memory_per_worker)
        yield from refused
        queue = deque(runnable)
        while len(self._pool) < min(self.workers, len(queue)):
            self._start()
        while queue or any(w.task is not None for w in self._pool):
            for worker in list(self._pool):
                if worker.task is None and queue:
                    self._assign(worker, queue)
            busy = [w for w in self._pool if w.task is not None]
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            for worker in busy:
                if worker.conn in ready or worker.process.sentinel in ready:
                    yield self._collect(worker)

    def _assign(self, worker: _Worker, queue: deque[Task]) -> None:
        """Send the next task to an idle ``worker`` (one that died idle is replaced)."""
        task = queue.popleft()
        try:
            worker.conn.send((task.fn, task.args))
        except OSError:
            self._retire(worker)
            worker = self._start()
            worker.conn.send((task.fn, task.args))
        worker.task = task

    def _collect(self, worker: _Worker) -> TaskOutcome:
        """The outcome of the task ``worker`` was running (a new worker replaces one that died)."""
        task = worker.task
        assert task is not None
        worker.task = None
        try:
            ok, value, error, seconds = worker.conn.recv()
        except (EOFError, OSError):
            self._retire(worker)
            self._start()
            code = worker.process.exitcode
            why = f"killed by signal {-code}" if code is not None and code < 0 else f"exit code {code}"
            return TaskOutcome(task, "lost", error=f"worker process died ({why}; out of memory?)")
        return TaskOutcome(task, "done" if ok else "failed", value, error, seconds)

    def close(self, *, kill: bool = False) -> None:
        """End the workers: ask them to stop, or kill them (``kill``) at once."""
        for worker in self._pool:
            if kill:
                worker.process.kill()
            else:
                with contextlib.suppress(OSError):
                    worker.conn.send(None)
        for worker in list(self._pool):
            self._retire(worker)
            if worker.process.is_alive():  # pragma: no cover - a worker that ignored the stop
                worker.process.kill()
                worker.process.join(JOIN_SECONDS)
