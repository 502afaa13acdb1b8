"""The distributed executor: every task a ``dask.distributed`` task on an existing cluster.

The scheduler is given by its address (``tcp://host:port``); its workers need
only this package installed (a task's function is imported there by name).
Tasks are submitted with their rank by cost as Dask priority, so the largest start
first; a task that raises comes back as ``failed``, one whose workers kept dying
(Dask's ``KilledWorker``) as ``lost``; a task whose memory estimate exceeds a
worker's memory limit (shared by its threads) is refused before submission. On
an exception (Ctrl-C included) the submitted tasks are cancelled and the client
closed. A scheduler that goes away mid-run ends it with :class:`ClusterError` (the
tasks that finished were handed out; none is labelled lost: the workers lived).
"""

from __future__ import annotations

import asyncio
import contextlib
import importlib.util
import logging
import socket
import threading
import time
import uuid
from collections.abc import Iterator, Sequence
from typing import Any
from urllib.parse import urlsplit

from comparison.runner.executor.base import Task, TaskOutcome, call, ordered

#: Seconds to wait for the scheduler to answer and for at least one worker.
CONNECT_SECONDS = 20.0
#: Seconds for the first contact (:func:`check_scheduler`: the host resolved, the connection made, Dask's
#: handshake and the scheduler's identity). Without it a silent TCP server held the client for minutes
#: (Dask waits for the handshake without a limit), and a server sending other bytes ended in a traceback
#: (measured: docs/speed.md, "What the code's choices rest on").
HANDSHAKE_SECONDS = 4.0


class ClusterError(RuntimeError):
    """The scheduler cannot be reached, is not a Dask scheduler, has no worker, or went away."""


def check_scheduler(address: str, seconds: float = HANDSHAKE_SECONDS) -> None:
    """Check that a Dask scheduler answers at ``address`` within ``seconds``: the transport usable here
    (:func:`_transport_problem`); for ``tcp://``, the host resolves and a connection is accepted; for every
    scheme, Dask's handshake comes back and the peer calls itself a scheduler.

    Raises:
        ClusterError: ``"no Dask scheduler at {address} ({why})"``, ``why`` naming the cause (a missing
            transport package or TLS settings, an HTTP server, the exception's type and message).
    """
    problem = _transport_problem(address)
    if problem:
        raise ClusterError(f"no Dask scheduler at {address} ({problem})")
    outcome: list[BaseException | None] = []

    deadline = time.monotonic() + seconds

    def probe() -> None:  # in a thread of its own: resolving a host has no time limit of its own
        try:
            if urlsplit(address).scheme == "tcp":
                _tcp_connect(address, seconds)
            left = max(deadline - time.monotonic(), 0.1)
            asyncio.run(asyncio.wait_for(_identity(address, left), left))
            outcome.append(None)
        except BaseException as exc:  # noqa: BLE001 - reported below, whatever it is
            outcome.append(exc)

    thread = threading.Thread(target=probe, name="xcheck-scheduler-check", daemon=True)
    thread.start()
    thread.join(seconds + 0.5)
    if not outcome:
        raise ClusterError(f"no Dask scheduler at {address} (no answer within {seconds:g} s)")
    exc = outcome[0]
    if exc is None:
        return
    if isinstance(exc, ClusterError):
        raise exc
    raise ClusterError(f"no Dask scheduler at {address} ({_cause(address, exc, seconds)})")


def _cause(address: str, exc: BaseException, seconds: float) -> str:
    """Why the check of ``address`` failed with ``exc``, in words."""
    if isinstance(exc, socket.gaierror):
        return f"cannot resolve the host: {exc.strerror or exc}"
    if _speaks_http(address):  # Dask's bytes read as an HTTP request: a 400, or a wait for the request's end
        return "an HTTP server answers there, not a Dask scheduler: give the scheduler's own port (default 8786)"
    if isinstance(exc, (TimeoutError, asyncio.TimeoutError)):
        return f"no Dask handshake within {seconds:g} s: not a Dask scheduler?"
    if isinstance(exc, OSError) and exc.strerror:
        return exc.strerror
    if isinstance(exc, MemoryError):  # Dask read the peer's first bytes as the size of what follows
        return ("its answer is not Dask's protocol (its first bytes read as a message too large to hold): not a "
                "Dask scheduler")
    message = " ".join(str(exc).split())
    message = message if len(message) <= 160 else f"{message[:157]}..."
    return f"not a Dask scheduler? {type(exc).__name__}" + (f": {message}" if message else "")


