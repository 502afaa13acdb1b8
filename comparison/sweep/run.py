"""Run a sweep: the macro side in one vectorised call, the micro side on an executor through the cache,
then its validation page.

The micro cells go through the report's content-addressed cache (keyed by the
wall, the method and its options, and the code version): a cell in the cache is
read, the others are computed on the executor, largest walls first, and stored
as each arrives. A sweep killed at any point and started again computes only
what is missing, and two sweeps that share walls compute them once. A cell
whose computation fails, whose worker dies, or whose memory estimate exceeds a
worker's memory is recorded with that status; the sweep goes on. A user's
macro model (:mod:`~comparison.sweep.usermodel`) runs in this process, once
per wall. The page (:mod:`~comparison.sweep.page`) is drawn from the table
alone, so a sweep resumed from the cache writes the same page.
"""

from __future__ import annotations

import contextlib
import csv
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from comparison.runner import Method, Prefetched, Record, ResultCache, code_version, prefetch
from comparison.runner.executor import Executor
from comparison.runner.fingerprint import versions_used
from comparison.sweep.grid import Grid
from comparison.sweep.isolation import ModelProcess
from comparison.sweep.plan import Cell, WallPoint, cells
from comparison.sweep.table import FAILURE_STATUS, machine, number, read_table, write_meta, write_table
from comparison.sweep.usermodel import UserModel
from comparison.utilities.progress import Progress


@dataclass(frozen=True)
class SweepRun:
    """What a sweep wrote and did.

    Attributes:
        table: the CSV table.
        meta: the JSON metadata.
        counts: cells by what happened to them (``macro``, ``user`` (a user model's cells), ``cached``,
            ``computed``, ``failed`` (a micro computation, or a user model that raised or gave no number),
            ``skipped``).
        macro_walls_per_second: speed of the vectorised macro side.
        micro_seconds: wall time of the micro computations.
        page: the validation page (``None``: not asked for).
    """

    table: Path
    meta: Path
    counts: dict[str, int]
    macro_walls_per_second: float
    micro_seconds: float
    page: Path | None = None


def run_sweep(
    grid: Grid, out_dir: Path, *, cache: ResultCache, executor: Executor, progress: Progress, page: bool = True
) -> SweepRun:
    """Compute every cell of ``grid`` and write ``<name>.csv`` and ``<name>.json`` into ``out_dir``, and
    with ``page`` the validation page ``<name>.md`` and its figures (:func:`~comparison.sweep.page.write_page`)."""
    start = time.perf_counter()
    plan = cells(grid)
    known = previous_seconds(out_dir / f"{grid.name}.csv")  # before the table is written again
    rows: dict[int, dict[str, Any]] = {}
    macro_rate = _macro_side(plan, rows)
    user_failed = _user_side(plan, rows)
    early = Prefetched()
    early_items: set[Any] = set()
    if any(c.where_needed for c in plan):  # the associative LPs first: their bounds say where it is needed
        first = [c.item for c in plan if c.micro and not c.skip and c.method.kind == "micro-assoc"]
        early_items = set(dict.fromkeys(i for i in first if i is not None and i not in cache))
        early = prefetch(cache, list(early_items), executor, progress)
        plan = [needed(c, plan, rows, cache) if c.where_needed else c for c in plan]
    runnable = [c for c in plan if c.micro and not c.skip]
    items = {c.index: c.item for c in runnable if c.item is not None}
    cached = {i for i, item in items.items() if item in cache and item not in early_items}
    pending = list(dict.fromkeys(item for i, item in items.items() if i not in cached))
    skipped = sum(1 for c in plan if c.skip)
    users = sum(1 for c in plan if isinstance(c.method, UserModel) and not c.skip)
    progress.say(
        f"plan: {len(plan)} cells: {len(plan) - len(runnable) - skipped - users} macro (one vectorised call), "
        + (f"{users} of user models, " if users else "")
        + f"{len(runnable)} micro ({len(cached)} cached, {len(pending)} to compute on {executor.where}), "
        f"{skipped} skipped"
    )
    t0 = time.perf_counter()
    wanted = {cell.item: cell for cell in reversed(runnable)}  # the first cell of each item
    seconds = {item: known[_row_key(wanted[item])] for item in pending if _row_key(wanted[item]) in known}
    done = prefetch(cache, [i for i in pending if i not in cache], executor, progress, cached=len(cached),
                    known=seconds)
    done = Prefetched(done.computed + early.computed, {**early.failures, **done.failures},
                      {**early.unstored, **done.unstored})
    micro_seconds = time.perf_counter() - t0
    progress.close()
    rows.update({c.index: _micro_row(c, cache, done, c.index in cached) for c in plan if c.micro})
    counts = {
        "cells": len(plan),
        "macro": sum(1 for c in plan if not c.micro and not c.skip) - users,
        "user": users,
        "cached": len(cached),
        "computed": done.computed,
        "failed": len(done.failures) + user_failed,
        "skipped": skipped,
    }
    table = write_table((rows[c.index] for c in plan), out_dir / f"{grid.name}.csv")
    meta = {
        "grid": grid.to_dict(),
        "counts": counts,
        "executor": {"where": executor.where, "workers": executor.workers, "memory": executor.memory_per_worker},
        "code": code_version(cache.directory),
        "versions": versions_used(),
        "machine": machine(),
        "macro_walls_per_second": macro_rate,
        "micro_seconds": micro_seconds,
        "seconds": time.perf_counter() - start,
    }
    path = write_meta(meta, out_dir / f"{grid.name}.json")
    written = None
    if page:
        from comparison.sweep.page import write_page

        written = write_page(table, out_dir, grid.name).path
    progress.say(
        f"{counts['computed']} computed, {counts['cached']} cached, {counts['failed']} failed, "
        f"{counts['skipped']} skipped in {meta['seconds']:.1f} s: {table}"
    )
    return SweepRun(table, path, counts, macro_rate, micro_seconds, written)


