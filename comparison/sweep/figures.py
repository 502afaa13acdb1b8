"""The figures of a sweep's validation page, drawn from its walls (:mod:`~comparison.sweep.wall_comparisons`) and rows.

* :func:`error_map`: a macro column's difference from the micro reference as heat maps over the grid's
  axes: the first two axes the grid varies (in :data:`~comparison.sweep.wall_comparisons.AXES`' order: t, m, f, p,
  rows, storeys, the bond) across and up each panel, one column of panels per value of the third, one row
  per combination of the others, with the line where the macro value turns unsafe;
* :func:`scatter`: every macro column against the micro reference, with the 1:1 line;
* :func:`histogram`: the distribution of the differences, per macro column;
* :func:`time_against_blocks`: each micro computation's seconds against its blocks (log-log).

One outlier (a local mechanism, a wall whose micro value is far off) must not flatten the others: the
error map's colour scale and the histogram's range end at the outlier fences (:func:`scale`), and a wall
beyond them is drawn at the end of the scale (its cell outlined, its number the true one) or in the
histogram's end bin (counted in the legend). Tukey's fences on the quartiles rather than a percentile: on
a grid of a dozen walls any high percentile still lies among the outliers.

Every function writes a PNG whole or not at all (:func:`micro.plot.save_figure`) and returns its path, or
``None`` when there is nothing to draw.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from comparison.sweep.table import number
from comparison.sweep.wall_comparisons import (
    AGREEMENT,
    MACRO_KINDS,
    SYMBOLS,
    Wall,
    axis_values,
    shown,
    success,
    varying,
)
from comparison.utilities.numbers import power_law
from micro.plot import save_figure

#: Resolution of the page's figures.
DPI = 130
#: The heat map writes each cell's difference on it up to this many cells a side.
ANNOTATE = 12
#: A cell whose colour lies this far from the map's middle (0 to 0.5) gets its number in white.
DARK = 0.3
#: The error map's least width, inches (its title's two lines).
MIN_WIDTH = 7.5
#: The histogram's bins: 'auto' (numpy's) unless it gives fewer than the first or more than the second.
MIN_BINS, MAX_BINS = 10, 40
#: The outlier fences: quartiles ± this many interquartile ranges (Tukey's "far out")...
FENCE_IQR = 3.0
#: ... and at least this far beyond the quartiles (a grid whose walls mostly agree has an interquartile
#: range near 0, and a difference of a few per cent is no outlier).
FENCE_FLOOR = 0.05
#: Outliers are left out of a scale only where they would stretch it more than this many times (two walls
#: at +26 % and +27 % are not told apart as in- and outlier).
STRETCH = 1.5
#: Statuses of a micro row that has no record (and so no time of a computation to draw).
NO_RECORD = frozenset({"not_applicable", "not_run", "refused_memory", "error", "worker_died"})


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: Path) -> Path:
    try:
        return save_figure(fig, path, dpi=DPI)
    finally:
        _pyplot().close(fig)


def layout(ws: Sequence[Wall]) -> tuple[str | None, str | None, str | None, list[str]]:
    """The error map's axes: ``(across, up, panel columns, panel rows)`` (module docstring); ``None`` where
    the grid varies fewer axes."""
    axes = varying(ws)
    pick = [*axes[:3], None, None, None]
    return pick[0], pick[1], pick[2], axes[3:]


def fixed(ws: Sequence[Wall]) -> str:
    """The axes the walls do not vary, with their value (``f = 0.6, p = 0``)."""
    moving = set(varying(ws))
    return ", ".join(f"{SYMBOLS[a]} = {shown(a, ws[0].value(a))}" for a in ("t", "m", "rows", "f", "p", "storeys")
                     if a not in moving)


def fences(values: Sequence[float]) -> tuple[float, float]:
    """The outlier fences of ``values``: ``(Q1 − r, Q3 + r)`` with ``r = max(FENCE_IQR · IQR, FENCE_FLOOR)``
    (:data:`FENCE_IQR`, :data:`FENCE_FLOOR`); a value outside them is an outlier."""
    import numpy as np

    q1, q3 = (float(q) for q in np.percentile(values, [25, 75]))
    reach = max(FENCE_IQR * (q3 - q1), FENCE_FLOOR)
    return q1 - reach, q3 + reach


def scale(values: Sequence[float]) -> tuple[float, float]:
    """The range a figure's scale spans: the inliers' (within :func:`fences`) where the outliers would stretch
    it more than :data:`STRETCH` times, else every value's."""
    lo, hi = fences(values)
    inliers = [v for v in values if lo <= v <= hi] or list(values)
    a, b = min(inliers), max(inliers)
    if max(values) - min(values) <= STRETCH * max(b - a, FENCE_FLOOR):
        return min(values), max(values)
    return a, b


