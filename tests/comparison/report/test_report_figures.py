"""The report's figures and their text: captions numbered, statuses explained, labels apart, mechanisms drawn
in block heights with the load arrow."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from comparison.report.figures import Figure, SpeedPoint, _cluster_labels, base_wall, pyplot, speed_accuracy
from comparison.report.tables import Table
from comparison.report.text import GLOSSARY, STATUS_LEGEND, figure_list, glossary, status_legend


def test_figures_are_numbered_with_their_captions() -> None:
    text = figure_list([Figure("a.png", "First."), Figure("b.png", "Second.")])
    assert text == "![Figure 1](a.png)\n\n**Figure 1.** First.\n\n![Figure 2](b.png)\n\n**Figure 2.** Second."


def test_status_legend_explains_every_status_shown_and_no_other() -> None:
    t = Table("t", "T", ["case", "λ", "status"])
    t.add("Set 2", "0.5466-0.5493 (cycling)", "cycling")
    t.add("Set 10", "not run", "not_run")
    t.add("Set 8", "n/a", "not_applicable")
    t.add("Set 8", math.nan, "max_iterations")
    t.add("Set 9", None, "converged")
    legend = status_legend({"t": t})
    shown = [line.split("`")[1] for line in legend.splitlines()]
    assert shown == ["converged", "cycling", "max_iterations", "not run", "n/a", "not_applicable", "–"]
    assert "time budget" in legend  # max_iterations also means the time budget
    assert set(STATUS_LEGEND) >= set(shown)


def test_glossary_defines_the_symbols_of_the_report() -> None:
    assert {"λ_r", "λ_s", "α_c", "α_c*", "band"} <= set(GLOSSARY)
    assert glossary().count("\n") == len(GLOSSARY) - 1


def test_base_wall_in_words() -> None:
    base = {"t": 1.0, "m": 1 / 3, "rows": 60, "f": 0.6, "p": 0.0, "storeys": 3}
    assert base_wall(base) == "t = 1, m = 1/3, o = 60, p = 0, f = 0.6, 3 storeys"


def test_speed_labels_once_per_resolution_and_apart(tmp_path: Path) -> None:
    pts = [
        SpeedPoint(f"{r} rows", fam, s, e, r) for fam in ("a", "b") for r, s, e in ((3, 0.01, 0.05), (6, 0.02, 0.052))
    ]
    labels = _cluster_labels(pts, 1e-7)
    assert sorted(k.rstrip("\u200b") for k in labels) == ["3 rows", "6 rows"]
    speed_accuracy(pts, "ref", tmp_path / "s.png")
    assert (tmp_path / "s.png").stat().st_size > 0


def test_mechanism_drawn_in_block_heights_with_arrow() -> None:
    """A dimensional wall (blocks 0.1 high, 60 rows) is drawn 60 block heights tall, with the arrow left of it."""
    from comparison.scene import load_scene
    from micro.plot import draw_mechanism

    wall = load_scene(Path(__file__).parents[3] / "examples" / "three-storey.toml").to_micro()
    vel = np.zeros((len(wall.xc), 3))
    vel[:, 0] = wall.yc / wall.height  # a shear-like field, largest at the top
    plt = pyplot()
    fig, ax = plt.subplots()
    amp = draw_mechanism(ax, wall, vel, direction="+x")
    assert ax.get_xlabel() == f"x [block heights]; displacements × {amp:.3g} (largest: {amp * vel[:, 0].max():.2g})"
    assert ax.get_ylabel() == "y [block heights]"
    (arrow,) = [t for t in ax.texts if getattr(t, "arrow_patch", None) is not None]
    assert arrow.xy[0] < 0 < arrow.xy[1] < 60  # pointing right, at the wall's left
    assert ax.dataLim.y1 == pytest.approx(60, abs=1)  # the top course, not 6.0
    plt.close(fig)