def needed(cell: Cell, plan: Sequence[Cell], rows: dict[int, dict[str, Any]], cache: ResultCache) -> Cell:
    """A ``where_needed`` cell (over the block limit) made runnable where its wall's verdict needs the
    non-associative method: the macro λ is finite and not above the associative LP's of the same wall and
    bond (:func:`comparison.domain.proof.above`); else it stays skipped, its message saying why."""
    from comparison.domain.proof import above

    lam_macro = next((rows[c.index]["load_factor"] for c in plan if c.point == cell.point and c.method.kind == "macro"
                      and c.index in rows), math.nan)
    assoc = [c for c in plan if c.point == cell.point and c.method.kind == "micro-assoc" and c.item is not None
             and not c.skip and c.spec == cell.spec and isinstance(c.method, Method)
             and isinstance(cell.method, Method) and c.method.first_course == cell.method.first_course
             and c.method.head_joints == cell.method.head_joints]
    record = cache.load(*assoc[0].item) if assoc and assoc[0].item is not None else None
    lam_assoc = record.load_factor if record is not None else math.nan
    if not (math.isfinite(lam_macro) and math.isfinite(lam_assoc)):
        return replace(cell, message=f"{cell.message}; no macro or associative value to tell whether it is needed")
    if above(lam_macro, lam_assoc):
        return replace(cell, message=f"{cell.message}; not needed: the associative bound settles the verdict")
    return replace(cell, skip="", message="")


def _row_key(cell: Cell) -> tuple[str, str]:
    """A cell's wall and method as the table writes them (how :func:`previous_seconds` finds it)."""
    return cell.point.label, cell.method.label


def previous_seconds(table: Path) -> dict[tuple[str, str], float]:
    """The seconds each micro cell of an earlier run of the same sweep took, by ``(wall, method)``: the
    expected cost of computing it again (after a code change), for the progress display's ETA. Empty
    without an earlier table (or one that cannot be read)."""
    try:
        rows = read_table(table) if table.is_file() else []
    except (OSError, UnicodeDecodeError, csv.Error):
        return {}
    out: dict[tuple[str, str], float] = {}
    for row in rows:
        if row.get("kind", "").startswith("micro") and row.get("blocks"):
            with contextlib.suppress(ValueError):
                s = number(row.get("seconds", ""))
                if math.isfinite(s) and s > 0:
                    out[(row.get("wall", ""), row.get("method", ""))] = s
    return out


def _inputs(cell: Cell) -> dict[str, Any]:
    """The columns that say what the cell is."""
    p, m = cell.point, cell.method
    micro = m if isinstance(m, Method) and cell.micro else None
    return {
        "cell": cell.index,
        "wall": p.label,
        **{k: getattr(p, k) for k in ("t", "m", "rows", "f", "p", "storeys")},
        "method": m.label,
        "kind": m.kind,
        "solver": micro.solver if micro is not None and micro.kind == "micro-assoc" else None,
        "scheme": micro.scheme if micro is not None and micro.kind == "micro-nonassoc" else None,
        "first_course": micro.first_course if micro is not None else None,
        "head_joints": micro.head_joints if micro is not None else None,
        "ends": cell.spec.ends if micro is not None and cell.spec is not None else None,
        "half_blocks": _half_blocks(p),
        "blocks": cell.blocks or None,
    }


def _half_blocks(p: WallPoint) -> float:
    """The wall's length in half blocks, ``L/(l/2) = 2 rows m / t``: a whole number but for walls whose courses
    end in closers or cut pieces (``docs/micro/walls.md``)."""
    return 2.0 * p.rows * p.m / p.t


