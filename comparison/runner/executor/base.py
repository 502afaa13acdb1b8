"""What every executor shares: tasks, outcomes, the call wrapper, the memory refusal.

A :class:`Task` is a module-level function with picklable arguments (a worker
imports the function by name, so a Dask worker needs only this package
installed), its cost (the order of the work: larger tasks go first) and its
estimated peak memory. An executor yields one :class:`TaskOutcome` per task, in the
order they finish; a task that raises, whose worker dies, or that would not fit
in a worker's memory gives an outcome with that status, never an exception, so
one bad cell never aborts a run.
"""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable, Hashable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, Literal, Protocol, Self

#: How a task ended: ``done`` (its value is there), ``failed`` (it raised),
#: ``lost`` (its worker died under it), ``refused`` (its memory estimate
#: exceeds a worker's memory; not run).
OutcomeKind = Literal["done", "failed", "lost", "refused"]


@dataclass(frozen=True)
class Task:
    """One unit of work.

    Attributes:
        key: identifies the task to its caller (any hashable).
        fn: a module-level function (picklable by reference).
        args: its positional arguments (picklable).
        cost: the work it is expected to be (e.g. seconds): the largest tasks start first.
        memory: estimated peak memory in bytes (0: unknown, never refused).
        label: a short name for progress lines.
    """

    key: Hashable
    fn: Callable[..., Any]
    args: tuple[Any, ...]
    cost: float = 0.0
    memory: int = 0
    label: str = ""


@dataclass(frozen=True)
class TaskOutcome:
    """How one task ended.

    Attributes:
        task: the task.
        kind: see :data:`OutcomeKind`.
        value: the function's return value (``None`` unless ``kind == "done"``).
        error: why there is no value (``""`` when done).
        seconds: wall time of the call in its worker (0 when not run).
    """

    task: Task
    kind: OutcomeKind
    value: Any = None
    error: str = ""
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        """The task returned a value."""
        return self.kind == "done"


class Executor(Protocol):
    """Runs tasks in worker processes, largest first; a context manager that ends its workers on exit.

    Attributes:
        workers: tasks that can run at once.
        memory_per_worker: the memory one task may use, in bytes (``None``: unknown).
        where: a short description for metadata (``"local, 2 processes"``, a scheduler address).
    """

    workers: int
    memory_per_worker: int | None
    where: str

    def run(self, tasks: Sequence[Task]) -> Iterator[TaskOutcome]:
        """Run ``tasks``; yield each outcome as it finishes (refused tasks first)."""
        ...

    def __enter__(self) -> Self: ...

    def __exit__(self, exc_type: object, *rest: object) -> None: ...


def call(fn: Callable[..., Any], args: tuple[Any, ...]) -> tuple[bool, Any, str, float]:
    """Run ``fn(*args)`` in a worker: ``(ok, value, error, seconds)``; an exception becomes its message."""
    t0 = time.perf_counter()
    try:
        return True, fn(*args), "", time.perf_counter() - t0
    except Exception as exc:  # noqa: BLE001 - recorded as the task's failure, never aborting the run
        return False, None, describe(exc), time.perf_counter() - t0


def describe(exc: BaseException) -> str:
    """``Type: message`` and the innermost frame of ``exc``, on one line."""
    frames = traceback.extract_tb(exc.__traceback__)
    where = f" (at {frames[-1].filename.rsplit('/', 1)[-1]}:{frames[-1].lineno})" if frames else ""
    return f"{type(exc).__name__}: {exc}{where}".replace("\n", " ")


def ordered(tasks: Sequence[Task], memory_per_worker: int | None) -> tuple[list[Task], list[TaskOutcome]]:
    """The tasks to run, largest first, and the outcomes of those refused for their memory."""
    runnable: list[Task] = []
    refused: list[TaskOutcome] = []
    for task in tasks:
        if memory_per_worker is not None and task.memory > memory_per_worker:
            error = (
                f"estimated {task.memory / 1e9:.3g} GB exceeds a worker's {memory_per_worker / 1e9:.3g} GB: not run"
            )
            refused.append(TaskOutcome(task, "refused", error=error))
        else:
            runnable.append(task)
    runnable.sort(key=lambda t: t.cost, reverse=True)
    return runnable, refused
