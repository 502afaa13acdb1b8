"""The report's results: the plan computed, read by the tables, figures and text."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import macro
from comparison.domain.wall import WallSpec
from comparison.report.plan import Plan
from comparison.runner import MechanismRecord, Method, Record, Runner

#: Macro solves timed for the speed-accuracy table (their mean is shown).
MACRO_TIMING_REPEATS = 20


@dataclass(frozen=True)
class Results:
    """Everything the report shows, computed from its :class:`~comparison.report.plan.Plan`.

    Attributes:
        plan: the plan.
        macro: the macro result of every wall of :meth:`Plan.macro_specs`.
        records: the record of every (wall, method) of :meth:`Plan.items`.
        mechanisms: the micro mechanisms of those records that have one.
        macro_seconds: mean time of one macro solve of the speed-accuracy base wall.
    """

    plan: Plan
    macro: dict[WallSpec, macro.MacroResult]
    records: dict[tuple[WallSpec, Method], Record]
    mechanisms: dict[tuple[WallSpec, Method], MechanismRecord]
    macro_seconds: float

    def record(self, spec: WallSpec, method: Method) -> Record:
        """The record of ``method`` on ``spec``.

        Raises:
            KeyError: the pair is not in the plan (a bug of the plan).
        """
        return self.records[(spec, method)]

    def best_micro(self, spec: WallSpec) -> Record:
        """The reference (non-associative) record when it has a load factor, else the associative one."""
        rec = self.record(spec, self.plan.reference)
        return rec if math.isfinite(rec.load_factor) else self.record(spec, self.plan.methods[0])

    def nonassoc_record(self, spec: WallSpec) -> Record | None:
        """The reference (non-associative) record of ``spec``, if the plan has one."""
        return self.records.get((spec, self.plan.reference))

    def mechanism_band(self, spec: WallSpec) -> tuple[float, float] | None:
        """The mechanism band of the reference record of ``spec``, if it has a finite one."""
        nonassoc = self.record(spec, self.plan.reference).nonassoc
        band = None if nonassoc is None else nonassoc.mechanism_band
        return None if band is None or not all(math.isfinite(v) for v in band) else band


def compute(plan: Plan, runner: Runner) -> Results:
    """Run the plan: the macro model in this process, the micro records through ``runner``."""
    macro_results = {spec: macro.solve(spec.to_macro()) for spec in plan.macro_specs()}
    records: dict[tuple[WallSpec, Method], Record] = {}
    mechanisms: dict[tuple[WallSpec, Method], MechanismRecord] = {}
    for item in plan.items():
        key = (item.spec, item.method)
        if item.skip:
            records[key] = Record(item.spec.name or "wall", item.method, 0.0, skipped="not_run", message=item.skip)
            continue
        records[key] = runner.run(*key)
        mechanism = runner.mechanism(*key)
        if mechanism is not None:
            mechanisms[key] = mechanism
    base = plan.speed_spec(int(plan.base["rows"]), "macro").to_macro()
    t0 = time.perf_counter()
    for _ in range(MACRO_TIMING_REPEATS):
        macro.solve(base)
    return Results(plan, macro_results, records, mechanisms, (time.perf_counter() - t0) / MACRO_TIMING_REPEATS)
