"""Figures of the report (matplotlib, Agg, PNG)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np


def _plt():  # type: ignore[no-untyped-def]
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


def _save(fig, ax, path: Path, fontsize: int) -> Path:  # type: ignore[no-untyped-def]
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
            ax.annotate(p.label, (max(p.error, floor), max(p.seconds, 1e-5)), fontsize=7, xytext=(4, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"|Δλ| / λ against {reference} (errors below {floor:g} drawn at {floor:g})")
    ax.set_ylabel("time [s]")
    ax.grid(True, which="both", alpha=0.3)
    return _save(fig, ax, path, 8)


def sensitivity(panels: Mapping[str, Mapping[str, tuple[Sequence[float], Sequence[float]]]], path: Path, published: Mapping[str, tuple[Sequence[float], Sequence[float]]] | None = None) -> Path:
    """Load factor against each parameter; one panel per parameter, one line per method."""
    plt = _plt()
    n = len(panels)
    cols = min(3, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), dpi=110, squeeze=False)
    for ax, (param, series) in zip(axes.ravel(), panels.items(), strict=False):
        for label, (x, y) in series.items():
            y = np.asarray(y, dtype=float)
            ax.plot(x, y, marker="o", ms=3.5, label=label)
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
