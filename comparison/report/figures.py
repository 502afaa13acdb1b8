"""Figures of the report (matplotlib, Agg, PNG), drawn from its results.

The generic charts (:func:`speed_accuracy`, :func:`sensitivity`,
:func:`histories`) take plain series; the report's figures read the
:class:`~comparison.report.results.Results`, and :func:`mechanism_figures`
draws each micro mechanism with the macro crack (α_c and α_c*) over it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import macro
from comparison.cases import cases_in_table
from comparison.report.results import Results
from comparison.report.tables import mechanism_record, published, speed_reference, speed_rows


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


@dataclass(frozen=True)
class SpeedPoint:
    """One point of the speed-accuracy chart."""

    label: str
    family: str
    seconds: float
    error: float  # |lambda - reference| / reference


def _save(fig, ax, path: Path, fontsize: int) -> Path:
    """Legend (when anything is labelled), layout, write, close."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=fontsize)
    fig.tight_layout()
    fig.savefig(path)
    _plt().close(fig)
    return path


def speed_accuracy(points: Sequence[SpeedPoint], reference: str, path: Path) -> Path:
    """Time (log) against relative error in lambda, one marker per family."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.5, 5), dpi=110)
    markers = dict(zip(sorted({p.family for p in points}), "osD^v<>phX", strict=False))
    floor = 1e-7
    for fam, mk in markers.items():
        pts = [p for p in points if p.family == fam and math.isfinite(p.error) and math.isfinite(p.seconds)]
        if not pts:
            continue
        ax.scatter([max(p.error, floor) for p in pts], [max(p.seconds, 1e-5) for p in pts], marker=mk, s=45, label=fam)
        for p in pts:
            ax.annotate(
                p.label,
                (max(p.error, floor), max(p.seconds, 1e-5)),
                fontsize=7,
                xytext=(4, 3),
                textcoords="offset points",
            )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"|Δλ| / λ against {reference} (errors below {floor:g} drawn at {floor:g})")
    ax.set_ylabel("time [s]")
    ax.grid(True, which="both", alpha=0.3)
    return _save(fig, ax, path, 8)


def sensitivity(
    panels: Mapping[str, Mapping[str, tuple[Sequence[float], Sequence[float]]]],
    path: Path,
    published: Mapping[str, tuple[Sequence[float], Sequence[float]]] | None = None,
) -> Path:
    """Load factor against each parameter; one panel per parameter, one line per method."""
    plt = _plt()
    n = len(panels)
    cols = min(3, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), dpi=110, squeeze=False)
    for ax, (param, series) in zip(axes.ravel(), panels.items(), strict=False):
        for label, (x, y) in series.items():
            ax.plot(x, np.asarray(y, dtype=float), marker="o", ms=3.5, label=label)
        if published and param in published:
            px, py = published[param]
            ax.scatter(px, py, marker="x", color="k", zorder=5, label="paper (Table 5)")
        ax.set_xlabel(param)
        ax.set_ylabel("λ")
        ax.grid(True, alpha=0.3)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    return _save(fig, axes.ravel()[0], path, 7)


def histories(series: Mapping[str, Sequence[float]], path: Path, title: str = "") -> Path:
    """Load factor against iteration of the iterated LP, one line per run."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4), dpi=110)
    for label, lam in series.items():
        ax.plot(np.arange(1, len(lam) + 1), lam, marker=".", label=label)
    ax.set_xlabel("iteration")
    ax.set_ylabel("λ")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    return _save(fig, ax, path, 7)


# ---------------------------------------------------------------- the report's figures


def sensitivity_figure(res: Results, path: Path) -> Path:
    """λ against each parameter of the base wall, macro and micro; in the full report with Table 5's values."""
    plan = res.plan
    panels: dict[str, dict[str, tuple[list[float], list[float]]]] = {}
    for param, values in plan.sweeps.items():
        specs = [plan.sweep_spec(param, v) for v in values]
        series = {"macro": (list(values), [res.macro[s].load_factor for s in specs])}
        for m in plan.methods:
            series[m.kind] = (list(values), [res.record(s, m).load_factor for s in specs])
        panels[param] = series
    return sensitivity(panels, path, None if plan.quick else _table5_points(plan.base))


