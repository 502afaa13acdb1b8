"""Scaling of the micro methods: run time against blocks (log-log) with fitted exponents.

Every micro record of the report's plan (the paper's walls, the bond variants,
the sensitivity sweeps, the speed-accuracy resolutions) is a point: its blocks
and its seconds as run (build and solve, first computation). The exponent
``k`` of ``seconds ~ c blocks**k`` is the least-squares slope in log-log over
the records that reached an answer (``optimal``, ``converged``); the others
are drawn, marked by status, and left out of the fit. Times depend on the
machine and its load (the report's other numbers do not); the table names no
cell that the golden test pins (its timing columns name seconds).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from comparison.report.computed import Results
from comparison.report.figures import MARKERS, Figure, pyplot, save_figure
from comparison.report.tables import Table
from comparison.utilities.numbers import power_law

#: Statuses whose records enter the fit.
ANSWERED = ("optimal", "converged")
#: The fitted time is quoted at these block counts.
QUOTED_BLOCKS = (1_000, 7_575)


@dataclass(frozen=True)
class ScalingPoint:
    """One micro record: its method, wall, blocks, seconds and status."""

    method: str
    wall: str
    blocks: int
    seconds: float
    status: str


@dataclass(frozen=True)
class Fit:
    """``seconds ~ prefactor * blocks**exponent`` over ``points`` answered records."""

    exponent: float
    prefactor: float
    points: int

    def seconds(self, blocks: Any) -> Any:
        """The fitted time at ``blocks`` (a number or an array)."""
        return self.prefactor * np.asarray(blocks, dtype=float) ** self.exponent


def scaling_points(res: Results) -> list[ScalingPoint]:
    """Every record of the report's micro methods (the associative LP and the iterated LP, as in the
    paper's tables) with its blocks and seconds (cache reads keep their first time)."""
    out = []
    for (spec, method), rec in res.records.items():
        if (method not in res.plan.methods or rec.micro is None or not math.isfinite(rec.seconds)
                or rec.seconds <= 0):
            continue
        out.append(ScalingPoint(method.label, spec.name or "wall", int(rec.micro.blocks), float(rec.seconds),
                                rec.status))
    return sorted(out, key=lambda p: (p.method, p.blocks))


def fit(points: Sequence[ScalingPoint]) -> Fit | None:
    """The log-log least-squares fit over the answered points with at least two block counts (else ``None``)."""
    good = [p for p in points if p.status in ANSWERED]
    law = power_law([p.blocks for p in good], [p.seconds for p in good])
    return None if law is None else Fit(law[0], law[1], len(good))


def by_method(points: Sequence[ScalingPoint]) -> dict[str, list[ScalingPoint]]:
    """The points grouped by method label, in order of appearance."""
    groups: dict[str, list[ScalingPoint]] = {}
    for p in points:
        groups.setdefault(p.method, []).append(p)
    return groups


def scaling_table(res: Results) -> Table:
    """One row per micro method: walls, block range, the fitted exponent and times."""
    t = Table(
        "scaling",
        "Run time against blocks (both micro methods; timings of this run, not pinned)",
        ["method", "records (answered)", "blocks min", "blocks max", "exponent k of seconds ~ blocks^k",
         *(f"fitted seconds at {b:,} blocks" for b in QUOTED_BLOCKS), "largest answered wall seconds"],
    )
    for method, pts in by_method(scaling_points(res)).items():
        f = fit(pts)
        good = [p for p in pts if p.status in ANSWERED]
        largest = max(good, key=lambda p: (p.blocks, p.seconds), default=None)
        t.add(method, f"{len(pts)} ({len(good)})", min(p.blocks for p in pts), max(p.blocks for p in pts),
              math.nan if f is None else f.exponent,
              *(math.nan if f is None else float(f.seconds(b)) for b in QUOTED_BLOCKS),
              math.nan if largest is None else largest.seconds)
    t.note = ("Least squares in log-log over the records with an answer (`optimal`, `converged`); seconds: build "
              "and solve as first run on the machine above; figure: `scaling.png`.")
    return t


def scaling_figure(res: Results, path: Path) -> Figure | None:
    """Seconds against blocks, log-log, one marker per method, the fit as a line (``None``: no points)."""
    groups = by_method(scaling_points(res))
    if not groups:
        return None
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5), dpi=110)
    for i, ((method, pts), mk) in enumerate(zip(groups.items(), MARKERS, strict=False)):
        good = [p for p in pts if p.status in ANSWERED]
        other = [p for p in pts if p.status not in ANSWERED]
        ax.scatter([p.blocks for p in good], [p.seconds for p in good], marker=mk, s=22, color=f"C{i}",
                   label=method, alpha=0.8)
        if other:
            ax.scatter([p.blocks for p in other], [p.seconds for p in other], marker=mk, s=30, facecolors="none",
                       edgecolors=f"C{i}", label=f"{method}: no answer (cycling, cap)")
        f = fit(pts)
        if f is not None:
            xs = np.geomspace(min(p.blocks for p in pts), max(p.blocks for p in pts), 50)
            ax.plot(xs, f.seconds(xs), color=f"C{i}", lw=1, ls="--", label=f"fit: k = {f.exponent:.2f}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("blocks")
    ax.set_ylabel("time [s] (build and solve)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    save_figure(fig, path)
    return Figure(
        path.name,
        "Run time against blocks of every micro record of this report (the paper's walls, the bond variants, "
        "the sweeps, the speed-accuracy walls), log-log; filled markers reached an answer and enter the fit "
        "(dashed, exponent k), open ones did not. Times as run on the machine named in `timings.md`; "
        "data: `scaling.csv`.",
    )
