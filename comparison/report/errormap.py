"""The error map: where the macro model is unsafe, from the committed sweep table.

Reads the committed sweep table ``sweeps/errormap.csv`` of the report's tables
directory (:mod:`comparison.report.committed`; written by ``xcheck sweep
examples/sweeps/errormap.toml --out reports/sweeps``; the report does not
recompute it) and pairs, wall by wall, the macro load factor with the micro
reference: the iterated non-associative LP where it converged, else the
associative LP (an upper bound of the non-associative load factor, so that a
macro value above it is unsafe for certain). The relative error
``(lambda_macro - lambda_micro) / lambda_micro`` is drawn as heat maps over
``(t, m)``, one per number of rows and storeys, with the contour where it
exceeds :data:`AGREEMENT` (where the macro model turns unsafe), and the worst
cells are tabulated.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

from comparison.sweep.table import number, read_table
from micro.plot import save_figure

#: Relative difference within which the two models agree (the LPs are solved to about 1e-6 relative):
#: a wall is unsafe when the macro load factor exceeds the micro reference by more. Walls where both
#: slide at lambda = f differ by 1e-9 and count as agreeing.
AGREEMENT = 1e-4
#: Worst cells listed in the report.
WORST = 12
#: Micro statuses whose load factor counts as a reference.
REFERENCE_STATUS = {"micro-nonassoc": "converged", "micro-assoc": "optimal"}


@dataclass(frozen=True)
class MapCell:
    """One wall of the error map.

    Attributes:
        t, m, rows, storeys, f, p: the wall.
        blocks: blocks of its micro wall (0 when none was built).
        macro: the macro load factor.
        assoc: the associative micro load factor (NaN when not run or failed).
        nonassoc: the converged non-associative load factor (NaN otherwise).
    """

    t: float
    m: float
    rows: int
    storeys: int
    f: float
    p: float
    blocks: int
    macro: float
    assoc: float
    nonassoc: float

    @property
    def reference(self) -> float:
        """The micro reference: the non-associative load factor if converged, else the associative one."""
        return self.nonassoc if math.isfinite(self.nonassoc) else self.assoc

    @property
    def reference_kind(self) -> str:
        """``"non-assoc"``, ``"assoc"`` or ``""`` (no micro result)."""
        if math.isfinite(self.nonassoc):
            return "non-assoc"
        return "assoc" if math.isfinite(self.assoc) else ""

    @property
    def error(self) -> float:
        """``(macro - reference) / reference`` (NaN without a reference)."""
        ref = self.reference
        return (self.macro - ref) / ref if math.isfinite(ref) else math.nan


def wall_values(path: Path) -> dict[tuple[str, ...], dict[str, Any]]:
    """Per wall of a sweep table, keyed ``(t, m, rows, storeys, f, p)`` as the table writes them: the
    macro load factor (``"macro"``), the micro ones that count as references (``"micro-assoc"``,
    ``"micro-nonassoc"``; NaN otherwise), the blocks of those (``"blocks"``), and how the iterated LP
    ended (``"nonassoc_status"``, ``"nonassoc_lps"``; ``""`` and 0 without it). Micro rows: the bond
    with a full first course."""
    walls: dict[tuple[str, ...], dict[str, Any]] = {}
    for row in read_table(path):
        key = (row["t"], row["m"], row["rows"], row["storeys"], row["f"], row["p"])
        w = walls.setdefault(key, {"macro": math.nan, "micro-assoc": math.nan, "micro-nonassoc": math.nan,
                                   "blocks": 0, "nonassoc_status": "", "nonassoc_lps": 0})
        kind = row["kind"]
        if kind == "macro" and row["status"] == "optimal":
            w["macro"] = number(row["load_factor"])
        elif REFERENCE_STATUS.get(kind) == row["status"] and row["first_course"] == "full":
            w[kind] = number(row["load_factor"])
            w["blocks"] = max(w["blocks"], int(row["blocks"] or 0))
        if kind == "micro-nonassoc" and row["first_course"] == "full":
            w["nonassoc_status"], w["nonassoc_lps"] = str(row["status"]), int(row["iterations"] or 0)
    return walls


def load(path: Path) -> list[MapCell]:
    """The walls of a sweep table with their macro and micro load factors."""
    cells = []
    for (t, m, rows, storeys, f, p), w in wall_values(path).items():
        wall = (float(t), float(m), int(rows), int(storeys), float(f), float(p))
        cells.append(MapCell(*wall, w["blocks"], w["macro"], w["micro-assoc"], w["micro-nonassoc"]))
    return cells


def fraction(x: float) -> str:
    """``x`` as a short fraction (``2/3``) or number."""
    f = Fraction(x).limit_denominator(12)
    return str(f) if abs(float(f) - x) < 1e-9 else f"{x:g}"


def summary(cells: Sequence[MapCell]) -> dict[str, Any]:
    """The headline numbers: share of unsafe walls, by reference, rows and storeys."""
    ref = [c for c in cells if math.isfinite(c.error)]

    def part(cs: Sequence[MapCell]) -> dict[str, Any]:
        errs = [c.error for c in cs]
        return {
            "walls": len(cs),
            "unsafe": sum(e > AGREEMENT for e in errs),
            "agree": sum(abs(e) <= AGREEMENT for e in errs),
            "above_10pct": sum(e > 0.10 for e in errs),
            # None (JSON null) for an empty part: NaN is not JSON (report.json)
            "median": statistics.median(errs) if errs else None,
            "max": max(errs) if errs else None,
        }

    groups = sorted({(c.storeys, c.rows) for c in ref})
    return {
        "all": part(ref),
        "nonassoc": part([c for c in ref if c.reference_kind == "non-assoc"]),
        "assoc": part([c for c in ref if c.reference_kind == "assoc"]),
        "by_group": {f"N={n}, o={o}": part([c for c in ref if (c.storeys, c.rows) == (n, o)]) for n, o in groups},
        "no_reference": len(cells) - len(ref),
    }


def worst(cells: Sequence[MapCell], n: int = WORST) -> list[MapCell]:
    """The ``n`` walls where the macro model lies furthest above the micro reference."""
    return sorted((c for c in cells if math.isfinite(c.error)), key=lambda c: c.error, reverse=True)[:n]


def figure(cells: Sequence[MapCell], path: Path) -> Path:
    """Heat maps of the relative error over ``(t, m)``, one panel per (storeys, rows), with the zero contour."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.colors import TwoSlopeNorm

    ts, ms = sorted({c.t for c in cells}), sorted({c.m for c in cells})
    storeys, rows = sorted({c.storeys for c in cells}), sorted({c.rows for c in cells})
    errs = [c.error for c in cells if math.isfinite(c.error)]
    span = max(0.05, max((abs(e) for e in errs), default=0.05))
    norm = TwoSlopeNorm(0.0, -span, span)
    size = (2.6 * len(rows) + 1.2, 2.5 * len(storeys) + 0.9)
    fig, axes = plt.subplots(
        len(storeys), len(rows), figsize=size, squeeze=False, sharex=True, sharey=True, layout="constrained"
    )
    by = {(c.storeys, c.rows, c.t, c.m): c for c in cells}
    mesh = None
    for i, n in enumerate(storeys):
        for j, o in enumerate(rows):
            ax = axes[i][j]
            grid = np.full((len(ms), len(ts)), np.nan)
            for a, m in enumerate(ms):
                for b, t in enumerate(ts):
                    c = by.get((n, o, t, m))
                    if c is not None and math.isfinite(c.error):
                        grid[a, b] = c.error
                        star = "" if c.reference_kind == "non-assoc" else "*"
                        ax.text(b, a, f"{100 * c.error:+.0f}{star}", ha="center", va="center", fontsize=7)
            ax.set_facecolor("0.85")
            mesh = ax.pcolormesh(np.ma.masked_invalid(grid), cmap="RdBu_r", norm=norm, shading="nearest")
            if min(grid.shape) >= 2 and np.nanmin(grid, initial=np.inf) < AGREEMENT < np.nanmax(grid, initial=-np.inf):
                ax.contour(np.ma.masked_invalid(grid), levels=[AGREEMENT], colors="k", linewidths=1.5)
            ax.set_title(f"{n} storey{'s' if n > 1 else ''}, o = {o} rows", fontsize=9)
            ax.set_xticks(range(len(ts)), [fraction(t) for t in ts], fontsize=8)
            ax.set_yticks(range(len(ms)), [fraction(m) for m in ms], fontsize=8)
            if i == len(storeys) - 1:
                ax.set_xlabel("t = H/L")
            if j == 0:
                ax.set_ylabel("m = b/l")
    if mesh is not None:
        bar = fig.colorbar(mesh, ax=axes, shrink=0.8, format=lambda x, _: f"{100 * x:+.0f} %")
        bar.set_label("(λ_macro − λ_micro) / λ_micro")
    walls = ", ".join(f"{k} = {' / '.join(sorted({f'{getattr(c, k):g}' for c in cells}))}" for k in ("f", "p"))
    fig.suptitle(
        f"Macro vs micro load factor ({walls}). Red: macro above micro (unsafe); black line: where it turns unsafe;\n"
        "numbers in %; * the associative LP is the reference (elsewhere the non-associative); grey: no micro result",
        fontsize=9,
    )
    try:
        return save_figure(fig, path, dpi=130)  # whole or not at all
    finally:
        plt.close(fig)