def _transport_problem(address: str) -> str:
    """Why Dask cannot use the transport of ``address`` here (``""``: it can be tried): ``ucx://`` needs the
    UCX package, ``tls://`` and ``wss://`` Dask's TLS settings (without them Dask raised a ``TypeError`` about
    its own classes)."""
    scheme = urlsplit(address).scheme
    if scheme == "ucx" and importlib.util.find_spec("distributed_ucxx") is None:  # Dask's own ucx:// was removed
        return "ucx:// needs Dask's UCX transport, the distributed-ucxx package, which is not installed"
    if scheme in ("tls", "wss"):
        from distributed.security import Security

        if Security().get_connection_args("client").get("ssl_context") is None:
            return (f"{scheme}:// needs Dask's TLS settings (distributed.comm.tls.ca-file, "
                    "distributed.comm.tls.client.cert and .key in Dask's configuration), and none are set")
    return ""


#: Seconds the HTTP probe of :func:`_speaks_http` waits for an answer.
HTTP_PROBE_SECONDS = 1.0


def _speaks_http(address: str) -> bool:
    """Whether an HTTP server answers at the host and port of a ``tcp://`` or ``ws://`` ``address`` (asked
    only once Dask's handshake failed there)."""
    parts = urlsplit(address)
    if parts.scheme not in ("tcp", "ws"):
        return False
    try:
        with socket.create_connection((parts.hostname or "", parts.port or 0), timeout=HTTP_PROBE_SECONDS) as conn:
            conn.sendall(b"HEAD / HTTP/1.0\r\n\r\n")
            return conn.recv(5) == b"HTTP/"
    except (OSError, ValueError):
        return False


def _tcp_connect(address: str, seconds: float) -> None:
    """A plain TCP connection to ``tcp://host:port`` (a refused one says so at once; Dask retries it)."""
    parts = urlsplit(address)
    with socket.create_connection((parts.hostname or "", parts.port or 0), timeout=seconds):
        pass


async def _identity(address: str, seconds: float) -> None:
    """Dask's handshake, then the peer's identity (``{"op": "identity"}``): a scheduler's type is ``Scheduler``."""
    from distributed.comm import connect
    from distributed.security import Security

    # the client's connection arguments from Dask's configuration (TLS certificates), as Client uses them
    comm = await connect(address, timeout=seconds, **Security().get_connection_args("client"))
    try:
        await comm.write({"op": "identity", "reply": True})
        reply = await comm.read()
    finally:
        comm.abort()
    kind = reply.get("type") if isinstance(reply, dict) else None
    if kind != "Scheduler":
        raise ClusterError(f"no Dask scheduler at {address} (it answers as {kind or 'something else'})")


