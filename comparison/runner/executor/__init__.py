"""Executors: run tasks in worker processes, largest first, memory-bounded, interrupt-safe.

* :mod:`~comparison.runner.executor.base`: :class:`Task`, :class:`TaskOutcome`
  and the :class:`Executor` protocol;
* :mod:`~comparison.runner.executor.processes`: :class:`LocalExecutor`, local
  processes that ignore Ctrl-C (the parent ends them) and die with their parent;
* :mod:`~comparison.runner.executor.cluster`: :class:`DaskExecutor`, every task
  a ``dask.distributed`` task on an existing cluster (optional dependency).

:func:`make_executor` picks one from the command line's ``--workers`` and
``--scheduler``.
"""

from __future__ import annotations

import os

from comparison.runner.executor.base import Executor, OutcomeKind, Task, TaskOutcome
from comparison.runner.executor.processes import LocalExecutor


def make_executor(
    workers: int | None = None, scheduler: str | None = None, memory_per_worker: int | None = None
) -> Executor:
    """A :class:`~comparison.runner.executor.cluster.DaskExecutor` on ``scheduler`` if given, else a
    :class:`LocalExecutor`.

    Args:
        workers: local processes (default: the number of CPUs); ignored with a scheduler.
        scheduler: address of a ``dask.distributed`` scheduler.
        memory_per_worker: bytes one task may use (default: see each executor).

    Raises:
        ImportError: a scheduler is given and ``dask.distributed`` is not installed.
        comparison.runner.executor.cluster.ClusterError: the scheduler cannot be reached.
    """
    if scheduler is not None:
        from comparison.runner.executor.cluster import DaskExecutor

        return DaskExecutor(scheduler, memory_per_worker)
    return LocalExecutor(workers or os.cpu_count() or 1, memory_per_worker)


__all__ = ["Executor", "LocalExecutor", "TaskOutcome", "OutcomeKind", "Task", "make_executor"]