def nonassoc_stops(path: Path) -> dict[str, int]:
    """How the iterated LP ended on the walls of the map (bond as in :func:`load`), by status."""
    stops: dict[str, int] = {}
    for row in read_table(path):
        if row["kind"] == "micro-nonassoc" and row["first_course"] == "full" and row["status"] != "not_run":
            stops[row["status"]] = stops.get(row["status"], 0) + 1
    return stops


def section(
    cells: Sequence[MapCell],
    figure_name: str,
    source: str,
    stops: dict[str, int] | None = None,
    number: int | None = None,
) -> str:
    """The report's error-map section: headline numbers, the figure with its caption, the worst cells.

    ``stops`` (see :func:`nonassoc_stops`) says why the iterated LP gave no reference where it did not;
    ``number`` is the figure's number in the report.
    """
    s = summary(cells)
    a, na, asc = s["all"], s["nonassoc"], s["assoc"]
    lines = [
        "## Error map: where the macro model is unsafe",
        "",
        f"From the committed sweep `{source}` (`xcheck sweep examples/sweeps/errormap.toml --out reports/sweeps`; "
        "the report reads it and does not recompute it). For every wall the macro load factor is compared with "
        "the micro reference: the iterated non-associative LP where it converged, else the associative LP (an "
        "upper bound of the non-associative load factor: a macro value above it is unsafe for certain).",
        "",
        f"* The macro model lies **above** the micro reference (unsafe) on **{a['unsafe']} of {a['walls']} walls** "
        f"({_share(a)}), by more than 10 % on {a['above_10pct']}; the two agree within {AGREEMENT:.0e} on "
        f"{a['agree']} (both slide at λ = f); median error {100 * a['median']:+.1f} %, worst {100 * a['max']:+.1f} %.",
        f"* Against the converged non-associative LP: {na['unsafe']} of {na['walls']} unsafe ({_share(na)}); "
        f"against the associative LP (where the iterated LP was not run or did not converge): {asc['unsafe']} of "
        f"{asc['walls']} ({_share(asc)}). {s['no_reference']} walls have no micro result (above the block limit).",
        *(
            [f"* How the iterated LP ended on the walls it ran on: {_stops(stops)}."]
            if stops
            else []
        ),
        "",
        f"![{_label(number)}]({figure_name})",
        "",
        f"**{_label(number)}.** {caption(cells)}",
        "",
        "| storeys, rows | walls | unsafe | > +10 % | agree | median | worst |",
        "|---|---|---|---|---|---|---|",
    ]
    for group, g in s["by_group"].items():
        lines.append(
            f"| {group} | {g['walls']} | {g['unsafe']} | {g['above_10pct']} | {g['agree']} "
            f"| {100 * g['median']:+.1f} % | {100 * g['max']:+.1f} % |"
        )
    header = "| N | o | t | m | blocks | λ macro | λ micro | reference | error |"
    lines += ["", "Worst cells:", "", header, "|---" * 9 + "|"]
    for c in worst(cells):
        lines.append(
            f"| {c.storeys} | {c.rows} | {fraction(c.t)} | {fraction(c.m)} | {c.blocks} | {c.macro:.4f} "
            f"| {c.reference:.4f} | {c.reference_kind} | {100 * c.error:+.1f} % |"
        )
    return "\n".join(lines) + "\n"


