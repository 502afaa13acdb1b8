"""The iterated LP's default runs on Table 7's walls, solved once per pytest run and read by the tests of
several files (the sequence, the certificate, the descent): each reads the same result object, which the
results' immutability keeps as solved."""

from __future__ import annotations

from collections.abc import Callable

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.backends.base import Outcome, Status
from micro.nonassociative import solve_nonassociative

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey, 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


@pytest.fixture(scope="session")
def table7_default() -> list[micro.NonAssociativeResult]:
    """``solve_nonassociative`` with no options on Sets 11-14, in :data:`TABLE7`'s order."""
    return [solve_nonassociative(WallSpec.from_paper(t=t, m=m, rows=12, f=0.75, p=0, storeys=1).to_micro())
            for t, m, _ in TABLE7]  # fmt: skip


def _failing_solver(status: Status, seconds: float = 0.0, calls: list[int] | None = None) -> type:
    """A stand-in for an interior-point role (``InteriorLP``, ``InteriorLPRetry``): built with any
    arguments, its every solve ends with ``status`` after ``seconds``, each direction asked appended to
    ``calls``."""

    class Failing:
        def __init__(self, *args: object, **kwargs: object) -> None:
            pass

        def solve(self, direction: int) -> Outcome:
            if calls is not None:
                calls.append(direction)
            return Outcome(status, "forced by the test", seconds=seconds)

    return Failing


@pytest.fixture
def failing_solver() -> Callable[..., type]:
    """:func:`_failing_solver`, for the tests that make a solver role fail."""
    return _failing_solver