def error_map(ws: Sequence[Wall], column: str, path: Path) -> Path | None:
    """Heat maps of ``column``'s difference from the micro reference (module docstring)."""
    if not any(math.isfinite(w.error(column)) for w in ws):
        return None
    from matplotlib.colors import TwoSlopeNorm

    plt = _pyplot()
    across, up, panel_col, panel_rows = layout(ws)
    xs = axis_values(ws, across) if across else [None]
    ys = axis_values(ws, up) if up else [None]
    cols = axis_values(ws, panel_col) if panel_col else [None]
    rows = list(itertools.product(*(axis_values(ws, a) for a in panel_rows)))
    errs = [e for w in ws if math.isfinite(e := w.error(column))]
    span = max(0.05, *(abs(e) for e in scale(errs)))
    clipped = any(abs(e) > span for e in errs)
    norm = TwoSlopeNorm(0.0, -span, span)
    width, height = (max(2.2, min(6.0, 0.6 + 0.4 * len(xs))), max(1.8, min(5.0, 0.5 + 0.4 * len(ys))))
    size = (max(width * len(cols) + 1.4, MIN_WIDTH), height * len(rows) + 1.1)
    fig, axes = plt.subplots(len(rows), len(cols), figsize=size, squeeze=False, sharex=True, sharey=True,
                             layout="constrained")
    by = {tuple(w.value(a) for a in (across, up, panel_col, *panel_rows) if a): w for w in ws}
    mesh = None
    for i, rkey in enumerate(rows):
        for j, ckey in enumerate(cols):
            ax = axes[i][j]
            panel = [[by.get(tuple(v for v in (x, y, ckey, *rkey) if v is not None)) for x in xs] for y in ys]
            mesh = _panel(ax, panel, column, norm)
            title = [_title(a, v) for a, v in zip(panel_rows, rkey, strict=True)]
            if panel_col:
                title.append(_title(panel_col, ckey))  # type: ignore[arg-type]
            if title:
                ax.set_title(", ".join(title), fontsize=9)
            _ticks(ax.set_xticks, xs, across)
            _ticks(ax.set_yticks, ys, up)
            if i == len(rows) - 1 and across:
                ax.set_xlabel(_axis_label(across))
            if j == 0 and up:
                ax.set_ylabel(_axis_label(up))
    if mesh is not None:
        bar = fig.colorbar(mesh, ax=axes, shrink=0.8, format=lambda x, _: f"{100 * x:+.0f} %",
                           extend="both" if clipped else "neither")
        bar.set_label(f"(λ {column} − λ micro) / λ micro")
    where = fixed(ws)
    fig.suptitle(
        f"λ {column} against λ micro" + (f" ({where})" if where else "") + ". Red: above micro (unsafe); black "
        "line: where it turns unsafe;\nnumbers in %; * the associative LP is the reference (elsewhere the "
        "non-associative); hatched grey: no micro value"
        + (";\noutlined: an outlier beyond the colour scale (its own number written)" if clipped else ""),
        fontsize=9,
    )
    return _save(fig, path)


