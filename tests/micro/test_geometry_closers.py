"""Builder: the default end treatment ``ends="closers"`` (docs/micro/walls.md, "How a course ends").

Every joint stays at its running-bond position (every lap half a block); a remainder narrower than the closer
width ``min(mu b, l/4)`` is not laid alone but taken up by a long last unit; whole walls are the walls of
``ends="cut"``; and the load factor does not jump at a whole length.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import micro
from comparison.domain.wall import WallSpec
from micro.courses import closer_width


def wall(length: float, ends: str = "closers", **kw: object) -> micro.BlockWall:
    args: dict[str, object] = dict(length=length, block_length=3.0, block_height=1.0, rows=(2,), thickness=(1.0,),
                                   overload=(0.0,), unit_weight=1.0, friction=0.6, ends=ends)
    args.update(kw)
    return micro.build_wall(**args)  # type: ignore[arg-type]


def courses(w: micro.BlockWall) -> list[list[float]]:
    return [[float(x) for x in w.block_lengths[w.course == c]] for c in range(w.n_courses)]


def test_closer_width_is_mu_b_capped_at_a_quarter_block() -> None:
    assert closer_width(3.0, 1.0, 0.6) == pytest.approx(0.6)
    assert closer_width(1.0, 1.0, 0.6) == pytest.approx(0.25)  # square blocks: the cap
    assert closer_width(3.0, 1.0, 0.75) == pytest.approx(0.75)  # mu b = l/4 exactly


@pytest.mark.parametrize("w_over_b", [0.2, 0.6, 0.75])
def test_a_closer_mu_b_wide_tips_alone_at_mu_under_both_flow_rules(w_over_b: float) -> None:
    """The closed forms of a piece that carries nothing (micro.local_mechanisms): non-associative ``w/b``, associative
    ``(w/b)(1 + mu^2)/(1 - mu^2 + 2 mu w/b)``; at ``w = mu b`` both are ``mu``, the wall's base-sliding load."""
    mu = w_over_b
    assoc = w_over_b * (1 + mu**2) / (1 - mu**2 + 2 * mu * w_over_b)
    assert assoc == pytest.approx(mu, rel=1e-14) and w_over_b == pytest.approx(mu)


def test_set8_layout_by_hand() -> None:
    """Set 8: L = 20, l = 3, b = 1, mu = 0.6: 13.33 half blocks. The half-start courses would end in a 0.5-long
    sliver, narrower than the closer width 0.6: their last unit runs to the end, 3.5 long. The full-start
    courses end in a 2-long closer, as with cut ends."""
    w = wall(20.0)
    assert courses(w) == [[3.0] * 6 + [2.0], [1.5] + [3.0] * 5 + [3.5]]
    assert courses(wall(20.0, ends="cut")) == [[3.0] * 6 + [2.0], [1.5] + [3.0] * 6 + [0.5]]


def test_a_remainder_as_wide_as_the_closer_is_laid() -> None:
    # 20.1: the half-start courses' remainder is 0.6 = mu b: a closer, laid as with cut ends
    assert courses(wall(20.1)) == courses(wall(20.1, ends="cut"))
    assert min(courses(wall(20.1))[1]) == pytest.approx(0.6)
    assert courses(wall(20.09))[1][-1] == pytest.approx(3.59)


