"""The wall's own mechanism where a local one governs (``comparison.domain.wall_mechanism.solve_wall_mechanism``).

The grid walls whose top course ends with a thin cut piece (t = 3/2, m = 1/2, 8 rows: a 1/3-wide piece;
t = 1, m = 1/3, 8 rows: 1/2) govern the block model by that piece alone; the paper's walls of Table 7
(Sets 12-14) do not.
"""

from __future__ import annotations

import functools
import math

import pytest

import micro
from comparison.domain.cases import case
from comparison.domain.wall import WallSpec
from comparison.domain.wall_mechanism import FAILED, LOCAL_LEFT, WALL, solve_wall_mechanism

SOLVES = {"associative": micro.solve_associative,
          "nonassociative": functools.partial(micro.solve_nonassociative, lowest=True)}


@pytest.mark.parametrize("method", sorted(SOLVES))
@pytest.mark.parametrize("t, m, width", [(1.5, 0.5, 1 / 3), (1.0, 1 / 3, 0.5)])
def test_local_piece_then_the_walls_own(method: str, t: float, m: float, width: float) -> None:
    """Local: one block, the top course's cut end piece (non-associative: at lambda = w/b); the wall's own
    mechanism holds that block, is higher, and is not local; its load factor is the held result's."""
    wall = WallSpec.from_paper(t=t, m=m, rows=8, f=0.65).to_micro()
    wm = solve_wall_mechanism(wall, SOLVES[method])
    assert wm.local is not None
    assert wm.local.blocks == (wall.n_blocks - 1,)
    if method == "nonassociative":
        assert wm.local_load_factor == pytest.approx(width, rel=1e-7)
    assert wm.status == WALL and wm.rounds == 1 and wm.held == wm.local.blocks
    assert wm.result is not wm.result_local
    assert wm.load_factor > wm.local_load_factor + 0.01
    assert micro.local_mechanism(wm.held_wall.wall, wm.result) is None
    d = wm.to_dict()
    assert d["wall_load_factor"] == wm.load_factor
    assert d["local_mechanism"]["description"].startswith("the cut end piece of course 8 (right end")


@pytest.mark.parametrize("method", sorted(SOLVES))
@pytest.mark.parametrize("name", ["12", "13", "14"])
def test_paper_walls_are_not_local(method: str, name: str) -> None:
    """Sets 12-14 (Table 7) collapse as walls: nothing local, no held analysis, the wall's own value is the
    block model's value to quote."""
    wall = case(name).spec().to_micro()
    calls = []

    def solve(w: micro.BlockWall) -> object:
        calls.append(w)
        return SOLVES[method](w)

    wm = solve_wall_mechanism(wall, solve)
    assert wm.local is None and len(calls) == 1 and wm.result is wm.result_local and wm.held == ()
    quoted = wm.result.load_factor
    assert wm.load_factor == quoted and math.isnan(wm.local_load_factor)
    assert wm.to_dict() == {"wall_load_factor": quoted, "local_mechanism": None}


def test_first_result_is_not_computed_again() -> None:
    """A result passed as ``first`` is used as the block model's: only the held wall is solved."""
    wall = WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65).to_micro()
    first = micro.solve_associative(wall)
    seen: list[int] = []

    def solve(w: micro.BlockWall) -> micro.LimitResult:
        seen.append(w.n_blocks)
        return micro.solve_associative(w)

    wm = solve_wall_mechanism(wall, solve, first=first)
    assert wm.result_local is first and seen == [wall.n_blocks - 1]


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2"])
def test_max_rounds_refused(bad: object) -> None:
    wall = WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65).to_micro()
    with pytest.raises(ValueError, match="max_rounds must be a positive integer"):
        solve_wall_mechanism(wall, micro.solve_associative, max_rounds=bad)  # type: ignore[arg-type]


def test_held_analysis_that_fails_says_so() -> None:
    """A held analysis that fails (here a time limit no solve can meet) gives status ``failed``, a NaN wall
    value and the reason, never the block model's value in its place."""
    wall = WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65).to_micro()
    first = micro.solve_associative(wall)
    wm = solve_wall_mechanism(wall, functools.partial(micro.solve_associative, time_limit=1e-9), first=first)
    assert wm.local is not None and wm.status == FAILED and math.isnan(wm.load_factor)
    assert wm.message.startswith("the analysis of the held wall failed: time_limit")
    assert wm.to_dict()["wall_load_factor"] is None


def test_rounds_are_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    """When every held wall's mechanism is local again, the loop stops after ``max_rounds`` held analyses
    with status ``local after the last round`` and no wall value (the detection is forced local here)."""
    import comparison.domain.wall_mechanism as local

    wall = WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65).to_micro()

    def always_local(w: micro.BlockWall, result: object) -> micro.LocalMechanism:
        top = w.n_blocks - 1
        return micro.LocalMechanism((top,), 0.001, 0.3, "+x", f"block {top} tips over alone")

    monkeypatch.setattr(local, "local_mechanism", always_local)
    wm = solve_wall_mechanism(wall, micro.solve_associative, max_rounds=2)
    assert wm.status == LOCAL_LEFT and wm.rounds == 2 and math.isnan(wm.load_factor)
    assert len(wm.held) == 2 and wm.message.startswith("the held wall's mechanism is still local after 2 rounds")


def test_record_keeps_the_local_mechanism() -> None:
    """The runner's record of a local wall carries the local mechanism and the wall's own value, through
    its JSON form (the cache) unchanged; ``wall_load_factor`` is the held analysis', ``load_factor`` the
    block model's."""
    from comparison.runner import MICRO_NONASSOC, Record
    from comparison.runner.runner import compute

    spec = WallSpec.from_paper(t=1.5, m=0.5, rows=8, f=0.65)
    rec, _ = compute(spec, MICRO_NONASSOC)
    assert rec.local is not None
    assert rec.load_factor == pytest.approx(1 / 3, rel=1e-7) == rec.local.load_factor
    assert rec.wall_load_factor == rec.local.wall_load_factor > rec.load_factor + 0.01
    back = Record.from_dict(rec.to_dict())
    assert back.local == rec.local and back.wall_load_factor == rec.wall_load_factor
    plain, _ = compute(case("13").spec(), MICRO_NONASSOC)
    assert plain.local is None and plain.wall_load_factor == plain.load_factor
    assert Record.from_dict(plain.to_dict()).local is None