def _skipped(cell: Cell) -> dict[str, Any]:
    return {**_inputs(cell), "load_factor": math.nan, "status": cell.skip, "message": cell.message}


def _macro_side(plan: Sequence[Cell], rows: dict[int, dict[str, Any]]) -> float:
    """The rows of the macro cells, one :func:`macro.sweep` call per number of storeys; walls per second."""
    import macro
    from macro.sweep import MECHANISMS

    todo = [c for c in plan if c.method.kind == "macro"]
    rows.update({c.index: _skipped(c) for c in todo if c.skip})
    todo = [c for c in todo if not c.skip]
    seconds = 0.0
    for storeys in sorted({c.point.storeys for c in todo}):
        group = [c for c in todo if c.point.storeys == storeys]
        t, m, rows_, f, p = (np.array([getattr(c.point, k) for c in group]) for k in ("t", "m", "rows", "f", "p"))
        t0 = time.perf_counter()
        r = macro.sweep(t, m, rows_, f, p, storeys=storeys)
        dt = time.perf_counter() - t0
        seconds += dt
        results = zip(
            r.load_factor.tolist(),
            r.rocking_load_factor.tolist(),
            r.alpha_c_deg.tolist(),
            r.hinge_storey.tolist(),
            r.mechanism.tolist(),
            strict=True,
        )
        for cell, (lam, rocking, alpha, hinge, mechanism) in zip(group, results, strict=True):
            rows[cell.index] = {
                **_inputs(cell),
                "load_factor": lam,
                "status": "optimal" if math.isfinite(lam) else "failed",
                "rocking_load_factor": rocking,
                "alpha_c_deg": alpha,
                "hinge_storey": hinge,
                "mechanism": MECHANISMS[mechanism],
                "seconds": dt / len(group),
                "cached": False,
            }
    return len(todo) / seconds if seconds > 0 else math.nan


def _user_side(plan: Sequence[Cell], rows: dict[int, dict[str, Any]]) -> int:
    """The rows of the user models' cells, each model called once per wall in this process; how many
    raised or gave no number."""
    failed = 0
    models = list(dict.fromkeys(c.method for c in plan if isinstance(c.method, UserModel)))
    with ModelProcess(models) as process:
        for cell in plan:
            model = cell.method
            if not isinstance(model, UserModel):
                continue
            if cell.skip:
                rows[cell.index] = _skipped(cell)
                continue
            p = cell.point
            lam, status, message, seconds = process.evaluate(model, (p.t, p.m, p.rows, p.f, p.p, p.storeys),
                                                             where=p.label)
            failed += status != "optimal"
            rows[cell.index] = {**_inputs(cell), "load_factor": lam, "status": status, "seconds": seconds,
                                "cached": False, "message": message}
    return failed


def _micro_row(cell: Cell, cache: ResultCache, done: Prefetched, cached: bool) -> dict[str, Any]:
    """The row of a micro cell: skipped, failed, or its record (from the cache, or computed and not stored)."""
    if cell.skip:
        return _skipped(cell)
    item = cell.item
    assert item is not None
    outcome = done.failures.get(item)
    if outcome is not None:
        status = FAILURE_STATUS[outcome.kind]
        return {**_skipped(cell), "status": status, "seconds": outcome.seconds, "message": outcome.error}
    unstored = done.unstored.get(item)
    record = unstored[0] if unstored is not None else cache.load(*item)
    if record is None:  # pragma: no cover - stored (or kept) by prefetch a moment ago
        raise RuntimeError(f"cell {cell.index} ({cell.point.label}, {cell.method.label}) missing from the cache")
    return {**_inputs(cell), **_record_fields(record), "cached": cached}


def _record_fields(record: Record) -> dict[str, Any]:
    """The result columns of a micro record."""
    r = record.micro
    fields: dict[str, Any] = {"load_factor": record.load_factor, "status": record.status, "seconds": record.seconds}
    if r is None:
        return {**fields, "message": record.message}
    fields.update(blocks=r.blocks, iterations=r.iterations, direction=r.direction, message=r.message or record.message)
    local = record.local
    fields.update(held_load_factor=local.held_load_factor if local else None,
                  local_mechanism=local.description if local else None)
    na = record.nonassoc
    if na is not None:
        band, mband = na.lambda_band or (None, None), na.mechanism_band or (None, None)
        fields.update(associative_load_factor=na.associative_load_factor, band_lo=band[0], band_hi=band[1])
        fields.update(mechanism_band_lo=mband[0], mechanism_band_hi=mband[1])
        fields.update(quoted=na.quoted, iterated_load_factor=na.iterated_load_factor, lowest_stop=na.lowest_stop)
    return fields
