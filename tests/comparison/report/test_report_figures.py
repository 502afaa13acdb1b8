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
    assert "cap of LPs" in legend and "time budget" not in legend  # no wall-clock stop in the report
    assert set(STATUS_LEGEND) >= set(shown)


def test_glossary_defines_the_symbols_of_the_report() -> None:
    assert {"λ_r", "λ_s", "α_c", "α_c*", "band"} <= set(GLOSSARY)
    assert glossary().count("\n") == len(GLOSSARY) - 1


def test_base_wall_in_words() -> None:
    base = {"t": 1.0, "m": 1 / 3, "rows": 60, "f": 0.6, "p": 0.0, "storeys": 3}
    assert base_wall(base) == "t = 1, m = 1/3, o = 60, p = 0, f = 0.6, 3 storeys"


def test_speed_labels_once_per_resolution_and_apart(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Each family is one line through its points; each wall resolution is labelled once, and no two
    labels overlap on the drawn figure."""
    import comparison.report.figures as figures

    kept: list = []
    monkeypatch.setattr(figures, "save_figure", lambda fig, path: kept.append(fig) or path)
    pts = [
        SpeedPoint(f"{r} rows", fam, s, e, r) for fam in ("a", "b") for r, s, e in ((3, 0.01, 0.05), (6, 0.02, 0.052))
    ]
    labels = _cluster_labels(pts, 1e-7)
    assert sorted(k.rstrip("\u200b") for k in labels) == ["3 rows", "6 rows"]
    speed_accuracy(pts, "ref", tmp_path / "s.png")
    (fig,) = kept
    ax = fig.axes[0]
    lines = {ln.get_label(): (list(ln.get_xdata()), list(ln.get_ydata())) for ln in ax.get_lines()}
    assert lines == {"a": ([0.05, 0.052], [0.01, 0.02]), "b": ([0.05, 0.052], [0.01, 0.02])}
    texts = [t for t in ax.texts if t.get_text() in ("3 rows", "6 rows")]
    assert sorted(t.get_text() for t in texts) == ["3 rows", "6 rows"]
    renderer = fig.canvas.get_renderer()
    a, b = (t.get_window_extent(renderer) for t in texts)
    assert not a.overlaps(b)
    assert ax.get_xscale() == ax.get_yscale() == "log" and ax.get_ylabel() == "time [s]"
    pyplot().close(fig)


def test_mechanism_drawn_in_block_heights_with_arrow() -> None:
    """A dimensional wall (blocks 0.1 high, 60 rows) is drawn 60 block heights tall, with the arrow left of it."""
    from comparison.domain.scene import load_scene
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


def test_mechanism_colour_bar_says_what_it_is_normalised_to() -> None:
    """Colours are block speeds over the fastest block's (0 to 1), and the colour bar says so."""
    from matplotlib.collections import PolyCollection

    from micro import build_wall
    from micro.plot import draw_mechanism

    wall = build_wall(length=12, block_length=3, block_height=1, rows=(4,), thickness=(1,), overload=(0,),
                      unit_weight=1, friction=0.75)  # fmt: skip
    vel = np.zeros((len(wall.xc), 3))
    vel[:, 0] = 0.002 * wall.yc  # speeds in the LP's units, far below 1
    plt = pyplot()
    fig, ax = plt.subplots()
    draw_mechanism(ax, wall, vel, fig=fig)
    (moved,) = [c for c in ax.collections if isinstance(c, PolyCollection) and c.get_array() is not None]
    assert float(np.max(moved.get_array())) == pytest.approx(1.0)
    assert moved.get_clim() == (0.0, 1.0)
    assert "fastest block" in fig.axes[-1].get_ylabel()
    plt.close(fig)


def test_speed_reference_point_is_marked_at_the_floor_off_the_line(tmp_path: Path, monkeypatch) -> None:
    """The exact reference (error 0) is a hollow marker at the axis floor, named, not a line across the chart;
    the macro point is named."""
    import comparison.report.figures as figures

    kept = []
    monkeypatch.setattr(figures, "save_figure", lambda fig, path: kept.append(fig) or path)
    pts = [SpeedPoint(f"{r} rows", "nonassoc", s, e, r) for r, s, e in ((12, 0.1, 0.2), (24, 0.5, 0.08), (60, 5, 0))]
    pts.append(SpeedPoint("60 rows", "macro", 1e-3, 0.24, 60))
    speed_accuracy(pts, "nonassoc, 60 rows", tmp_path / "s.png")
    (fig,) = kept
    ax = fig.axes[0]
    (line,) = [ln for ln in ax.get_lines() if ln.get_label() == "nonassoc"]
    assert list(line.get_xdata()) == [0.2, 0.08]  # the reference is not on its family's line
    floor = [ln for ln in ax.get_lines() if list(ln.get_xdata()) == [figures.SPEED_FLOOR]]
    assert len(floor) == 1 and floor[0].get_markerfacecolor() == "none"
    texts = [t.get_text() for t in ax.texts]
    assert any("the reference (error 0)" in t for t in texts)
    assert any(t.startswith("macro model") for t in texts)
    pyplot().close(fig)


def test_lowest_chart_one_bin_width_readable_groups_both_axes_labelled() -> None:
    from comparison.stability.lowest_render import BIN_WIDTH, GROUPS, chart_figure

    fig = chart_figure([0.0, -1e-10, 0.1, 0.31], {"grid": [0.0, 0.02, 0.09], "tiny": [0.45], "table7": [0.01]})
    widths = {round(p.get_width(), 9) for ax in fig.axes for p in ax.patches if p.get_height() > 0}
    assert widths == {BIN_WIDTH}
    left, right = fig.axes[:2]
    assert left.get_ylabel() == right.get_ylabel() == "walls"
    assert sum(p.get_height() for p in left.patches) == 4  # the rounding excess (-1e-10) counts at 0
    labels = [t.get_text() for t in right.get_legend().get_texts()]
    assert labels == [f"{GROUPS[g]} ({n})" for g, n in (("grid", 3), ("tiny", 1), ("table7", 1))]
    assert not any(name in ("grid", "tiny", "table7") for name in labels)
    pyplot().close(fig)


def test_quick_report_numbers_the_error_map_and_the_lowest_figure(quick_report_dir: Path) -> None:
    """Every figure of REPORT.md is numbered in order with its caption, the error map and lowest.png too."""
    import re

    text = (quick_report_dir / "REPORT.md").read_text()
    images = re.findall(r"!\[([^\]]*)\]\(([^)]+)\)", text)
    assert [label for label, _ in images] == [f"Figure {i}" for i in range(1, len(images) + 1)]
    names = [name for _, name in images]
    assert names[-5:] == ["errormap-map.png", "errormap-scatter.png", "errormap-histogram.png", "errormap-time.png",
                          "lowest.png"]
    assert all((quick_report_dir / name).stat().st_size > 0 for name in names)
    for i in range(1, len(images) + 1):
        assert f"**Figure {i}.** " in text
    assert "README" not in text


def test_the_lowest_figure_draws_the_committed_study(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """The report's ``lowest.png`` is drawn from ``reports/lowest.csv``: the left histogram counts the walls
    where the global search closed, the right one every wall of each group, stacked; read back from the
    figure the report draws."""
    from comparison.report import lowest as report_lowest
    from comparison.stability import lowest_render

    kept: list = []

    def keep(over_global, over_lowest, path):  # type: ignore[no-untyped-def]
        kept.append(lowest_render.chart_figure(over_global, over_lowest))
        return path

    monkeypatch.setattr(report_lowest, "chart", keep)
    rows = report_lowest.load(Path(__file__).parents[3] / "reports" / "lowest.csv")
    report_lowest.figure(rows, tmp_path / "lowest.png")
    (fig,) = kept
    left, right = fig.axes[:2]
    closed = sum(1 for r in rows if r["global_status"] == "optimal")
    assert sum(p.get_height() for p in left.patches) == closed > 0
    assert sum(p.get_height() for p in right.patches) == len(rows)
    legend = [t.get_text() for t in right.get_legend().get_texts()]
    assert legend == [f"{lowest_render.GROUPS[g]} ({sum(1 for r in rows if r['group'] == g)})"
                      for g in lowest_render.GROUPS if any(r["group"] == g for r in rows)]
    pyplot().close(fig)


def test_mechanism_caption_says_not_run_where_the_reference_was_not_run() -> None:
    from types import SimpleNamespace

    from comparison.report.mechanisms import _why_not

    case = SimpleNamespace(spec=lambda: "wall")
    for status, words in (("not_run", "not run on this wall"), ("cycling", "ended `cycling`")):
        res = SimpleNamespace(
            record=lambda spec, method, s=status: SimpleNamespace(status=s),
            plan=SimpleNamespace(reference=SimpleNamespace(kind="micro-nonassoc", column="micro-nonassoc")),
        )
        text = _why_not(res, case)  # type: ignore[arg-type]
        assert words in text and "did not converge" not in text


def test_full_sensitivity_sweep_reaches_the_papers_widest_wall() -> None:
    """The t sweep reaches t = 3 (Table 5's Set 8), so its curves reach the paper's point."""
    from comparison.domain.cases import cases_in_table
    from comparison.report.plan import SWEEPS_FULL

    assert max(SWEEPS_FULL["t"]) >= max(c.t for c in cases_in_table("5"))


def _marks_drawn(ax: object, block_height: float) -> dict[str, object]:
    """What a mechanism plot marks, read back from its axes: the floor lines' heights and spans, the hinge
    marker's points and label, the storey names of the second y axis (bottom first), in block heights."""
    from matplotlib.lines import Line2D

    lines = [a for a in ax.get_lines() if isinstance(a, Line2D)]  # type: ignore[attr-defined]
    floors = [ln for ln in lines if ln.get_linestyle() == "--" and ln.get_color() == "0.1"]
    hinge = [ln for ln in lines if ln.get_marker() == "o"]
    storeys = [t.get_text() for c in ax.child_axes for t in c.get_yticklabels()]  # type: ignore[attr-defined]
    return {
        "floors": sorted(float(ln.get_ydata()[0]) for ln in floors),
        "spans": {tuple(float(x) for x in ln.get_xdata()) for ln in floors},
        "hinge": [list(zip(ln.get_xdata(), ln.get_ydata(), strict=True)) for ln in hinge],
        "hinge_label": [ln.get_label() for ln in hinge],
        "storeys": storeys,
    }


def test_the_mechanism_plot_marks_floors_and_a_hinge_given_as_plain_numbers() -> None:
    """The mechanism plots mark the floors and the macro model's hinge, which the micro plot takes as plain
    numbers (micro imports neither macro nor comparison): dashed lines across the wall at the floors, the
    storeys named on a second axis, the hinge as a labelled circle at the toe the wall rotates about (the
    side the load pushes towards)."""
    from comparison.domain.scene import load_scene
    from micro.plot import draw_mechanism

    wall = load_scene(Path(__file__).parents[3] / "examples" / "three-storey.toml").to_micro()  # 3 x 20 rows, b = 0.1
    vel = np.zeros((len(wall.xc), 3))
    vel[:, 0] = wall.yc / wall.height
    plt = pyplot()
    for direction, toe in (("+x", 60.0), ("-x", 0.0)):
        fig, ax = plt.subplots()
        draw_mechanism(ax, wall, vel, direction=direction, floors=[2.0, 4.0], hinge=2.0, hinge_label="macro hinge")
        drawn = _marks_drawn(ax, wall.block_height)
        assert drawn["floors"] == pytest.approx([20.0, 40.0])  # block heights
        assert drawn["spans"] == {(0.0, 60.0)}  # across the wall, L = 6 m = 60 block heights
        assert drawn["hinge"] == [[(pytest.approx(toe), pytest.approx(20.0))]]
        assert drawn["hinge_label"] == ["macro hinge"]
        assert drawn["storeys"] == ["storey 3", "storey 2", "storey 1"]
        plt.close(fig)
    fig, ax = plt.subplots()
    draw_mechanism(ax, wall, vel)  # nothing asked: nothing marked
    assert _marks_drawn(ax, wall.block_height) == {"floors": [], "spans": set(), "hinge": [], "hinge_label": [],
                                                   "storeys": []}  # fmt: skip
    plt.close(fig)


def test_the_report_marks_the_floors_and_the_macro_hinge_on_each_mechanism(tmp_path: Path, monkeypatch) -> None:
    """The report's mechanism figure of a three-storey wall (Set 5, its associative mechanism) shows the two
    floors, the three storeys and the macro model's hinge at the base of its storey, where the macro crack
    starts; the caption names the floor lines."""
    from types import SimpleNamespace

    import macro
    import micro
    from comparison.domain.cases import case
    from comparison.report import mechanisms
    from comparison.runner import MICRO_ASSOC, MechanismRecord

    c = case("5")
    spec = c.spec()
    r = macro.solve(spec.to_macro())
    sol = micro.solve_associative(spec.to_micro())
    assert sol.mechanism is not None
    mechanism = MechanismRecord(sol.mechanism.velocities, sol.direction)
    res = SimpleNamespace(plan=SimpleNamespace(cases=[c], reference=MICRO_ASSOC, methods=[MICRO_ASSOC]),
                          macro={spec: r}, mechanisms={(spec, MICRO_ASSOC): mechanism})  # fmt: skip
    monkeypatch.setattr(mechanisms, "mechanism_record",
                        lambda res, c: SimpleNamespace(method=MICRO_ASSOC, load_factor=sol.load_factor,
                                                       nonassoc=None))  # fmt: skip
    plt = pyplot()
    kept = []
    monkeypatch.setattr(mechanisms, "save_figure", lambda fig, path: kept.append(fig))
    (figure,) = mechanisms.mechanism_figures(res, tmp_path)  # type: ignore[arg-type]
    ax = kept[0].axes[0]
    drawn = _marks_drawn(ax, spec.block_height)
    assert drawn["floors"] == pytest.approx([12.0, 24.0]) and drawn["storeys"] == ["storey 3", "storey 2", "storey 1"]
    toe = 36.0 if sol.direction == "+x" else 0.0  # o m = 12 blocks of 3: L = 36 block heights
    base = 12.0 * (3 - r.hinge_storey)
    assert drawn["hinge"] == [[(pytest.approx(toe), pytest.approx(base))]]
    assert drawn["hinge_label"] == [f"macro hinge: base of storey {r.hinge_storey}"]
    crack = next(ln for ln in ax.get_lines() if ln.get_label() == "macro crack through the hinge (α_c)")
    assert (crack.get_xdata()[0], crack.get_ydata()[0]) == (pytest.approx(toe), pytest.approx(base))
    assert {t.get_text() for t in ax.get_legend().get_texts()} >= {"floor", drawn["hinge_label"][0]}
    assert "dashed: the floors" in figure.caption
    assert f"the hinge (circle) at the base of storey {r.hinge_storey}" in figure.caption
    plt.close(kept[0])
