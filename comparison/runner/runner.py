"""Run one method on one wall: :func:`compute`, and the caching :class:`Runner`.

A :class:`Runner` returns the :class:`~comparison.runner.records.Record` of a
method on a wall, from memory, from the on-disk
:class:`~comparison.runner.cache.ResultCache` (see there for the key and for
where the cache lives) or computed anew, and keeps the micro mechanisms for the
figures.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from comparison.domain.failure import FailureMode, failure_mode
from comparison.domain.wall import WallSpec
from comparison.domain.wall_mechanism import solve_wall_mechanism
from comparison.runner.cache import ResultCache
from comparison.runner.macro_record import macro_record
from comparison.runner.methods import Method
from comparison.runner.records import MechanismRecord, Record
from micro.records import AssociativeRecord, NonAssociativeRecord


def compute(spec: WallSpec, method: Method) -> tuple[Record, MechanismRecord | None]:
    """Run ``method`` on ``spec``: its record and, for a micro solve with a mechanism, the mechanism.

    A micro record says whether a local mechanism governs and gives the wall's own value
    (``Record.local``, :func:`comparison.domain.wall_mechanism.solve_wall_mechanism`: the held wall is solved
    only then);
    the mechanism kept for the figures is the block model's.

    A micro wall that cannot be built (e.g. a length that is not a whole number
    of half blocks) gives a ``not_applicable`` record, not an exception.
    """
    name = spec.name or "wall"
    t0 = time.perf_counter()
    if method.kind == "macro":
        import macro

        result = macro_record(macro.solve(spec.to_macro()))
        return Record(name, method, time.perf_counter() - t0, result), None
    import micro

    try:
        wall = spec.to_micro(first_course=method.first_course, head_joints=method.head_joints)
    except ValueError as exc:
        return Record(name, method, 0.0, skipped="not_applicable", message=str(exc)), None
    mechanism = None
    record: AssociativeRecord | NonAssociativeRecord
    solve: Callable[[micro.BlockWall], micro.LimitResult | micro.NonAssociativeResult]
    if method.kind == "micro-assoc":
        res = micro.solve_associative(wall, solver=method.solver)
        solve = functools.partial(micro.solve_associative, solver=method.solver)
        record = res.to_record()
        first: micro.LimitResult | micro.NonAssociativeResult = res
        if res.velocities is not None and res.direction:
            mechanism = MechanismRecord(np.asarray(res.velocities), res.direction)
    else:
        solve = functools.partial(micro.solve_nonassociative,
                                  tuning=method.nonassoc_tuning() if method.tuning else None)
        nres = solve(wall)
        first = nres
        record = nres.to_record()
        # the mechanism of the state quoted: the lowest certified one, else the iterated LP's
        low = nres.lowest_state
        gov = low.state if low is not None else next((d for d in nres.directions if d.direction == nres.direction),
                                                     None)
        if gov is not None and gov.mechanism is not None:
            mechanism = MechanismRecord(np.asarray(gov.mechanism.velocities), gov.direction)
    failure: FailureMode | None = None
    message = ""
    if mechanism is not None:
        try:
            failure = failure_mode(wall, mechanism.velocities, mechanism.direction)
        except ValueError as exc:
            message = str(exc)
    local = solve_wall_mechanism(wall, solve, first=first).to_record()
    return Record(name, method, time.perf_counter() - t0, record, failure, message=message, local=local), mechanism


def summary_line(record: Record) -> str:
    """One line for a progress display: the wall, the method, lambda, the status and the time."""
    return (
        f"{record.wall}: {record.method.label}: lambda = {record.load_factor:.4f} ({record.status}) "
        f"in {record.seconds:.2f} s"
    )


class Runner:
    """Compute methods on walls, each once, caching records on disk.

    Args:
        cache_dir: where records live (``None``: no disk cache, results kept in memory only).
        progress: called with one line per computation (``None``: silent).

    Attributes:
        computed: computations run by this runner.
        hits: records read from the disk cache.
    """

    def __init__(self, cache_dir: Path | None, progress: Callable[[str], None] | None = None) -> None:
        self.cache = None if cache_dir is None else ResultCache(cache_dir)
        self.progress = progress
        self.computed = 0
        self.hits = 0
        self._memory: dict[tuple[WallSpec, Method], tuple[Record, MechanismRecord | None]] = {}

    def run(self, spec: WallSpec, method: Method) -> Record:
        """The record of ``method`` on ``spec``: from memory, from the cache, or computed."""
        return self._entry(spec, method)[0]

    def mechanism(self, spec: WallSpec, method: Method) -> MechanismRecord | None:
        """The mechanism of the micro record of ``method`` on ``spec``, if it has one."""
        return self._entry(spec, method)[1]

    def keep(self, entries: Mapping[tuple[WallSpec, Method], tuple[Record, MechanismRecord | None]]) -> None:
        """Hold ``entries`` (computed elsewhere, not in the cache) for this runner's lifetime."""
        self._memory.update(entries)

    def _entry(self, spec: WallSpec, method: Method) -> tuple[Record, MechanismRecord | None]:
        key = (spec, method)
        if key in self._memory:
            return self._memory[key]
        stored = None if self.cache is None else self.cache.entry(spec, method)
        if stored is not None:
            self.hits += 1
            entry = stored
        else:
            entry = compute(spec, method)
            self.computed += 1
            record = entry[0]
            if self.progress:
                self.progress(summary_line(record))
            if self.cache is not None:
                self.cache.store(spec, *entry)
        self._memory[key] = entry
        return entry
