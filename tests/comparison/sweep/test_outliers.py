"""One outlier does not flatten the validation page's colour scale and histogram: the outlier fences."""

from __future__ import annotations

from pathlib import Path

import pytest

from comparison.sweep.figures import FENCE_FLOOR, fences
from comparison.sweep.page import render

#: The differences of a 12-wall grid (t = 1/2, 1, 3/2; m = 1/3, 1/2; 8 and 16 rows; f = 0.65) whose worst
#: wall's micro value is a cut end piece of the top course tipping on its own (+215 %).
GRID = [2.150, 0.417, 0.300, 0.231, 0.035, 0.034, 0.033, 0.032, 0.002, 0.0, -0.075, -0.075]


def test_the_fences_leave_out_the_outlier_only() -> None:
    lo, hi = fences(GRID)
    assert [d for d in GRID if not lo <= d <= hi] == [2.150]
    assert lo < -0.075 and hi > 0.417


def test_walls_that_agree_make_no_outliers_of_a_few_per_cent() -> None:
    """Most walls agree (an interquartile range of 0): a difference within the floor is no outlier."""
    lo, hi = fences([0.0] * 9 + [0.03, -0.04, 0.5])
    assert (lo, hi) == (pytest.approx(-FENCE_FLOOR), pytest.approx(FENCE_FLOOR))
    assert lo < -0.04 and 0.03 < hi < 0.5


def test_a_page_with_an_outlier_draws_and_says_so(tmp_path: Path) -> None:
    base = {"m": "0.5", "rows": "12", "f": "0.75", "p": "0", "storeys": "1", "first_course": "full",
            "head_joints": "frictional", "blocks": "78", "quoted": "lowest certified", "message": ""}
    rows = []
    for t, d in zip(("0.5", "1", "1.5", "2"), (0.01, -0.02, 0.03, 2.0), strict=True):
        wall = {**base, "t": t, "wall": f"t={t}"}
        rows += [{**wall, "method": "macro", "kind": "macro", "load_factor": repr(0.5 * (1 + d)), "status": "optimal"},
                 {**wall, "method": "micro-nonassoc", "kind": "micro-nonassoc", "load_factor": "0.5",
                  "status": "converged"}]
    page = render(rows, tmp_path, title="t", intro="", prefix="o", source="o.csv")
    assert [p.name for p in page.figures] == ["o-map.png", "o-scatter.png", "o-histogram.png"]
    assert "a wall beyond them is outlined" in page.text and "drawn in the end bins" in page.text


def test_the_scale_leaves_out_only_an_outlier_that_would_stretch_it() -> None:
    from comparison.sweep.figures import scale

    assert scale(GRID) == (-0.075, 0.417)  # +215 % would stretch it fivefold
    near = [-0.14, -0.14, 0.266, 0.0, 0.0, 0.0, 0.05, 0.05, 0.27, 0.0, 0.0, 0.12]
    assert scale(near) == (-0.14, 0.27)  # +27 % beside +26.6 %: no outlier to leave out
