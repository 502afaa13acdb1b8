"""Figures of the report (matplotlib, Agg, PNG), drawn from its results, each with its caption.

The generic charts (:func:`speed_accuracy`, :func:`sensitivity`,
:func:`histories`) take plain series; the report's figures read the
:class:`~comparison.report.computed.Results` and return a :class:`Figure`: the
file and a caption that says what is drawn, on which wall, by which method and
in which load direction (``REPORT.md`` numbers them). The mechanism figures are
in :mod:`comparison.report.mechanisms`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.ticker import MaxNLocator

from comparison.domain.cases import cases_in_table
from comparison.report.computed import Results
from comparison.report.speed_accuracy import speed_reference, speed_rows
from comparison.report.tables import published

#: How each swept parameter is named on its axis.
PARAMETERS = {
    "f": "f (friction coefficient)",
    "t": "t = H/L (wall shape)",
    "m": "m = b/l (block shape)",
    "rows": "o (rows)",
    "p": "p (floor load ratio)",
}

#: Errors below this are drawn at it, hollow (the speed-accuracy chart's reference itself: error 0).
SPEED_FLOOR = 1e-7

#: Marker per series, so that overlapping series stay apart without colour.
MARKERS = "osD^v<>phX*"


@dataclass(frozen=True)
class Figure:
    """A figure of the report.

    Attributes:
        name: its file name (next to ``REPORT.md``).
        caption: what is drawn, the wall, the method and the load direction.
    """

    name: str
    caption: str


@dataclass(frozen=True)
class SpeedPoint:
    """One point of the speed-accuracy chart."""

    label: str
    family: str
    seconds: float
    error: float  # |lambda - reference| / reference
    rows: int = 0


@dataclass(frozen=True)
class History:
    """The iterated LP on one wall, for :func:`histories`.

    Attributes:
        label: the wall.
        status: how the sequence ended.
        load_factors: λ of every LP, the associative one first.
        band: the mechanism band (converged) or the cycling band, if any.
        band_kind: what ``band`` is (``"mechanism band"`` or ``"cycling band"``).
    """

    label: str
    status: str
    load_factors: Sequence[float]
    band: tuple[float, float] | None = None
    band_kind: str = "mechanism band"


def pyplot() -> Any:
    """``matplotlib.pyplot`` on the Agg back end."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig: Any, path: Path) -> Path:
    """Write ``fig`` to ``path`` (tight bounding box; whole or not at all, :func:`micro.plot.save_figure`)
    and close it."""
    from micro.plot import save_figure as save_whole

    try:
        return save_whole(fig, path, bbox_inches="tight")
    finally:
        pyplot().close(fig)


def _legend_entries(axes: Any) -> dict[str, Any]:
    """Every labelled artist of ``axes``, once per label, for one legend of the figure."""
    handles: dict[str, Any] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(label, handle)
    return handles


