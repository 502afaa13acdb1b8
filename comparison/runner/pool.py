"""Compute missing cache entries on an executor, largest walls first, and store them.

The workers only compute (:func:`comparison.runner.runner.compute`); this
process stores each record in the cache as it arrives, so that the workers need
no shared disk (a Dask cluster) and a run killed at any point keeps every
record finished before it: a restart computes only the rest.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from comparison.progress import Progress
from comparison.runner.cache import ResultCache
from comparison.runner.executor import Executor, Task, TaskOutcome
from comparison.runner.methods import Method
from comparison.runner.records import MechanismRecord, Record
from comparison.runner.runner import compute, summary_line
from comparison.wall import WallSpec

Item = tuple[WallSpec, Method]
#: A computed record and its micro mechanism.
Entry = tuple[Record, MechanismRecord | None]


def approximate_blocks(spec: WallSpec) -> int:
    """Blocks of the running-bond wall of ``spec`` (to within one per course)."""
    return int(round(spec.rows * (spec.length / spec.block_length + 0.5)))


def compute_task(spec: WallSpec, method: Method) -> Task:
    """The task that computes ``method`` on ``spec``: its cost is the wall's blocks, its memory their estimate."""
    from micro.geometry import estimate_bytes

    blocks = approximate_blocks(spec)
    memory = 0 if method.kind == "macro" else estimate_bytes(blocks)
    return Task((spec, method), compute, (spec, method), blocks, memory, f"{spec.name or 'wall'}: {method.label}")


@dataclass(frozen=True)
class Prefetched:
    """What :func:`prefetch` did.

    Attributes:
        computed: records computed (stored, or kept in ``unstored``).
        failures: the outcome of every item that gave no record (failed, lost or refused).
        unstored: the entries computed but not stored, their result being cut short by a wall-clock
            limit (:func:`~comparison.runner.cache.stopped_by_wall_clock`): this run uses them, a later
            one computes them again.
    """

    computed: int = 0
    failures: dict[Item, TaskOutcome] = field(default_factory=dict)
    unstored: dict[Item, Entry] = field(default_factory=dict)


def prefetch(
    cache: ResultCache, items: Sequence[Item], executor: Executor, progress: Progress | None = None
) -> Prefetched:
    """Compute the records of ``items`` on ``executor`` and store each in ``cache`` as it arrives.

    A failure is kept in the result, never raised: the other items go on.
    """
    computed = 0
    failures: dict[Item, TaskOutcome] = {}
    unstored: dict[Item, Entry] = {}
    for outcome in executor.run([compute_task(spec, method) for spec, method in items]):
        key: Item = outcome.task.key  # type: ignore[assignment]
        if outcome.ok:
            record, mechanism = outcome.value
            if not cache.store(key[0], record, mechanism):
                unstored[key] = (record, mechanism)
            computed += 1
            line = summary_line(record)
        else:
            failures[key] = outcome
            line = f"{outcome.task.label}: {outcome.kind}: {outcome.error}"
        if progress is not None:
            progress.advance(line)
    return Prefetched(computed, failures, unstored)
