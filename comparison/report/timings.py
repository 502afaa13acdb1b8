"""The report's run times, kept apart from its results.

Everything in ``REPORT.md``, ``report.json`` and the table CSVs is a function
of the code and the inputs; run times, the machine and what came from the
cache are not. They go to ``timings.md``, ``timings.csv`` and ``timings.json``
(with the speed-accuracy figure, whose axis is seconds), so that regenerating
the report on another machine changes nothing else.
"""

from __future__ import annotations

import json
import math
import platform
from collections.abc import Collection, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from comparison.domain.wall import WallSpec
from comparison.report.computed import MACRO_TIMING_REPEATS, Results
from comparison.report.reproduce import machine
from comparison.report.scaling import scaling_table
from comparison.report.tables import Table
from comparison.runner import Method
from comparison.utilities.outputs import write_text

#: The files of a report that hold run times (everything else reproduces exactly).
TIMING_FILES = (
    "timings.md",
    "timings.csv",
    "timings.json",
    "speed_accuracy.png",
    "scaling.csv",
    "scaling.png",
)


def timings_table(res: Results, computed: Collection[tuple[WallSpec, Method]] = ()) -> Table:
    """Seconds of every computation of the report: the macro solve and each (wall, method) run.

    Args:
        res: the results.
        computed: the (wall, method) entries this run computed; the others' records were in the cache
            before it started ("read from the cache": the records this run computed in worker processes
            are read back from the cache too, and are not counted as such).
    """
    done_now = set(computed)
    t = Table(
        "timings",
        "Run times (as computed; a record read from the cache keeps the time of its computation)",
        ["wall", "method", "blocks", "build + solve s", "total s", "read from the cache"],
        keys=2,
    )
    t.add(
        "speed-accuracy base wall",
        f"macro (mean of {MACRO_TIMING_REPEATS} solves)",
        None,
        None,
        res.macro_seconds,
        "no",
    )
    for key, rec in res.records.items():
        if rec.skipped:
            continue
        micro = rec.micro
        build_solve = None if micro is None else micro.build_seconds + micro.solve_seconds
        t.add(rec.wall, key[1].label, None if micro is None else micro.blocks, build_solve, rec.seconds,
              "yes" if rec.cached and key not in done_now else "no")  # fmt: skip
    return t


def nonassociative_cost(res: Results) -> Table:
    """The non-associative method's seconds against the associative LP's: how much dearer the method that
    decides most verdicts is than the bound it refines.

    Two sums and the spread of the per-wall ratio, each from the records' seconds (:func:`timings_table`):

    * over the report: every computation of the non-associative method (the library's method, no research
      knob) against every computation of the associative LP by the default back end, whether or not the
      same wall has the other (Table 9's walls have only the associative LP);
    * over the walls with both: the same sums restricted to the walls (and bond phase and head-joint
      friction) that ran both;
    * per wall with both: the median, the 90th percentile and the largest of the ratio, with its wall.
    """
    from micro import DEFAULT_SOLVER

    t = Table("nonassociative_cost",
              "The non-associative method's seconds against the associative LP's (the default back end)",
              ["over", "computations", "non-associative s", "associative s", "ratio"], keys=1)
    assoc: dict[tuple[WallSpec, str, str], float] = {}
    nonassoc: dict[tuple[WallSpec, str, str], tuple[str, float]] = {}
    for (spec, method), rec in res.records.items():
        if rec.skipped or rec.seconds is None or not math.isfinite(rec.seconds):
            continue
        key = (spec, method.first_course, method.head_joints)
        if method.kind == "micro-assoc" and method.solver == DEFAULT_SOLVER:
            assoc[key] = float(rec.seconds)
        elif method.kind == "micro-nonassoc" and not method.tuning:
            nonassoc[key] = (f"{rec.wall} ({method.label})", float(rec.seconds))
    if not assoc or not nonassoc:
        return t
    both = [k for k in nonassoc if k in assoc and assoc[k] > 0]
    sum_n, sum_a = sum(v for _, v in nonassoc.values()), sum(assoc.values())
    t.add("the report", f"{len(nonassoc)} / {len(assoc)}", sum_n, sum_a, sum_n / sum_a)
    if both:
        pair_n, pair_a = sum(nonassoc[k][1] for k in both), sum(assoc[k] for k in both)
        t.add("the walls with both", f"{len(both)} / {len(both)}", pair_n, pair_a, pair_n / pair_a)
        ratios = sorted((nonassoc[k][1] / assoc[k], nonassoc[k][0]) for k in both)
        median, p90 = np.quantile([r for r, _ in ratios], [0.5, 0.9])
        t.add("per wall with both: median", len(both), None, None, float(median))
        t.add("per wall with both: 90th percentile", len(both), None, None, float(p90))
        t.add(f"per wall with both: largest, {ratios[-1][1]}", len(both), None, None, ratios[-1][0])
    return t


def write_timings(
    res: Results, out: Path, run: Mapping[str, Any], computed: Collection[tuple[WallSpec, Method]] = ()
) -> Path:
    """Write ``timings.md``, ``timings.csv`` and ``timings.json``.

    Args:
        res: the results.
        out: the report's directory.
        run: this run's facts (``seconds``, ``computed``, ``cached``); the machine is added here.
        computed: the (wall, method) entries this run computed (see :func:`timings_table`).

    Returns:
        The path of ``timings.md``.
    """
    run = {"python": platform.python_version(), "machine": machine(), **run}
    table = timings_table(res, computed)
    scaling = scaling_table(res)
    cost = nonassociative_cost(res)
    table.write_csv(out / "timings.csv")
    scaling.write_csv(out / "scaling.csv")
    write_text(out / "timings.json",
               json.dumps({"run": dict(run), "timings": table.records(), "scaling": scaling.records(),
                           "nonassociative_cost": cost.records()}, indent=1))
    path = out / "timings.md"
    write_text(
        path,
        f"# Run times of the report\n\nPython {run['python']} on {run['machine']}. "
        f"This run: {run['seconds']:.1f} s, {run['computed']} computations, {run['cached']} read from the result "
        "cache (keyed by the wall, the method and the source of the packages it runs). Seconds change from run "
        "to run and machine to machine; nothing else in the report does. Figures: `speed_accuracy.png`, "
        "`scaling.png`.\n\n"
        f"{table.markdown()}\n\n{scaling.markdown()}\n\n{cost.markdown()}\n"
    )
    return path


def previous_seconds(out: Path, items: Sequence[tuple[WallSpec, Method]]) -> dict[tuple[WallSpec, Method], float]:
    """The seconds each of ``items`` took in the report last written into ``out`` (its ``timings.json``,
    by wall and method): the expected cost of computing it again after a code change, for the progress
    display's ETA. Empty without that file (or one that cannot be read)."""
    try:
        rows = json.loads((out / "timings.json").read_text(encoding="utf-8"))["timings"]
        took = {(r["wall"], r["method"]): float(r["total s"]) for r in rows if r.get("total s") is not None}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return {}
    found = {(spec, m): took.get((spec.name, m.label), math.nan) for spec, m in items}
    return {k: s for k, s in found.items() if math.isfinite(s) and s > 0}