def speed_accuracy(points: Sequence[SpeedPoint], reference: str, path: Path) -> Path:
    """Time (log) against relative error in λ, one marker per family joined by rows; each wall resolution
    labelled once. A point of error below :data:`SPEED_FLOOR` (the reference itself, error 0) is drawn
    hollow at the axis floor, off its family's line, and named; the macro point is named too."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 5.2), dpi=110)
    floor = SPEED_FLOOR
    shown = [p for p in points if math.isfinite(p.error) and math.isfinite(p.seconds)]
    exact = [p for p in shown if p.error < floor]
    for i, (fam, mk) in enumerate(zip(sorted({p.family for p in shown}), MARKERS, strict=False)):
        pts = sorted((p for p in shown if p.family == fam and p.error >= floor), key=lambda p: p.rows)
        xy = [p.error for p in pts], [max(p.seconds, 1e-5) for p in pts]
        ax.plot(*xy, marker=mk, ms=7, lw=0.7, color=f"C{i}", label=fam, alpha=0.85)
        for p in (q for q in exact if q.family == fam):
            ax.plot([floor], [max(p.seconds, 1e-5)], marker=mk, ms=9, mfc="none", mew=1.5, color=f"C{i}", ls="")
            what = "the reference (error 0)" if p.error == 0 else f"error {p.error:.0e}"
            ax.annotate(f"{fam}, {p.label}: {what}, drawn at {floor:g}", (floor, max(p.seconds, 1e-5)),
                        fontsize=7, xytext=(8, -3), textcoords="offset points", ha="left", va="top")
        for p in (q for q in pts if fam == "macro"):
            ax.annotate(f"macro model, {p.label}", (p.error, max(p.seconds, 1e-5)), fontsize=7, xytext=(-8, 0),
                        textcoords="offset points", ha="right", va="center")
    ax.set_xscale("log")
    ax.set_yscale("log")
    texts = [
        ax.annotate(label.rstrip("\u200b"), (x, y), fontsize=7, xytext=(0, 7), textcoords="offset points",
                    ha="center", bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8})
        for label, (x, y) in _cluster_labels([p for p in shown if p.family != "macro" and p.error >= floor],
                                             floor).items()
    ]  # fmt: skip
    _dodge(fig, texts)
    ax.set_xlim(left=floor / 2)
    ax.set_xlabel(f"|Δλ| / λ against {reference} (hollow: the reference itself, error 0, drawn at {floor:g})")
    ax.set_ylabel("time [s]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), title="method", title_fontsize=8)
    return save_figure(fig, path)


def _dodge(fig: Any, texts: list[Any]) -> None:
    """Move labels up, lowest first, until none overlaps one placed before it."""
    renderer = fig.canvas.get_renderer()
    placed: list[Any] = []
    for t in sorted(texts, key=lambda t: t.get_window_extent(renderer).y0):
        for _ in range(20):
            box = t.get_window_extent(renderer)
            if not any(box.overlaps(b) for b in placed):
                break
            dx, dy = t.get_position() if t.get_anncoords() == "offset points" else (0, 0)
            t.set_position((dx, dy + 9))
        placed.append(t.get_window_extent(renderer))


def _cluster_labels(points: Sequence[SpeedPoint], floor: float) -> dict[str, tuple[float, float]]:
    """One label per group of points of a resolution that share (nearly) one error, above the group's top."""
    out: dict[str, tuple[float, float]] = {}
    groups: list[list[SpeedPoint]] = []
    for p in sorted(points, key=lambda q: (q.label, max(q.error, floor))):
        g = groups[-1] if groups else None
        near = g is not None and g[0].label == p.label
        if g is not None and near and abs(math.log10(max(p.error, floor) / max(g[-1].error, floor))) < 0.15:
            g.append(p)
        else:
            groups.append([p])
    for i, g in enumerate(groups):
        key = g[0].label + "\u200b" * i  # the same label may stand over several groups
        out[key] = (max(g[0].error, floor), max(max(q.seconds for q in g), 1e-5))
    return out


def sensitivity(
    panels: Mapping[str, Mapping[str, tuple[Sequence[float], Sequence[float]]]],
    path: Path,
    title: str,
    published: Mapping[str, tuple[Sequence[float], Sequence[float]]] | None = None,
) -> Path:
    """λ against each parameter; one panel per parameter, one line (and marker) per series; the legend in a
    panel of its own."""
    plt = pyplot()
    cols = 3
    rows = math.ceil((len(panels) + 1) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.3 * cols, 3.4 * rows), dpi=110, squeeze=False, layout="constrained")
    flat = axes.ravel()
    labels = list(dict.fromkeys(label for series in panels.values() for label in series))
    markers = dict(zip(labels, MARKERS, strict=False))
    for ax, (param, series) in zip(flat, panels.items(), strict=False):
        for label, (x, y) in series.items():
            mk = markers[label]
            dotted = label.startswith("macro λ_r")
            ax.plot(x, np.asarray(y, dtype=float), marker=mk, ms=4, label=label,
                    ls=":" if dotted else "-", color="C0" if dotted else None)  # fmt: skip
        if published and param in published:
            px, py = published[param]
            ax.scatter(px, py, marker="x", color="k", s=40, zorder=5, label="paper λ_r (Table 5)")
        ax.set_xlabel(PARAMETERS.get(param, param))
        ax.set_ylabel("λ")
        ax.grid(True, alpha=0.3)
    handles = _legend_entries(flat[: len(panels)])
    for ax in flat[len(panels) :]:
        ax.axis("off")
    flat[len(panels)].legend(handles.values(), handles.keys(), loc="center", fontsize=8, frameon=False)
    fig.suptitle(title, fontsize=10)
    return save_figure(fig, path)


