"""The distributed executor: every task a ``dask.distributed`` task on an existing cluster.

The scheduler is given by its address (``tcp://host:port``); its workers need
only this package installed (a task's function is imported there by name).
Tasks are submitted with their cost as Dask priority, so the largest start
first; a task that raises comes back as ``failed``, one whose workers kept dying
(Dask's ``KilledWorker``) as ``lost``; a task whose memory estimate exceeds a
worker's memory limit (shared by its threads) is refused before submission. On
an exception (Ctrl-C included) the submitted tasks are cancelled and the client
closed.
"""

from __future__ import annotations

import contextlib
import uuid
from collections.abc import Iterator, Sequence
from typing import Any

from comparison.runner.executor.base import Task, TaskOutcome, call, ordered

#: Seconds to wait for the scheduler to answer and for at least one worker.
CONNECT_SECONDS = 20.0


class ClusterError(RuntimeError):
    """The scheduler cannot be reached, or has no worker."""


class DaskExecutor:
    """Tasks on the ``dask.distributed`` cluster at ``address``.

    Args:
        address: the scheduler, e.g. ``tcp://127.0.0.1:8786``.
        memory_per_worker: bytes one task may use (default: the smallest
            worker memory limit over its threads; ``None`` when the workers have none).

    Raises:
        ClusterError: no scheduler answers at ``address`` within
            :data:`CONNECT_SECONDS`, or it has no worker.
        ImportError: ``dask.distributed`` is not installed.

    Attributes:
        workers: threads over all workers (tasks that can run at once).
        memory_per_worker: bytes one task may use (``None``: unlimited).
        where: the scheduler address.
    """

    def __init__(self, address: str, memory_per_worker: int | None = None) -> None:
        from distributed import Client

        try:
            self.client = Client(address, timeout=CONNECT_SECONDS, set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise ClusterError(f"no Dask scheduler at {address} ({type(exc).__name__}: {exc})") from None
        try:
            self.client.wait_for_workers(1, timeout=CONNECT_SECONDS)
        except (OSError, TimeoutError):
            self.client.close()
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
        for i, task in enumerate(runnable):
            key = f"xcheck-{run_id}-{i}"
            by_key[key] = task
            self._futures.append(
                self.client.submit(call, task.fn, task.args, key=key, pure=False, priority=int(task.cost))
            )
        for future in as_completed(self._futures, loop=self.client.loop):
            task = by_key[future.key]
            try:
                ok, value, error, seconds = future.result()
            except Exception as exc:  # noqa: BLE001 - KilledWorker and other losses are the task's outcome
                yield TaskOutcome(task, "lost", error=f"{type(exc).__name__}: {exc}")
                continue
            finally:
                future.release()
            yield TaskOutcome(task, "done" if ok else "failed", value, error, seconds)
        self._futures.clear()

    def close(self, *, kill: bool = False) -> None:
        """Cancel what is still submitted (``kill``) and close the client."""
        with contextlib.suppress(Exception):
            if kill and self._futures:
                self.client.cancel(self._futures, force=True)
            self.client.close(timeout=CONNECT_SECONDS / 4)
