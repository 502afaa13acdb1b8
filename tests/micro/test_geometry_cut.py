"""Builder: walls of any length with cut ends (``ends="cut"``), and bit-identity of the whole-half-block walls."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from wall_fingerprints import fingerprint, whole_wall_cases

import micro
from micro.geometry import BASE, BED, HEAD
from micro.memory import estimate_bytes


def cut_wall(length: float, rows: tuple[int, ...] = (2,), **kw: object) -> micro.BlockWall:
    args: dict[str, object] = dict(length=length, block_length=3.0, block_height=1.0, rows=rows,
                                   thickness=(1.0,) * len(rows), overload=(0.0,) * len(rows), unit_weight=1.0,
                                   friction=0.6, ends="cut")
    args.update(kw)
    return micro.build_wall(**args)  # type: ignore[arg-type]


def test_whole_half_block_walls_are_bit_identical_to_the_builder_before_cut_ends() -> None:
    """Same blocks, same order, same contacts, same bytes: 514 walls, among
    them every paper wall but Set 8, both bonds (fingerprints saved from the
    builder that refused cut walls; see ``wall_fingerprints.py``)."""
    saved = json.loads((Path(__file__).parent / "whole_walls.json").read_text())
    built = {key: fingerprint(micro.build_wall(**kw)) for key, kw in whole_wall_cases()}
    assert len(built) == len(saved) == 514
    assert [k for k in saved if built[k] != saved[k]] == []


def test_set8_layout_by_hand() -> None:
    # Set 8: L = 20, l = 3: 13.33 half blocks. Full-start course: six blocks
    # and a 2-long cut block; half-start course: a half block, five blocks, a
    # full block and a 0.5-long cut block.
    w = cut_wall(20.0)
    c0, c1 = w.course == 0, w.course == 1
    assert np.array_equal(w.x0[c0], [0, 3, 6, 9, 12, 15, 18]) and np.array_equal(w.x1[c0], [3, 6, 9, 12, 15, 18, 20])
    assert np.array_equal(w.x0[c1], [0, 1.5, 4.5, 7.5, 10.5, 13.5, 16.5, 19.5])
    assert np.array_equal(w.x1[c1], [1.5, 4.5, 7.5, 10.5, 13.5, 16.5, 19.5, 20])
    bed = w.contact_kind == BED
    assert np.array_equal(w.px[bed][-2:], [[18.0, 19.5], [19.5, 20.0]])
    assert list(zip(w.contact_a[bed][-2:], w.contact_b[bed][-2:], strict=True)) == [(6, 13), (6, 14)]
    assert not w.mirror_symmetric


def test_paper_set8_builds() -> None:
    from comparison.domain.cases import case

    w = case("8").spec().to_micro(ends="cut")
    assert w.n_blocks == 30 * 7 + 30 * 8
    assert w.total_weight == pytest.approx(20.0 * 60.0, rel=1e-14)


@settings(max_examples=60, deadline=None)
@given(
    half_blocks=st.floats(1.0, 14.0, allow_nan=False),
    rows=st.lists(st.integers(1, 4), min_size=1, max_size=3),
    first=st.sampled_from(["full", "half"]),
    heads=st.sampled_from(["frictional", "frictionless"]),
)
def test_cut_layout_invariants(half_blocks: float, rows: list[int], first: str, heads: str) -> None:
    thick = tuple(0.5 + 0.25 * i for i in range(len(rows)))
    w = micro.build_wall(length=1.5 * half_blocks, block_length=3.0, block_height=0.5, rows=tuple(rows),
                         thickness=thick, overload=(0.0,) * len(rows), unit_weight=2.0, friction=0.5,
                         first_course=first, head_joints=heads, ends="cut")  # type: ignore[arg-type]
    L, lengths = w.length, w.block_lengths
    assert np.all(lengths > 0.0)
    for c in range(w.n_courses):
        sel = np.flatnonzero(w.course == c)
        # the course runs from 0 to exactly L; only its last block may be cut
        assert w.x0[sel[0]] == 0.0 and w.x1[sel[-1]] == pytest.approx(L, rel=1e-9)  # exact unless whole
        assert np.array_equal(w.x0[sel[1:]], w.x1[sel[:-1]])
        assert np.all(np.isin(lengths[sel[:-1]], [1.5, 3.0]))
        assert np.all(lengths[sel[1:-1]] == 3.0)
        assert lengths[sel[-1]] <= 3.0
    # weight: gamma * L * b * thickness per course, exactly up to rounding
    first_blocks = np.searchsorted(w.course, np.arange(w.n_courses))
    t_course = np.asarray(thick)[w.storey[first_blocks] - 1]
    assert w.total_weight == pytest.approx(2.0 * L * 0.5 * float(np.sum(t_course)), rel=1e-13)
    # every bed-joint overlap has positive length, lies on both blocks, and they tile each bed line
    bed = w.contact_kind == BED
    a, b = w.contact_a[bed], w.contact_b[bed]
    assert np.all(w.px[bed, 1] > w.px[bed, 0])
    for blk in (a, b):
        assert np.all(w.x0[blk] <= w.px[bed, 0]) and np.all(w.px[bed, 1] <= w.x1[blk])
    assert np.sum(w.px[bed, 1] - w.px[bed, 0]) == pytest.approx(L * (w.n_courses - 1), rel=1e-13)
    assert np.array_equal(w.course[b], w.course[a] + 1)
    # head joints: one per pair of neighbours in a course, at the left block's end
    head = w.contact_kind == HEAD
    assert np.count_nonzero(head) == w.n_blocks - w.n_courses
    assert np.array_equal(w.px[head, 0], w.x1[w.contact_a[head]])
    assert np.array_equal(w.contact_b[head], w.contact_a[head] + 1)
    assert np.all(w.mu[head] == (0.0 if heads == "frictionless" else 0.5))
    base = w.contact_kind == BASE
    assert np.sum(w.px[base, 1] - w.px[base, 0]) == pytest.approx(L)
    # the memory guard counts exactly the blocks that are built
    micro.build_wall(length=1.5 * half_blocks, block_length=3.0, block_height=0.5, rows=tuple(rows),
                     thickness=thick, overload=(0.0,) * len(rows), unit_weight=2.0, friction=0.5,
                     first_course=first, ends="cut", max_bytes=estimate_bytes(w.n_blocks))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="too large"):
        micro.build_wall(length=1.5 * half_blocks, block_length=3.0, block_height=0.5, rows=tuple(rows),
                         thickness=thick, overload=(0.0,) * len(rows), unit_weight=2.0, friction=0.5,
                         first_course=first, ends="cut",
                         max_bytes=estimate_bytes(w.n_blocks) - 1)  # type: ignore[arg-type]


def test_loads_of_a_cut_wall() -> None:
    w = micro.build_wall(length=10.0, block_length=3.0, block_height=0.5, rows=(2, 3), thickness=(0.25, 0.5),
                         overload=(4.0, 6.0), unit_weight=18.0, friction=0.6, ends="cut")
    weight = 18.0 * 10.0 * 0.5 * (3 * 0.5 + 2 * 0.25)
    assert w.total_weight == pytest.approx(weight, rel=1e-14)
    assert w.total_dead_load == pytest.approx(weight + 6.0 * 10.0 + 4.0 * 10.0, rel=1e-14)
    assert np.sum(w.live[:, 0]) == pytest.approx(w.total_dead_load, rel=1e-14)
    end = w.x1 == 10.0  # the cut blocks carry their own length's weight
    assert np.allclose(-w.dead[end & (w.course == 0), 1], 18.0 * (w.x1 - w.x0)[end & (w.course == 0)] * 0.5 * 0.5)


@pytest.mark.parametrize("length", [20.0, 10.0, 7.3, 4.4, 2.0])
@pytest.mark.parametrize("first", ["full", "half"])
def test_dead_load_equilibrium_is_feasible(length: float, first: str) -> None:
    """The wall stands under its own weight: the feasible load factors
    contain 0 in both directions (HiGHS dual simplex, re-checked)."""
    w = cut_wall(length, rows=(4, 3), first_course=first)
    r = micro.solve_associative(w, solver="highs-simplex", directions="both")
    assert r.ok, r.message
    assert all(d.load_factor > 0.0 for d in r.directions)


def test_mirror_symmetry_of_cut_walls() -> None:
    assert cut_wall(12.0).mirror_symmetric  # 8 half blocks: whole and even
    assert not cut_wall(10.5).mirror_symmetric  # 7 half blocks: whole and odd
    assert not cut_wall(12.3).mirror_symmetric  # cut
    assert not cut_wall(2.0).mirror_symmetric  # [0, 2] under [0, 1.5] [1.5, 2]
    assert cut_wall(2.0, rows=(1,)).mirror_symmetric  # one block
    # a cut wall solved in both directions: +x and -x differ
    r = micro.solve_associative(cut_wall(12.3, rows=(4,)), solver="highs-simplex")
    lam = {d.direction: d.load_factor for d in r.directions}
    assert set(lam) == {"+x", "-x"} and not math.isclose(lam["+x"], lam["-x"], rel_tol=1e-6)


def test_a_length_within_tolerance_of_whole_is_whole() -> None:
    a, b = cut_wall(12.0), cut_wall(12.0 * (1 + 1e-12))
    assert np.array_equal(a.x1, b.x1) and a.mirror_symmetric and b.mirror_symmetric
    c = cut_wall(12.0 + 1e-6)  # a genuine sliver of 1e-6
    assert c.n_blocks == a.n_blocks + 1 and c.block_lengths.min() == pytest.approx(1e-6)


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"length": 1.4}, "length must be at least half a block (block_length/2 = 1.5), got 1.4"),
        ({"length": -1.0}, "length must be a positive number, got -1.0"),
        ({"length": "abc"}, "length must be a positive number, got 'abc'"),
        ({"length": True}, "length must be a positive number, got True"),
        ({"block_height": float("inf")}, "block_height must be a positive number, got inf"),
        ({"rows": (2, 0)}, "rows[1] must be a positive integer, got 0"),
        ({"rows": (2.5,)}, "rows[0] must be a positive integer, got 2.5"),
        ({"rows": (float("nan"),)}, "rows[0] must be a positive integer, got nan"),
        ({"rows": (float("inf"),)}, "rows[0] must be a positive integer, got inf"),
        ({"thickness": (0.0, 1.0)}, "thickness[0] must be a positive number, got 0.0"),
        ({"overload": (0.0, -2.0)}, "overload[1] must be zero or a positive number, got -2.0"),
    ],
)
def test_messages(kw: dict[str, object], message: str) -> None:
    base: dict[str, object] = {"length": 10.0, "rows": (2, 2), "thickness": (1.0, 1.0), "overload": (0.0, 0.0)}
    base.update(kw)
    with pytest.raises(ValueError) as err:
        cut_wall(**base)  # type: ignore[arg-type]
    assert str(err.value) == message


def test_a_wall_says_whether_its_end_blocks_are_cut() -> None:
    kw = {"block_length": 3.0, "block_height": 1.0, "rows": (4,), "thickness": (1.0,), "overload": (0.0,),
          "unit_weight": 1.0, "friction": 0.6, "ends": "cut"}
    cut = micro.build_wall(length=20.0, **kw)  # Set 8's 13.33 half blocks
    assert cut.end_blocks_cut and cut.half_blocks == pytest.approx(40 / 3)
    whole = micro.build_wall(length=21.0, **kw)
    assert not whole.end_blocks_cut and whole.half_blocks == 14.0
    near = micro.build_wall(length=21.0 * (1 + 1e-12), **kw)  # within WHOLE_TOLERANCE: whole
    assert not near.end_blocks_cut
