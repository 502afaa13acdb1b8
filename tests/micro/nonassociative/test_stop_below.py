"""``stop_below``: the search stops at the first certified state below a target (what ``xcheck compare`` needs
to refute a macro λ), and says so; without a target, or with one below every state, nothing changes."""

from __future__ import annotations

import math

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative.final_checks import verify_collapse_state

#: Table 7's Set 13 (78 blocks): iterated LP 0.4912758 (certified), lowest certified state 0.4894591.
SET13 = WallSpec.from_paper(t=1, m=1 / 2, rows=12, f=0.75)
#: 11 rows of m = 1/2 (66 blocks): not mirror-symmetric, both directions solved.
LOPSIDED = WallSpec.from_paper(t=1, m=1 / 2, rows=11, f=0.6)


@pytest.fixture(scope="module")
def set13_full() -> micro.NonAssociativeResult:
    return micro.solve_nonassociative(SET13.to_micro())


@pytest.mark.parametrize("bad", ["0.5", math.nan, math.inf, True])
def test_stop_below_must_be_a_finite_number(bad: object) -> None:
    with pytest.raises(ValueError, match="stop_below"):
        micro.NonAssociativeOptions(stop_below=bad)  # type: ignore[arg-type]


def test_above_the_iterated_state_no_descent_lp_runs(set13_full: micro.NonAssociativeResult) -> None:
    r = micro.solve_nonassociative(SET13.to_micro(), stop_below=0.4914)
    (low,) = r.lowest
    assert (low.stop, low.lps, low.origin) == ("target", 0, "iterated")
    assert r.load_factor == r.iterated_load_factor == set13_full.iterated_load_factor
    assert r.to_record().lowest_stop == "target"
    residuals = verify_collapse_state(micro.assemble(SET13.to_micro()), low.state)  # type: ignore[arg-type]
    assert max(v for k, v in residuals.items() if k != "slipping_points") < 1e-6


def test_between_the_states_the_descent_stops_at_the_first_below(set13_full: micro.NonAssociativeResult) -> None:
    target = 0.4900  # between the lowest state (0.48946) and the iterated LP's (0.49128)
    r = micro.solve_nonassociative(SET13.to_micro(), stop_below=target)
    (low,) = r.lowest
    assert low.stop == "target" and low.load_factor < target
    assert low.lps <= set13_full.lowest[0].lps
    assert math.isnan(low.band[1]) if low.band is not None else False  # no LP for the band's upper end


def test_below_every_state_the_search_is_the_whole_one(set13_full: micro.NonAssociativeResult) -> None:
    r = micro.solve_nonassociative(SET13.to_micro(), stop_below=0.3)
    assert r.load_factor == set13_full.load_factor and r.lowest[0].stop == set13_full.lowest[0].stop == "finished"
    assert r.lowest[0].lps == set13_full.lowest[0].lps


def test_the_other_direction_is_skipped_once_one_is_below() -> None:
    wall = LOPSIDED.to_micro()
    assert not wall.mirror_symmetric
    both = micro.solve_nonassociative(wall)
    assert [d.direction for d in both.directions] == ["+x", "-x"]
    first = micro.solve_nonassociative(wall, stop_below=1.0)
    assert [d.direction for d in first.directions] == ["+x"] and first.status == "converged"
    assert [(low.direction, low.stop) for low in first.lowest] == [("+x", "target")]
