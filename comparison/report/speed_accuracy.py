"""The report's speed-accuracy study as rows and a table: each method, back end and resolution against the
finest micro reference (the tables of the paper's walls: :mod:`comparison.report.tables`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from comparison.report.computed import Results
from comparison.report.tables import Table
from comparison.runner import MICRO_ASSOC, Record


@dataclass(frozen=True)
class SpeedRow:
    """One method, back end and resolution of the speed-accuracy study."""

    label: str
    family: str
    rows: int
    blocks: int | None
    seconds: float
    load_factor: float
    error: float  # |lambda - reference| / reference


def speed_reference(res: Results) -> Record:
    """The reference of the speed-accuracy study: the best micro record of the finest wall the
    non-associative LP runs on (:attr:`~comparison.report.plan.Plan.reference_rows`)."""
    return res.best_micro(res.plan.speed_spec(res.plan.reference_rows, "finest"))


def speed_rows(res: Results) -> list[SpeedRow]:
    """Every method, back end and resolution of the speed-accuracy study, against :func:`speed_reference`."""
    plan, lam_ref = res.plan, speed_reference(res).load_factor

    def row(label: str, family: str, rows: int, blocks: int | None, seconds: float, lam: float) -> SpeedRow:
        err = abs(lam - lam_ref) / lam_ref if math.isfinite(lam) else float("nan")
        return SpeedRow(label, family, rows, blocks, seconds, lam, err)

    base_rows = int(plan.base["rows"])
    out = [row("macro", "macro", base_rows, None, res.macro_seconds, res.macro[plan.speed_spec(base_rows)].load_factor)]
    for rows in plan.resolutions:
        spec = plan.speed_spec(rows)
        for solver in plan.solvers:
            rec = res.record(spec, replace(MICRO_ASSOC, solver=solver))
            blocks = None if rec.micro is None else rec.micro.blocks
            out.append(
                row(f"micro-assoc {solver}", f"micro-assoc {solver}", rows, blocks, rec.seconds, rec.load_factor)
            )
        for m in plan.methods[1:]:
            rec = res.record(spec, m)
            if rec.status != "not_run":
                blocks = None if rec.micro is None else rec.micro.blocks
                out.append(row(m.label, m.kind, rows, blocks, rec.seconds, rec.load_factor))
    return out


def speed_accuracy(res: Results) -> Table:
    """Each method, back end and block resolution against the finest micro reference."""
    ref = speed_reference(res)
    t = Table(
        "speed_accuracy",
        f"Speed against accuracy (reference: {ref.method.column}, {res.plan.reference_rows} rows, "
        f"λ = {ref.load_factor:.4f})",
        ["method", "rows", "blocks", "λ", "rel. error of λ"],
        keys=2,
    )
    for r in speed_rows(res):
        t.add(r.label, r.rows, r.blocks, r.load_factor, r.error)
    t.note = "Run times: `timings.md` (they change from run to run); figure: `speed_accuracy.png`."
    return t