def histories(series: Sequence[History], path: Path, title: str) -> Path:
    """λ against LP of the iterated LP: one small panel per wall, with its band shaded."""
    plt = pyplot()
    cols = min(4, len(series))
    rows = math.ceil(len(series) / cols)
    fig, axes = plt.subplots(
        rows, cols, figsize=(3.3 * cols, 2.4 * rows + 0.5), dpi=110, squeeze=False, layout="constrained"
    )
    for ax, h in zip(axes.ravel(), series, strict=False):
        lam = np.asarray(h.load_factors, dtype=float)
        ax.plot(np.arange(len(lam)), lam, marker=".", ms=3, lw=1, color="C0", label="λ of each LP")
        ax.plot([0], [lam[0]], "s", color="C1", ms=4, label="associative start")
        if h.band is not None:
            ax.axhspan(*h.band, color="C2" if h.band_kind == "mechanism band" else "C3", alpha=0.2, label=h.band_kind)
        ax.set_title(f"{h.label}: {h.status}, {len(lam) - 1} LPs", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.grid(True, alpha=0.3)
    for ax in axes.ravel()[len(series) :]:
        ax.axis("off")
    for ax in axes[-1]:
        ax.set_xlabel("LP", fontsize=8)
    for ax in axes[:, 0]:
        ax.set_ylabel("λ", fontsize=8)
    handles = _legend_entries(axes.ravel())
    fig.legend(handles.values(), handles.keys(), loc="outside lower center", ncol=4, fontsize=8)
    fig.suptitle(title, fontsize=10)
    return save_figure(fig, path)


# ---------------------------------------------------------------- the report's figures


def base_wall(base: Mapping[str, float]) -> str:
    """The base wall of the sweeps in words: ``"t = 1, m = 1/3, o = 60, p = 0, f = 0.6, 3 storeys"``."""
    m = base["m"]
    m_text = f"1/{round(1 / m)}" if abs(1 / m - round(1 / m)) < 1e-9 and m < 1 else f"{m:g}"
    return (
        f"t = {base['t']:g}, m = {m_text}, o = {base['rows']:g}, p = {base['p']:g}, f = {base['f']:g}, "
        f"{base['storeys']:g} storey{'s' if base['storeys'] != 1 else ''}"
    )


def _micro_names(res: Results) -> str:
    return " and ".join(m.label for m in res.plan.methods)


def sensitivity_figure(res: Results, path: Path) -> Figure:
    """λ against each parameter of the base wall, macro and micro; in the full report with Table 5's values."""
    plan = res.plan
    panels: dict[str, dict[str, tuple[list[float], list[float]]]] = {}
    for param, values in plan.sweeps.items():
        specs = [plan.sweep_spec(param, v) for v in values]
        macro = [res.macro[s] for s in specs]
        series = {"macro λ = min(λ_r, f)": (list(values), [r.load_factor for r in macro])}
        if any(r.rocking_load_factor > r.load_factor for r in macro):
            series["macro λ_r (Eq. 10), above f"] = (list(values), [r.rocking_load_factor for r in macro])
        for m in plan.methods:
            series[m.column] = (list(values), [res.record(s, m).load_factor for s in specs])
        panels[param] = series
    base = base_wall(plan.base)
    sensitivity(panels, path, f"λ against each parameter of the base wall ({base})",
                None if plan.quick else _table5_points(plan.base))  # fmt: skip
    caption = (
        f"λ against each of t, m, o, p and f, the others held at the base wall ({base}): the macro model's "
        f"λ = min(λ_r, f) and, where λ_r exceeds f, Eq. (10)'s λ_r dotted; the {_micro_names(res)}; "
        "λ is the smaller of the two load directions (±x). "
    )
    if not plan.quick:
        caption += (
            "Crosses: the paper's Table 5, which tabulates λ_r: at f = 0.4 (Set 1) it prints λ_r = 0.519, "
            "where our λ is capped at f = 0.400 (the wall slides on a bed joint first); the dotted line "
            "shows our λ_r there. "
        )
    return Figure(path.name, caption + "Data: `sensitivity.csv`.")


def _table5_points(base: Mapping[str, float]) -> dict[str, tuple[list[float], list[float]]]:
    """Table 5's published λ against each parameter: the cases that differ from ``base`` in that parameter only."""
    out: dict[str, tuple[list[float], list[float]]] = {}
    for param in ("f", "p", "rows", "t", "m"):
        same = [c for c in cases_in_table("5") if all(getattr(c, k) == v for k, v in base.items() if k != param)]
        same.sort(key=lambda c: getattr(c, param))
        out[param] = ([getattr(c, param) for c in same], [published(c, "proposed") for c in same])
    return out


def speed_figure(res: Results, path: Path) -> Figure:
    """The speed-accuracy chart of :func:`comparison.report.speed_accuracy.speed_rows`."""
    rows = speed_rows(res)
    points = [SpeedPoint(f"{r.rows} rows", r.family, r.seconds, r.error, r.rows) for r in rows]
    ref = speed_reference(res)
    finest = res.plan.reference_rows
    speed_accuracy(points, f"{ref.method.column}, {finest} rows", path)
    base = base_wall({**res.plan.base, "rows": finest})
    blocks = {r.rows: r.blocks for r in rows if r.blocks is not None}
    built = ", ".join(f"{r} ({blocks[r]:,} blocks)" if r in blocks else str(r) for r in res.plan.resolutions)
    assoc_only = [r for r in res.plan.resolutions if r > finest]
    return Figure(
        path.name,
        f"Time against accuracy: every associative back end and the iterated LP on the base wall built with "
        f"{built} rows, and the macro model; the error is |Δλ|/λ against the {ref.method.column} "
        f"λ = {ref.load_factor:.4f} of the {finest}-row wall ({base})"
        + (f", the finest the report runs the iterated LP on ({', '.join(map(str, assoc_only))} rows: the "
           "associative back ends only; their error there is mostly the wall's own, λ falling as its blocks get "
           "smaller, with that of associative friction)"
           if assoc_only else "")
        + "; both load directions solved unless the wall is mirror-symmetric. Times are as run on the machine "
        "below (build and solve, first computation); data: `speed_accuracy.csv`.",
    )


def histories_figure(res: Results, path: Path) -> Figure | None:
    """λ per LP of the iterated LP on every case that ran it (``None``: none did)."""
    series = []
    for c in res.plan.cases:
        rec = res.record(c.spec(), res.plan.reference)
        na = rec.nonassoc
        if na is None or not na.history_load_factor:
            continue
        band, kind = na.mechanism_band, "mechanism band"
        if band is None and na.lambda_band is not None and all(math.isfinite(v) for v in na.lambda_band):
            band, kind = na.lambda_band, "cycling band"
        label = c.label if na.selection == "vertex" else f"{c.label}, {na.selection}"
        if na.reduced:
            label += f", model of {na.fused_bodies:,} bodies"
        series.append(History(label, rec.status, na.history_load_factor, band, kind))
    if not series:
        return None
    method = res.plan.reference.label
    histories(series, path, f"λ of every LP of the {method}, governing load direction")
    return Figure(
        path.name,
        f"The {method} on each of the paper's walls it ran on: λ of every LP of the governing load direction "
        "(the associative LP first, square), with the band of exact collapse states of the final mechanism "
        "(green) or, for a sequence that did not converge, the range of its last λ values (red). The panel's "
        "title gives the status (see the status legend) and the number of LPs (of the last sequence: a wall marked "
        "proximal shows that sequence, run after its vertex sequence ended without a state, see the "
        "table `histories`; a wall marked with a model of bodies, the reduced wall, shows the LPs of the model "
        "whose mechanism gave the state, its λ the model's); data: `histories.csv`.",
    )