def _panel(ax: Any, panel: Sequence[Sequence[Wall | None]], column: str, norm: Any) -> Any:
    """One heat map: the walls of ``panel`` (rows up, columns across; ``None``: no wall), annotated when
    small, with the line where ``column`` turns unsafe; its mesh."""
    import numpy as np

    grid = np.full((len(panel), len(panel[0])), np.nan)
    annotate = max(grid.shape) <= ANNOTATE
    for a, line in enumerate(panel):
        for b, w in enumerate(line):
            if w is None or not math.isfinite(w.error(column)):
                continue
            grid[a, b] = w.error(column)
            if annotate:
                star = "" if w.reference_kind == "non-assoc" else "*"
                dark = abs(float(norm(grid[a, b])) - 0.5) > DARK  # white on the deep reds and blues
                ax.text(b, a, f"{100 * grid[a, b]:+.0f}{star}", ha="center", va="center", fontsize=7,
                        color="w" if dark else "k")
    mesh = ax.pcolormesh(np.ma.masked_invalid(grid), cmap="RdBu_r", norm=norm, shading="nearest")
    for a, b in zip(*np.nonzero(np.isnan(grid)), strict=True):  # no micro value: hatched, never a pale colour
        ax.add_patch(_no_value(int(a), int(b)))
    for a, b in zip(*np.nonzero(np.abs(np.nan_to_num(grid)) > norm.vmax), strict=True):  # beyond the scale
        ax.add_patch(_outline(int(a), int(b)))
    for (a0, b0), (a1, b1) in _unsafe_edges(grid):
        ax.plot([b0, b1], [a0, a1], color="k", lw=1.8, solid_capstyle="butt")
    return mesh


def _no_value(a: int, b: int) -> Any:
    """The heat map's cell ``(a, b)`` without a micro value: grey and hatched, so that it cannot be read as
    a difference near 0 (the colour scale's middle is near-white)."""
    from matplotlib.patches import Rectangle

    return Rectangle((b - 0.5, a - 0.5), 1.0, 1.0, facecolor="0.8", edgecolor="0.45", hatch="///", lw=0.0)


def _outline(a: int, b: int) -> Any:
    """The dashed outline of the heat map's cell ``(a, b)`` (an outlier beyond the colour scale)."""
    from matplotlib.patches import Rectangle

    return Rectangle((b - 0.45, a - 0.45), 0.9, 0.9, fill=False, edgecolor="k", lw=1.0, ls="--")


def _unsafe_edges(grid: Any) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """The cell sides between an unsafe cell (above :data:`AGREEMENT`) and a neighbour with a value that is
    not, as ``((row, column), (row, column))`` ends in the heat map's coordinates (cell centres on integers):
    the line where the macro value turns unsafe, drawn along the cells it separates."""
    rows, cols = grid.shape
    out = []
    for a in range(rows):
        for b in range(cols):
            if not grid[a, b] > AGREEMENT:
                continue
            for da, db in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                na, nb = a + da, b + db
                if 0 <= na < rows and 0 <= nb < cols and math.isfinite(grid[na, nb]) and not grid[na, nb] > AGREEMENT:
                    if da:  # a horizontal side between the rows
                        y = a + da / 2
                        out.append(((y, b - 0.5), (y, b + 0.5)))
                    else:
                        x = b + db / 2
                        out.append(((a - 0.5, x), (a + 0.5, x)))
    return out


def _title(axis: str, value: float | str) -> str:
    """A panel's value of ``axis``: ``3 storeys``, ``o = 12 rows``, ``f = 0.6``, ``first course = half``."""
    if axis == "storeys":
        return f"{value:g} storey" + ("s" if value != 1 else "")
    if axis == "rows":
        return f"o = {value:g} rows"
    return f"{SYMBOLS[axis]} = {shown(axis, value)}"


def _ticks(setter: Any, values: Sequence[Any], axis: str | None) -> None:
    if axis is None:
        setter([])
        return
    step = max(1, math.ceil(len(values) / 12))  # at most a dozen labels
    setter(range(0, len(values), step), [shown(axis, v) for v in values[::step]], fontsize=8)


def _axis_label(axis: str) -> str:
    return {"t": "t = H/L", "m": "m = b/l", "rows": "rows o", "storeys": "storeys N", "f": "friction f",
            "p": "overloading p"}.get(axis, SYMBOLS[axis])


def _markers(ws: Sequence[Wall], column: str) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    """``(micro, macro)`` points of ``column``: against the non-associative reference, and the associative."""
    na: list[tuple[float, float]] = []
    asc: list[tuple[float, float]] = []
    for w in ws:
        if math.isfinite(w.error(column)):
            (na if w.reference_kind == "non-assoc" else asc).append((w.reference, w.macro[column]))
    return na, asc