class DaskExecutor:
    """Tasks on the ``dask.distributed`` cluster at ``address``.

    Args:
        address: the scheduler, e.g. ``tcp://127.0.0.1:8786``.
        memory_per_worker: bytes one task may use (default: the smallest
            worker memory limit over its threads; ``None`` when the workers have none).

    Raises:
        ClusterError: no Dask scheduler answers at ``address`` within
            :data:`HANDSHAKE_SECONDS` (:func:`check_scheduler`), or it has no
            worker within :data:`CONNECT_SECONDS`.
        ImportError: ``dask.distributed`` is not installed.

    Attributes:
        workers: threads over all workers (tasks that can run at once).
        memory_per_worker: bytes one task may use (``None``: unlimited).
        where: the scheduler address.
    """

    def __init__(self, address: str, memory_per_worker: int | None = None) -> None:
        from distributed import Client

        check_scheduler(address)
        _quiet_client(True)
        try:
            self.client = Client(address, timeout=CONNECT_SECONDS, set_as_default=False)
        except (OSError, TimeoutError) as exc:
            _quiet_client(False)
            raise ClusterError(f"no Dask scheduler at {address} ({type(exc).__name__}: {exc})") from None
        try:
            self.client.wait_for_workers(1, timeout=CONNECT_SECONDS)
        except (OSError, TimeoutError):
            self.client.close()
            _quiet_client(False)
            raise ClusterError(f"the Dask scheduler at {address} has no worker after {CONNECT_SECONDS:g} s") from None
        workers = self.client.scheduler_info()["workers"].values()
        self.workers = sum(int(w.get("nthreads", 1)) for w in workers)
        limits = [int(w["memory_limit"]) // max(1, int(w.get("nthreads", 1))) for w in workers if w.get("memory_limit")]
        self.memory_per_worker = memory_per_worker if memory_per_worker is not None else min(limits, default=None)
        self.where = address
        self._futures: list[Any] = []

    def __enter__(self) -> DaskExecutor:
        return self

    def __exit__(self, exc_type: object, *rest: object) -> None:
        self.close(kill=exc_type is not None)

    def run(self, tasks: Sequence[Task]) -> Iterator[TaskOutcome]:
        """Run ``tasks`` on the cluster; yield each outcome as it finishes (refused tasks first)."""
        from distributed import as_completed

        runnable, refused = ordered(tasks, self.memory_per_worker)
        yield from refused
        if not runnable:
            return
        run_id = uuid.uuid4().hex[:8]
        by_key: dict[str, Task] = {}
        for i, task in enumerate(runnable):  # largest first: the first the highest priority
            key = f"xcheck-{run_id}-{i}"
            by_key[key] = task
            self._futures.append(
                self.client.submit(call, task.fn, task.args, key=key, pure=False, priority=len(runnable) - i)
            )
        finished = 0
        for future in as_completed(self._futures, loop=self.client.loop):
            task = by_key[future.key]
            try:
                ok, value, error, seconds = future.result()
            except Exception as exc:  # noqa: BLE001 - KilledWorker and other losses are the task's outcome
                if _scheduler_lost(exc):
                    raise ClusterError(
                        f"the Dask scheduler at {self.where} went away after {finished} of {len(runnable)} "
                        "tasks (the finished ones are kept; run again to go on)") from None
                yield TaskOutcome(task, "lost", error=f"{type(exc).__name__}: {exc}")
                finished += 1
                continue
            finally:
                future.release()
            finished += 1
            yield TaskOutcome(task, "done" if ok else "failed", value, error, seconds)
        self._futures.clear()

    def close(self, *, kill: bool = False) -> None:
        """Cancel what is still submitted (``kill``) and close the client."""
        with contextlib.suppress(Exception):
            if kill and self._futures:
                self.client.cancel(self._futures, force=True)
            self.client.close(timeout=CONNECT_SECONDS / 4)
        _quiet_client(False)


#: The loggers of ``dask.distributed`` that print tracebacks while the client loses its scheduler.
_CLIENT_LOGGERS = ("distributed.client", "distributed.utils", "distributed.core", "distributed.comm",
                   "distributed.batched")
#: Their levels before :func:`_quiet_client` raised them.
_SAVED_LEVELS: dict[str, int] = {}


def _quiet_client(quiet: bool) -> None:
    """Silence (or restore) :data:`_CLIENT_LOGGERS`: a scheduler killed mid-run printed the client's
    reconnection tracebacks; the run says it in one line instead (:class:`ClusterError`)."""
    for name in _CLIENT_LOGGERS:
        log = logging.getLogger(name)
        if quiet:
            _SAVED_LEVELS.setdefault(name, log.level)
            log.setLevel(logging.CRITICAL + 1)
        elif name in _SAVED_LEVELS:
            log.setLevel(_SAVED_LEVELS.pop(name))


def _scheduler_lost(exc: BaseException) -> bool:
    """Whether a task's exception says the client lost its scheduler (not that a worker died)."""
    from distributed.client import FutureCancelledError

    return isinstance(exc, FutureCancelledError) and "scheduler-connection-lost" in str(exc.reason)
