"""Compute missing cache entries on an executor, largest walls first, and store them.

The workers only compute (:func:`comparison.runner.runner.compute`); this
process stores each record in the cache as it arrives, so that the workers need
no shared disk (a Dask cluster) and a run killed at any point keeps every
record finished before it: a restart computes only the rest.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from comparison.domain.wall import WallSpec
from comparison.runner.cache import ResultCache
from comparison.runner.executor import Executor, Task, TaskOutcome
from comparison.runner.methods import Method
from comparison.runner.records import MechanismRecord, Record
from comparison.runner.runner import compute, summary_line
from comparison.utilities.progress import Progress

Item = tuple[WallSpec, Method]
#: A computed record and its micro mechanism.
Entry = tuple[Record, MechanismRecord | None]


def approximate_blocks(spec: WallSpec) -> int:
    """Blocks of the running-bond wall of ``spec`` (to within one per course)."""
    return int(round(spec.rows * (spec.length / spec.block_length + 0.5)))


#: The seconds a micro computation is expected to take, ``a * blocks ** b`` per kind (``(a, b)``): fitted
#: to the run times of a full report (every micro record, 50 to 7,575 blocks). Only their ratios matter:
#: they order the work (largest first) and weigh the progress display's ETA.
COST_MODEL: Mapping[str, tuple[float, float]] = {"micro-assoc": (7.5e-5, 1.32), "micro-nonassoc": (3.1e-4, 1.54)}
#: The macro model's expected seconds (a millisecond, whatever the wall).
MACRO_SECONDS = 1e-3


def expected_seconds(spec: WallSpec, method: Method) -> float:
    """The seconds ``method`` is expected to take on ``spec``, from its blocks (:data:`COST_MODEL`)."""
    if method.kind not in COST_MODEL:
        return MACRO_SECONDS
    a, b = COST_MODEL[method.kind]
    return a * max(approximate_blocks(spec), 1) ** b


def compute_task(spec: WallSpec, method: Method, seconds: float | None = None) -> Task:
    """The task that computes ``method`` on ``spec``: its cost the seconds it is expected to take (``seconds``,
    e.g. what it took last time, else :func:`expected_seconds`), its memory the blocks' estimate."""
    from micro.memory import estimate_bytes

    blocks = approximate_blocks(spec)
    memory = 0 if method.kind == "macro" else estimate_bytes(blocks)
    cost = seconds if seconds is not None and seconds > 0 else expected_seconds(spec, method)
    return Task((spec, method), compute, (spec, method), cost, memory, f"{spec.name or 'wall'}: {method.label}")


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
    cache: ResultCache,
    items: Sequence[Item],
    executor: Executor,
    progress: Progress | None = None,
    *,
    cached: int = 0,
    known: Mapping[Item, float] | None = None,
) -> Prefetched:
    """Compute the records of ``items`` on ``executor`` and store each in ``cache`` as it arrives.

    A failure is kept in the result, never raised: the other items go on.

    Args:
        cache: where the records go.
        items: the (wall, method) pairs to compute.
        executor: where they run.
        progress: started here on ``items`` (``"micro"``), its ETA weighted by each one's expected seconds
            (:func:`compute_task`), and advanced as each ends.
        cached: the entries of the run already in the cache (for the progress display's lines).
        known: seconds some items took before (a previous run's), their expected cost.
    """
    computed = 0
    failures: dict[Item, TaskOutcome] = {}
    unstored: dict[Item, Entry] = {}
    known = known or {}
    tasks = [compute_task(spec, method, known.get((spec, method))) for spec, method in items]
    if progress is not None:
        progress.start(len(tasks), "micro", cached=cached, cost=sum(t.cost for t in tasks))
    for outcome in executor.run(tasks):
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
            progress.advance(line, cost=outcome.task.cost)
    return Prefetched(computed, failures, unstored)