def scatter(ws: Sequence[Wall], macro_columns: Sequence[str], path: Path) -> Path | None:
    """Each macro column against the micro reference, with the 1:1 line and ±10 % dotted."""
    points = {c: _markers(ws, c) for c in macro_columns}
    if not any(na or asc for na, asc in points.values()):
        return None
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.2, 5.0), layout="constrained")
    top, low = 0.0, math.inf
    for k, (column, (na, asc)) in enumerate(points.items()):
        colour = f"C{k}"
        if na:
            ax.scatter(*zip(*na, strict=True), s=16, color=colour, label=f"{column} (non-assoc. reference)")
        if asc:
            ax.scatter(*zip(*asc, strict=True), s=16, facecolors="none", edgecolors=colour,
                       label=f"{column} (assoc. reference)")
        top = max([top, *(max(p) for p in na + asc)])
        low = min([low, *(min(p) for p in na + asc)])
    top *= 1.05
    low = 0.9 * low
    ax.plot([0, top], [0, top], "k-", lw=1, label="1:1 (macro = micro)")
    at = low + 0.2 * (top - low)
    for factor, where in ((1.1, "right"), (0.9, "left")):
        ax.plot([0, top], [0, factor * top], "k:", lw=0.8)
        ax.text(at, factor * at, f" {100 * (factor - 1):+.0f} % ", ha=where, va="center", fontsize=7)
    ax.set_xlim(low, top)
    ax.set_ylim(low, top)
    ax.set_aspect("equal")
    ax.set_xlabel("λ micro (reference)")
    ax.set_ylabel("λ " + ", λ ".join(points))  # each macro column by its name
    # below the axes, clear of the points (which fill the square along its diagonal)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncols=2, frameon=False)
    ax.set_title("Above the 1:1 line: the macro value is unsafe", fontsize=9)
    return _save(fig, path)


def histogram(ws: Sequence[Wall], macro_columns: Sequence[str], path: Path) -> Path | None:
    """The differences of each macro column from the micro reference, in per cent."""
    import numpy as np

    diffs = {c: [100 * e for w in ws if math.isfinite(e := w.error(c))] for c in macro_columns}
    every = [d for ds in diffs.values() for d in ds]
    if not every:
        return None
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.0, 3.6), layout="constrained")
    lo, hi = (100 * x for x in scale([d / 100 for d in every]))
    auto = np.histogram_bin_edges([d for d in every if lo <= d <= hi], bins="auto")
    bins = len(auto) - 1 if MIN_BINS <= len(auto) - 1 <= MAX_BINS else min(MAX_BINS, max(MIN_BINS, len(every)))
    width = (hi - lo) / bins if hi - lo > 1e-9 else 1.0
    # one bin centred on 0: the walls where the two agree (both sliding at f) sit on 0, not beside it
    first = math.floor(lo / width - 0.5)
    last = max(math.ceil(hi / width - 0.5), first + 1)
    edges = (np.arange(first, last + 1) + 0.5) * width
    if edges[-1] > 0:
        ax.axvspan(0, edges[-1], color="tab:red", alpha=0.08, lw=0)
    ends: dict[float, int] = {}  # the open-ended bars: their place and height
    for k, (column, ds) in enumerate(diffs.items()):
        kind = "stepfilled" if len(diffs) == 1 else "step"
        inside, below, beyond = binned(ds, float(edges[0]), float(edges[-1]))
        apart = len(below) + len(beyond)
        ax.hist(inside, bins=edges, histtype=kind, color=f"C{k}", alpha=0.8 if len(diffs) == 1 else 1.0, lw=1.5,
                label=f"{column} ({len(ds)} walls" + (f"; hatched: {apart} beyond the scale" if apart else "") + ")")
        # the walls beyond the scale: an open-ended bar of their own beside it, never in the end bin
        for side, count, at in ((-1, len(below), edges[0] - width), (1, len(beyond), edges[-1] + width)):
            if count:
                ax.bar(at, count, width=width, fill=False, hatch="//", edgecolor=f"C{k}", lw=1.0)
                ends[at] = max(ends.get(at, 0), count)
                ax.text(at, ends[at], f"{'<' if side < 0 else '>'} {edges[0 if side < 0 else -1]:+.0f} %",
                        ha="center", va="bottom", fontsize=7)
    if ends:
        ax.set_ylim(top=1.12 * max(ax.get_ylim()[1], *ends.values()))
    ax.axvline(0, color="k", lw=1)
    ax.set_xlabel("(λ macro − λ micro) / λ micro, %  (right of 0: unsafe)")
    ax.set_ylabel("walls")
    ax.yaxis.get_major_locator().set_params(integer=True)
    ax.legend(fontsize=7)
    return _save(fig, path)


