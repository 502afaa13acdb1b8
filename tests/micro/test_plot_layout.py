"""The mechanism figure's layout: a long title stays over its axes, clear of the colour bar beside them."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import micro
import micro.plot

#: The title ``xcheck micro --friction nonassociative --plot`` gives a 54-block wall.
TITLE = ("non-associative micro λ = 0.6911 (lowest certified; iterated LP 0.7086), +x, 54 blocks")


@pytest.mark.parametrize(("rows", "length"), [(12, 12.0), (18, 6.0), (6, 40.0)])
def test_a_long_title_does_not_run_under_the_colour_bar(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, rows: int, length: float
) -> None:
    wall = micro.build_wall(length=length, block_length=3.0, block_height=1.0, rows=(rows,), thickness=(1.0,),
                            overload=(0.0,), unit_weight=1.0, friction=0.6)
    velocities = np.column_stack([wall.yc, np.zeros(wall.n_blocks), np.zeros(wall.n_blocks)]) * 1e-3
    seen: dict[str, Any] = {}

    def inspect(fig: Any, path: Any, **kw: Any) -> Path:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        ax, bar = fig.axes[0], fig.axes[1]
        seen["title"] = ax.title.get_window_extent(renderer)
        seen["bar"] = bar.get_window_extent(renderer)
        seen["text"] = ax.title.get_text()
        return Path(path)

    monkeypatch.setattr(micro.plot, "save_figure", inspect)
    micro.plot.plot_velocities(wall, velocities, tmp_path / "m.png", title=TITLE, direction="+x", hinge=0.0)
    assert seen["title"].x1 <= seen["bar"].x0, (seen["text"], seen["title"], seen["bar"])
    assert seen["text"].replace("\n", " ") == TITLE  # every word kept, broken at a comma or semicolon