@settings(max_examples=80, deadline=None)
@example(half_blocks=1.4, rows=[1], first="half", mu=0.6, height=1.0)  # a remainder of 0.6 - 4e-16: a closer
@given(
    half_blocks=st.floats(1.0, 14.0, allow_nan=False),
    rows=st.lists(st.integers(1, 4), min_size=1, max_size=3),
    first=st.sampled_from(["full", "half"]),
    mu=st.sampled_from([0.3, 0.6, 0.75, 1.0]),
    height=st.sampled_from([0.5, 1.0, 3.0]),
)
def test_closer_invariants(half_blocks: float, rows: list[int], first: str, mu: float, height: float) -> None:
    """Every joint at a running-bond position; no piece but a course's first narrower than the closer
    width; no unit longer than a block plus the closer width; the same joints as the cut wall but the
    last one of a course whose remainder is narrower than the closer width."""
    lb, half = 3.0, 1.5
    kw = dict(length=half * half_blocks, block_length=lb, block_height=height, rows=tuple(rows),
              thickness=(1.0,) * len(rows), overload=(0.0,) * len(rows), unit_weight=1.0, friction=mu,
              first_course=first)
    w = micro.build_wall(**kw, ends="closers")  # type: ignore[arg-type]
    c = micro.build_wall(**kw, ends="cut")  # type: ignore[arg-type]
    wmin = closer_width(lb, height, mu)
    tol = 1e-9 * w.length
    for k in range(w.n_courses):
        x0, x1 = w.x0[w.course == k], w.x1[w.course == k]
        cx0 = c.x0[c.course == k]
        joints = x0[1:]
        assert np.allclose(joints / half, np.round(joints / half), rtol=0, atol=1e-9)  # laps of half a block
        assert x0[0] == 0.0 and x1[-1] == pytest.approx(w.length, rel=1e-9)  # exact unless whole within tolerance
        lengths = x1 - x0
        assert np.all(lengths[1:] >= wmin - tol) and np.all(lengths <= lb + wmin + tol)
        if c.block_lengths[c.course == k][-1] < wmin - tol and cx0.size > 1:  # a sliver: taken up by the unit before
            assert np.array_equal(joints, cx0[1:-1])
        else:
            assert np.array_equal(joints, cx0[1:])
    assert w.total_weight == pytest.approx(c.total_weight, rel=1e-13)


def test_whole_walls_are_the_same_with_either_end_treatment() -> None:
    for length in (3.0, 12.0, 10.5, 21.0):
        a, b = wall(length), wall(length, ends="cut")
        assert np.array_equal(a.x0, b.x0) and np.array_equal(a.x1, b.x1) and a.ends == "closers"


def test_ends_is_checked() -> None:
    with pytest.raises(ValueError, match="ends must be 'closers' or 'cut', got 'sliver'"):
        wall(20.0, ends="sliver")


# The pairs (a wall a few per cent off a whole length, and the whole one): (rows, storeys, m, f, t, t whole).
PAIRS = [
    (10, 1, 0.4, 0.6, 1.3, 4 / 3),
    (10, 1, 0.4, 0.6, 1.36, 4 / 3),
    (24, 2, 1 / 3, 0.65, 1.1, 16 / 15),
    (12, 1, 1 / 3, 0.75, 0.97, 1.0),
    (12, 1, 1.0, 0.6, 1.03, 1.0),
    (8, 1, 0.5, 0.65, 1.55, 1.6),
]


@pytest.mark.parametrize(("rows", "storeys", "m", "f", "t", "t_whole"), PAIRS)
def test_the_load_factor_does_not_jump_at_a_whole_length(rows: int, storeys: int, m: float, f: float, t: float,
                                                         t_whole: float) -> None:
    """Within 10 % of the whole wall's, both flow rules; with cut ends the non-associative value falls far
    below on most of these (a sliver or the wedge over it collapses alone)."""
    near = WallSpec.from_paper(t=t, m=m, rows=rows, f=f, storeys=storeys).to_micro()
    whole = WallSpec.from_paper(t=t_whole, m=m, rows=rows, f=f, storeys=storeys).to_micro()
    assert near.end_blocks_cut and not whole.end_blocks_cut
    for solve in (micro.solve_associative, micro.solve_nonassociative):
        a, b = solve(near), solve(whole)
        assert a.ok and b.ok
        assert abs(a.load_factor - b.load_factor) <= 0.10 * b.load_factor, (solve.__name__, a.load_factor,
                                                                            b.load_factor)


def test_the_shared_wall_names_the_same_end_treatments() -> None:
    import comparison.domain.wall

    assert comparison.domain.wall.ENDS == micro.ENDS and micro.ENDS[0] == "closers"
    spec = WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65)
    assert spec.ends == "closers" and spec.to_micro().ends == "closers"
    assert WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65, ends="cut").to_micro().ends == "cut"
    assert spec.to_micro(ends="cut").ends == "cut"  # a builder option given to to_micro wins
    with pytest.raises(ValueError, match="ends must be one of closers, cut, got 'x'"):
        WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65, ends="x")