def _label(number: int | None) -> str:
    return "Error map" if number is None else f"Figure {number}"


def caption(cells: Sequence[MapCell]) -> str:
    """What the error map draws."""
    storeys = " and ".join(str(n) for n in sorted({c.storeys for c in cells}))
    rows = ", ".join(str(o) for o in sorted({c.rows for c in cells}))
    walls = ", ".join(f"{k} = {' / '.join(sorted({f'{getattr(c, k):g}' for c in cells}))}" for k in ("f", "p"))
    return (
        f"(λ_macro − λ_micro)/λ_micro in per cent over t = H/L (columns) and m = b/l (rows of each panel), one panel "
        f"per number of storeys ({storeys}) and rows o ({rows}); {walls}. Red: the macro model above the micro "
        "reference (unsafe), blue: below; the black line: where it turns unsafe. The reference is the converged "
        "iterated LP, or (marked *) the associative LP; grey cells: no micro result (above the block limit). "
        "Data: `reports/sweeps/errormap.csv`."
    )


def _stops(stops: dict[str, int]) -> str:
    why = {"max_iterations": "its cap of LPs reached"}
    return "; ".join(f"{n} `{status}`" + (f" ({why[status]})" if status in why else "") for status, n in stops.items())


def _share(part: dict[str, Any]) -> str:
    return f"{100 * part['unsafe'] / part['walls']:.0f} %" if part["walls"] else "no wall"


def write(out: Path, table: Path | None, number: int | None = None) -> tuple[str, dict[str, Any]]:
    """Draw ``errormap.png`` into ``out``; the section's markdown and its numbers (for ``report.json``).

    Without the committed table (``None``: :func:`~comparison.report.committed.committed_table` warned)
    the section says so and nothing is drawn. ``number``: the figure's number in the report.
    """
    if table is None or not table.exists():
        return "## Error map\n\nThe sweep table `reports/sweeps/errormap.csv` is missing.\n", {}
    cells = load(table)
    name = figure(cells, out / "errormap.png").name
    numbers = {"summary": summary(cells), "worst": [c.__dict__ | {"error": c.error} for c in worst(cells)]}
    stops = nonassoc_stops(table)
    text = section(cells, name, "reports/sweeps/errormap.csv", stops, number)
    return text, {**numbers, "nonassoc_stops": stops}
