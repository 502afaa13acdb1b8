"""The wall as built and, where a sliver's local mechanism governs it, the held wall
(``comparison.domain.wall_mechanism.solve_wall_mechanism``).

The grid walls of cut ends whose top course ends with a sliver (t = 3/2, m = 1/2, 8 rows: a 1/3-wide piece;
t = 1, m = 1/3, 8 rows: 1/2) are governed by that piece alone; the paper's walls of Table 7 (Sets 12-14)
and the same walls built with closers (the default) are not.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

import micro
from comparison.domain.cases import case
from comparison.domain.wall import WallSpec
from comparison.domain.wall_mechanism import FAILED, WALL, solve_wall_mechanism
from micro.local_mechanisms import slivers

SOLVES = {"associative": micro.solve_associative,
          "nonassociative": functools.partial(micro.solve_nonassociative, lowest=True)}


def cut(t: float, m: float) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=8, f=0.65, ends="cut").to_micro()


@pytest.mark.parametrize("method", sorted(SOLVES))
@pytest.mark.parametrize("t, m, width", [(1.5, 0.5, 1 / 3), (1.0, 1 / 3, 0.5)])
def test_local_piece_then_the_held_wall(method: str, t: float, m: float, width: float) -> None:
    """Local: the top course's cut end piece (non-associative: at lambda = w/b); the wall as built's value is
    that one; the held wall holds every sliver, is higher, and is not local."""
    wall = cut(t, m)
    wm = solve_wall_mechanism(wall, SOLVES[method])
    assert wm.local is not None
    assert wm.local.blocks == (wall.n_blocks - 1,) == wm.local.slivers
    assert wm.load_factor == wm.result.load_factor == wm.local.load_factor
    if method == "nonassociative":
        assert wm.load_factor == pytest.approx(width, rel=1e-7)
    assert wm.status == WALL and wm.held == tuple(int(b) for b in np.flatnonzero(slivers(wall)))
    assert wm.held_result is not None and wm.held_wall is not None
    assert wm.held_load_factor > wm.load_factor + 0.01
    assert micro.local_mechanism(wm.held_wall.wall, wm.held_result) is None
    d = wm.to_dict()
    assert d["held_load_factor"] == wm.held_load_factor
    assert d["local_mechanism"]["description"].startswith("the cut end piece of course 8 (right end")


@pytest.mark.parametrize("method", sorted(SOLVES))
def test_the_same_walls_with_closers_are_not_local(method: str) -> None:
    """Built with closers, the walls have no sliver: nothing local, one analysis."""
    for t, m in ((1.5, 0.5), (1.0, 1 / 3)):
        wall = WallSpec.from_paper(t=t, m=m, rows=8, f=0.65).to_micro()
        assert not np.any(slivers(wall))
        wm = solve_wall_mechanism(wall, SOLVES[method])
        assert wm.local is None and wm.held_result is None and math.isnan(wm.held_load_factor)


@pytest.mark.parametrize("method", sorted(SOLVES))
@pytest.mark.parametrize("name", ["12", "13", "14"])
def test_paper_walls_are_not_local(method: str, name: str) -> None:
    """Sets 12-14 (Table 7) collapse as walls: nothing local, no held analysis."""
    wall = case(name).spec().to_micro()
    calls = []

    def solve(w: micro.BlockWall) -> object:
        calls.append(w)
        return SOLVES[method](w)

    wm = solve_wall_mechanism(wall, solve)
    assert wm.local is None and len(calls) == 1 and wm.held_result is None and wm.held == ()
    assert wm.load_factor == wm.result.load_factor and math.isnan(wm.held_load_factor)
    assert wm.to_dict() == {"held_load_factor": None, "local_mechanism": None}


def test_first_result_is_not_computed_again() -> None:
    """A result passed as ``first`` is the wall as built's: only the held wall is solved."""
    wall = cut(1.5, 0.5)
    first = micro.solve_associative(wall)
    seen: list[int] = []

    def solve(w: micro.BlockWall) -> micro.LimitResult:
        seen.append(w.n_blocks)
        return micro.solve_associative(w)

    wm = solve_wall_mechanism(wall, solve, first=first)
    assert wm.result is first and seen == [wall.n_blocks - len(wm.held)]


def test_held_analysis_that_fails_says_so() -> None:
    """A held analysis that fails (here a time limit no solve can meet) gives status ``failed``, a NaN held value
    and the reason; the wall as built's value stays."""
    wall = cut(1.5, 0.5)
    first = micro.solve_associative(wall)
    wm = solve_wall_mechanism(wall, functools.partial(micro.solve_associative, time_limit=1e-9), first=first)
    assert wm.local is not None and wm.status == FAILED and math.isnan(wm.held_load_factor)
    assert wm.load_factor == first.load_factor
    assert wm.message.startswith("the analysis of the held wall failed: time_limit")
    assert wm.to_dict()["held_load_factor"] is None


def test_record_keeps_the_local_mechanism() -> None:
    """The runner's record of a local wall carries the local mechanism and the held wall's value, through its
    JSON form (the cache) unchanged; ``load_factor`` is the wall as built's."""
    from comparison.runner import MICRO_NONASSOC, Record
    from comparison.runner.runner import compute

    spec = WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65, ends="cut")
    rec, _ = compute(spec, MICRO_NONASSOC)
    assert rec.local is not None
    assert rec.load_factor == pytest.approx(1 / 3, rel=1e-7) == rec.local.load_factor
    assert rec.local.held_load_factor > rec.load_factor + 0.01
    back = Record.from_dict(rec.to_dict())
    assert back.local == rec.local
    plain, _ = compute(case("13").spec(), MICRO_NONASSOC)
    assert plain.local is None and Record.from_dict(plain.to_dict()).local is None
