"""No micro result pairs a success status with a load factor that is not a finite number; options are checked."""

from __future__ import annotations

import math

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.limit_result import DirectionResult, LimitResult
from micro.records import AssociativeRecord

WALL = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75).to_micro()


@pytest.mark.parametrize("bad", [-1, 0, math.nan, math.inf, "soon", True])
def test_solve_associative_checks_its_time_limit(bad: object) -> None:
    with pytest.raises(ValueError, match="time_limit must be a positive number of seconds"):
        micro.solve_associative(WALL, time_limit=bad)  # type: ignore[arg-type]


@pytest.mark.parametrize("lam", [math.nan, math.inf, -0.5])
@pytest.mark.parametrize("status", ["optimal", "converged"])
def test_a_success_status_needs_a_finite_load_factor(status: str, lam: float) -> None:
    with pytest.raises(ValueError, match="needs a finite load factor"):
        DirectionResult(direction="+x", status=status, load_factor=lam, iterations=1, seconds=0.0)


def test_every_result_type_holds_the_invariant() -> None:
    import dataclasses

    good = micro.solve_associative(WALL)
    assert good.ok
    for make in (
        lambda: dataclasses.replace(good, load_factor=math.nan),
        lambda: dataclasses.replace(good.to_record(), load_factor=math.inf),
        lambda: AssociativeRecord.from_dict(good.to_record().to_dict() | {"load_factor": None}),
    ):
        with pytest.raises(ValueError, match="needs a finite load factor"):
            make()
    failed = dataclasses.replace(good, status="inaccurate", load_factor=math.nan)
    assert isinstance(failed, LimitResult) and not failed.ok  # a failure may carry NaN


def test_the_non_associative_result_holds_it_too() -> None:
    import dataclasses

    result = micro.solve_nonassociative(WallSpec.from_paper(t=1, m=1 / 3, rows=6, f=0.75).to_micro())
    assert result.ok
    with pytest.raises(ValueError, match="needs a finite load factor"):
        dataclasses.replace(result, iterated_load_factor=math.nan)
    record = result.to_record()
    for name in ("load_factor", "iterated_load_factor"):  # the value to quote and the iterated LP's
        with pytest.raises(ValueError, match="needs a finite load factor"):
            dataclasses.replace(record, **{name: math.nan})