def binned(ds: Sequence[float], lo: float, hi: float) -> tuple[list[float], list[float], list[float]]:
    """The differences ``ds`` within the histogram's scale ``[lo, hi]``, below it and beyond it (the outliers,
    drawn apart as open-ended bars, never in an end bin)."""
    return [d for d in ds if lo <= d <= hi], [d for d in ds if d < lo], [d for d in ds if d > hi]


def time_against_blocks(rows: Sequence[Mapping[str, str]], path: Path) -> Path | None:
    """Seconds of every micro computation with a record against its blocks, per method, log-log, with the
    least-squares power law of each method's answered computations (dashed, its exponent in the legend);
    crosses: computations that gave no value (a failed solve, an iterated LP that did not converge)."""
    groups: dict[str, tuple[list[tuple[float, float]], list[tuple[float, float]]]] = {}
    for r in rows:
        kind, status = r["kind"], r["status"]
        if kind in MACRO_KINDS or status in NO_RECORD:
            continue
        blocks, seconds = number(r.get("blocks", "")), number(r.get("seconds", ""))
        if not (math.isfinite(blocks) and blocks > 0 and math.isfinite(seconds) and seconds > 0):
            continue
        label = r["method"].replace(", half first", "").replace(", frictionless heads", "")  # every bond
        ok, bad = groups.setdefault(label, ([], []))
        (ok if success(kind, status) else bad).append((blocks, seconds))
    if not groups:
        return None
    import numpy as np

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.6, 3.8), layout="constrained")
    for k, (label, (ok, bad)) in enumerate(groups.items()):
        law = power_law(*zip(*ok, strict=True)) if ok else None
        if ok:
            fitted = "" if law is None else f" (fit: seconds ~ blocks^{law[0]:.2f})"
            ax.scatter(*zip(*ok, strict=True), s=14, color=f"C{k}", label=f"{label}{fitted}")
        if law is not None:
            xs = np.geomspace(min(b for b, _ in ok), max(b for b, _ in ok), 20)
            ax.plot(xs, law[1] * xs ** law[0], color=f"C{k}", linewidth=1.0, linestyle="--")
        if bad:
            ax.scatter(*zip(*bad, strict=True), s=22, marker="x", color=f"C{k}", label=f"{label}: no value")
    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis, limits in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        _plain_log_ticks(axis, limits)
    ax.set_xlabel("blocks")
    ax.set_ylabel("seconds (as computed)")
    ax.legend(fontsize=7)
    return _save(fig, path)


#: Decades a log axis may span and still be labelled at 1, 2 and 5 of each (beyond: at the decades alone).
FEW_DECADES = 2.0


def _plain_log_ticks(axis: Any, limits: tuple[float, float]) -> None:
    """Plain numbers (``20``, ``0.05``) at 1, 2 and 5 of each decade on a log axis of few decades, at the
    decades alone on a wider one; no labels between. Matplotlib labels the minor ticks of an axis of less than
    a decade or so as ``2×10^1, 3×10^1, 4×10^1``, which ran into one another on a small sweep's wall sizes."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    lo, hi = (max(x, 1e-300) for x in limits)
    subs = (1.0, 2.0, 5.0) if math.log10(hi / lo) <= FEW_DECADES else (1.0,)
    axis.set_major_locator(LogLocator(base=10.0, subs=subs))
    axis.set_major_formatter(FuncFormatter(lambda value, _pos: f"{value:g}"))
    axis.set_minor_formatter(NullFormatter())
