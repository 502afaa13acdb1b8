"""Builder: block layout, loads and contacts checked by hand on tiny walls."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import micro
from micro.geometry import BASE, BED, HEAD
from micro.memory import available_memory_bytes


def tiny(**kw: object) -> micro.BlockWall:
    args = dict(length=6.0, block_length=3.0, block_height=1.0, rows=(2,), thickness=(1.0,), overload=(0.0,),
                unit_weight=1.0, friction=0.75)
    args.update(kw)
    return micro.build_wall(**args)  # type: ignore[arg-type]


def test_two_rows_two_blocks_by_hand() -> None:
    w = tiny()
    # bottom course: [0,3] [3,6]; top course: [0,1.5] [1.5,4.5] [4.5,6]
    assert w.n_blocks == 5
    assert np.allclose(w.x0, [0, 3, 0, 1.5, 4.5]) and np.allclose(w.x1, [3, 6, 1.5, 4.5, 6])
    assert np.allclose(w.y0, [0, 0, 1, 1, 1])
    assert w.total_weight == pytest.approx(2 * 6.0)  # 2 rows x length 6 x b=1 x t=1
    contacts = sorted(
        (int(k), int(a), int(b), tuple(px), tuple(py))
        for k, a, b, px, py in zip(w.contact_kind, w.contact_a, w.contact_b, w.px, w.py, strict=True)
    )
    assert contacts == sorted([
        (BASE, -1, 0, (0.0, 3.0), (0.0, 0.0)),
        (BASE, -1, 1, (3.0, 6.0), (0.0, 0.0)),
        (HEAD, 0, 1, (3.0, 3.0), (0.0, 1.0)),
        (HEAD, 2, 3, (1.5, 1.5), (1.0, 2.0)),
        (HEAD, 3, 4, (4.5, 4.5), (1.0, 2.0)),
        (BED, 0, 2, (0.0, 1.5), (1.0, 1.0)),
        (BED, 0, 3, (1.5, 3.0), (1.0, 1.0)),
        (BED, 1, 3, (3.0, 4.5), (1.0, 1.0)),
        (BED, 1, 4, (4.5, 6.0), (1.0, 1.0)),
    ])
    assert w.n_points == 18
    assert np.allclose(w.normal[w.contact_kind == HEAD], [1.0, 0.0])
    assert np.allclose(w.normal[w.contact_kind != HEAD], [0.0, 1.0])
    assert w.mirror_symmetric


def test_first_course_half_swaps_the_bond() -> None:
    w = tiny(first_course="half")
    assert np.allclose(w.x0[:3], [0, 1.5, 4.5]) and w.n_blocks == 5


def test_odd_half_blocks_end_with_half_block_and_is_not_symmetric() -> None:
    w = tiny(length=7.5)  # 5 half blocks: full, full, half / half, full, full
    assert np.allclose(w.x1[:3], [3, 6, 7.5])
    assert np.allclose(w.x0[3:], [0, 1.5, 4.5])
    assert not w.mirror_symmetric


def test_loads_self_weight_and_overload_at_floor_level() -> None:
    w = micro.build_wall(length=6.0, block_length=2.0, block_height=0.5, rows=(1, 2), thickness=(0.2, 0.4),
                         overload=(3.0, 5.0), unit_weight=10.0, friction=0.6)
    # storey 2 (bottom) courses 0-1, t=0.4, floor load 5 on course 1; storey 1: course 2, t=0.2, load 3
    weight = 10.0 * 0.5 * (2 * 6.0 * 0.4 + 6.0 * 0.2)
    assert w.total_weight == pytest.approx(weight)
    assert w.total_dead_load == pytest.approx(weight + 5.0 * 6.0 + 3.0 * 6.0)
    assert np.sum(w.live[:, 0]) == pytest.approx(w.total_dead_load)
    floor1 = w.course == 1
    q = 5.0 * (w.x1 - w.x0)
    assert np.allclose(w.live[floor1, 2], -q[floor1] * 0.25)  # overload mass at the top face
    assert np.allclose(w.live[w.course == 0, 2], 0.0)
    assert list(np.unique(w.storey[w.course == 2])) == [1]


def test_frictionless_head_joints() -> None:
    w = tiny(head_joints="frictionless")
    assert np.all(w.mu[w.contact_kind == HEAD] == 0.0)
    assert np.all(w.mu[w.contact_kind != HEAD] == 0.75)


def test_paper_block_counts() -> None:
    from comparison.domain.wall import WallSpec

    counts = {(0.5, 1 / 3): 102, (1.0, 1 / 3): 54, (1.0, 1.0): 150}
    for (t, m), n in counts.items():
        assert WallSpec.from_paper(t=t, m=m, rows=12, f=0.75).to_micro().n_blocks == n
    assert WallSpec.from_paper(t=1, m=1 / 3, rows=60, f=0.6, storeys=3).to_micro().n_blocks == 1230


def test_table9_wall_assembles() -> None:
    """Sizes of the 7,575-block wall (its build time is a benchmark: tests/benchmarks)."""
    from comparison.domain.wall import WallSpec

    w = WallSpec.from_paper(t=1, m=1 / 3, rows=150, f=0.6, storeys=5).to_micro()
    lp = micro.assemble(w)
    assert w.n_blocks == 7575
    assert lp.n_rows == 3 * 7575
    assert lp.n_cols == 2 * lp.n_points + 1


@pytest.mark.parametrize(
    ("kw", "word"),
    [
        ({"length": 1.0}, "length"),
        ({"length": -1.0}, "length"),
        ({"block_length": 0.0}, "block_length"),
        ({"rows": (0,)}, "rows"),
        ({"rows": ()}, "rows"),
        ({"rows": (2, 2)}, "thickness"),
        ({"thickness": (1.0, 1.0)}, "thickness"),
        ({"overload": (-1.0,)}, "overload"),
        ({"friction": 0.0}, "friction"),
        ({"unit_weight": float("nan")}, "unit_weight"),
        ({"first_course": "middle"}, "first_course"),
        ({"head_joints": "sticky"}, "head_joints"),
    ],
)
def test_bad_inputs(kw: dict[str, object], word: str) -> None:
    with pytest.raises(ValueError, match=word):
        tiny(**kw)


def test_memory_guard_quotes_estimate() -> None:
    with pytest.raises(ValueError, match=r"too large.*bytes.*available"):
        tiny(length=9e5, rows=(1000,))  # 3e8 blocks (lengths are bounded by 1e6 block heights)
    with pytest.raises(ValueError, match="too large"):
        tiny(max_bytes=1000)
    assert available_memory_bytes() is None or available_memory_bytes() > 0


@settings(max_examples=30, deadline=None)
@given(
    n_half=st.integers(1, 25),
    rows=st.lists(st.integers(1, 4), min_size=1, max_size=3),
    first=st.sampled_from(["full", "half"]),
)
def test_layout_invariants(n_half: int, rows: list[int], first: str) -> None:
    w = micro.build_wall(length=0.5 * n_half, block_length=1.0, block_height=0.25, rows=tuple(rows),
                         thickness=(1.0,) * len(rows), overload=(0.0,) * len(rows), unit_weight=1.0,
                         friction=0.5, first_course=first)  # type: ignore[arg-type]
    lengths = w.x1 - w.x0
    assert np.all(np.isclose(lengths, 1.0) | np.isclose(lengths, 0.5))
    # every course tiles [0, L]
    for c in range(w.n_courses):
        sel = w.course == c
        assert np.isclose(lengths[sel].sum(), w.length)
    assert w.total_weight == pytest.approx(w.length * w.height)
    # bed-joint overlaps tile every internal bed line; base tiles the base
    bed = w.contact_kind == BED
    assert np.isclose(np.sum(w.px[bed, 1] - w.px[bed, 0]), w.length * (w.n_courses - 1))
    base = w.contact_kind == BASE
    assert np.isclose(np.sum(w.px[base, 1] - w.px[base, 0]), w.length)
    # overlapping blocks really overlap
    a, b = w.contact_a[bed], w.contact_b[bed]
    assert np.all(w.x0[a] <= w.px[bed, 0] + 1e-12) and np.all(w.px[bed, 1] <= w.x1[a] + 1e-12)
    assert np.all(w.x0[b] <= w.px[bed, 0] + 1e-12) and np.all(w.px[bed, 1] <= w.x1[b] + 1e-12)
    assert np.allclose(w.y1[a], w.py[bed, 0]) and np.allclose(w.y0[b], w.py[bed, 0])
