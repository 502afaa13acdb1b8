"""The sweep page's figures: tick labels of the time-against-blocks figure, plain numbers (``20``, ``0.05``)
that do not run into each other.

Matplotlib labels a log axis of less than a decade or two at its minor ticks as well, in powers of ten
(``2×10^1, 3×10^1, 4×10^1``): wide labels close together, reported to overlap on a small sweep's figure.
"""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import Any

import pytest

import comparison.sweep.figures as figures


def _rows(blocks: list[int], seconds: list[float]) -> list[dict[str, str]]:
    return [{"kind": "micro-assoc", "status": "optimal", "blocks": str(b), "seconds": str(s),
             "method": "micro-assoc (highs-ipm)"} for b, s in zip(blocks, seconds, strict=True)]


@pytest.mark.parametrize(("blocks", "seconds"), [
    ([9, 15, 21, 39], [0.02, 0.05, 0.04, 0.1]),  # the tiny sweep's walls
    ([20, 35, 50, 65, 80, 95], [0.02, 0.025, 0.03, 0.033, 0.036, 0.04]),  # less than a decade: minor labels
    ([12, 54, 300, 1500], [0.01, 0.1, 3.0, 400.0]),  # several decades
])
def test_tick_labels_of_the_time_figure_do_not_overlap(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, blocks: list[int], seconds: list[float]
) -> None:
    boxes: dict[str, list[Any]] = {}
    texts: dict[str, list[str]] = {}

    def inspect(fig: Any, path: Path) -> Path:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        ax = fig.axes[0]
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            ticks = [*axis.get_major_ticks(), *axis.get_minor_ticks()]
            shown = [t.label1 for t in ticks if t.label1.get_visible() and t.label1.get_text()]
            texts[name] = [label.get_text() for label in shown]
            boxes[name] = [label.get_window_extent(renderer) for label in shown]
        return path

    monkeypatch.setattr(figures, "_save", inspect)
    figures.time_against_blocks(_rows(blocks, seconds), tmp_path / "time.png")
    for name, found in boxes.items():
        assert found, f"no {name} tick label"
        assert all(float(t) > 0 for t in texts[name]), texts[name]  # plain numbers, not 2×10^1
        for a, b in itertools.combinations(found, 2):
            assert not a.overlaps(b), (name, a, b)


def test_a_wall_beyond_the_histograms_scale_is_not_counted_in_its_end_bin() -> None:
    """Walls beyond the histogram's scale are drawn apart, as open-ended bars of their own, never in an end bin."""
    inside, below, beyond = figures.binned([-3.0, 0.0, 2.0, 6.0, 20.0], -2.0, 6.0)
    assert inside == [0.0, 2.0, 6.0] and below == [-3.0] and beyond == [20.0]


def test_a_cell_without_a_micro_value_is_hatched_not_pale(tmp_path: Path) -> None:
    """A cell of the error map without a micro value is hatched, never as pale as a difference near 0."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import TwoSlopeNorm

    fig, ax = plt.subplots()
    figures._panel(ax, [[None, None]], "macro", TwoSlopeNorm(0.0, -0.1, 0.1))
    hatched = [p for p in ax.patches if p.get_hatch()]
    plt.close(fig)
    assert len(hatched) == 2