def _table5_points(base: Mapping[str, float]) -> dict[str, tuple[list[float], list[float]]]:
    """Table 5's published λ against each parameter: the cases that differ from ``base`` in that parameter only."""
    out: dict[str, tuple[list[float], list[float]]] = {}
    for param in ("f", "p", "rows", "t", "m"):
        same = [c for c in cases_in_table("5") if all(getattr(c, k) == v for k, v in base.items() if k != param)]
        same.sort(key=lambda c: getattr(c, param))
        out[param] = ([getattr(c, param) for c in same], [published(c, "proposed") for c in same])
    return out


def speed_figure(res: Results, path: Path) -> Path:
    """The speed-accuracy chart of :func:`comparison.report.tables.speed_rows`."""
    points = [
        SpeedPoint(f"{r.rows} rows" if r.family.startswith("micro") else r.label, r.family, r.seconds, r.error)
        for r in speed_rows(res)
    ]
    ref = speed_reference(res)
    return speed_accuracy(points, f"{ref.method.kind}, {res.plan.resolutions[-1]} rows", path)


def histories_figure(res: Results, path: Path) -> Path | None:
    """λ per iteration of the iterated LP on every case that ran it (``None``: none did)."""
    series = {}
    for c in res.plan.cases:
        na = res.record(c.spec(), res.plan.reference).nonassoc
        if na is not None and na.history_load_factor:
            series[c.label] = list(na.history_load_factor)
    return histories(series, path, "λ per iteration of the iterated LP") if series else None


def mechanism_figures(res: Results, out: Path) -> list[str]:
    """One figure per case: the micro mechanism with the macro crack drawn over it; the file names."""
    from micro.plot import draw_mechanism

    plt = _plt()
    names = []
    for c in res.plan.cases:
        spec = c.spec()
        rec = mechanism_record(res, c)
        mech = res.mechanisms.get((spec, rec.method))
        if mech is None:
            continue
        wall = spec.to_micro()
        r = res.macro[spec]
        fig, ax = plt.subplots(figsize=(7, 7 * min(1.4, max(0.4, wall.height / wall.length))), dpi=100)
        draw_mechanism(ax, wall, mech.velocities, fig=fig)
        _draw_macro_crack(ax, r, mech.direction)
        ax.set_title(
            f"{c.label}: {rec.method.kind} λ = {rec.load_factor:.3f}, macro λ = {r.load_factor:.3f} "
            f"(α_c = {r.alpha_c_deg:.1f}°)",
            fontsize=9,
        )
        ax.legend(fontsize=7, loc="upper right")
        name = f"mechanism_{c.case.lower()}.png"
        fig.savefig(out / name, bbox_inches="tight")
        plt.close(fig)
        names.append(name)
    return names


def _draw_macro_crack(ax: Any, r: macro.MacroResult, direction: str) -> None:
    """The macro crack through the hinge (α_c) and the stepped crack (α_c*), in the micro wall's frame."""
    w = r.wall
    k = r.hinge_storey
    base = sum(w.rows[k:]) * w.block_height
    height = sum(w.rows[:k]) * w.block_height
    L, v = w.length, w.overlap
    ys = [0.0, height]
    lines = {
        "macro crack through the hinge (α_c)": [0.0, r.tan_alpha_c * height],
        "macro stepped crack (α_c*)": [v, v + r.tan_alpha_c_star * height],
    }
    for (label, xs), style in zip(lines.items(), ("--", "-"), strict=True):
        xs_c = [min(x, L) for x in xs]
        ys_c = [ys[0], ys[0] + (ys[1] - ys[0]) * (xs_c[1] - xs[0]) / (xs[1] - xs[0]) if xs[1] != xs[0] else ys[1]]
        if direction == "+x":
            xs_c = [L - x for x in xs_c]
        ax.plot(xs_c, [base + y for y in ys_c], style, color="red", lw=1.5, label=label)
