"""The iterated LP and the descent reach HiGHS only through the back ends' persistent model.

Every HiGHS object a non-associative run creates is watched: it must be made, and each of its methods
called, by ``micro.backends.highs`` (or by highspy's own wrapper), never by ``micro.nonassociative``.
"""

from __future__ import annotations

import sys
from typing import Any

import highspy
import pytest

import micro
from comparison.wall import WallSpec


def test_the_non_associative_method_calls_highs_only_through_micro_backends(monkeypatch: pytest.MonkeyPatch) -> None:
    callers: set[str] = set()
    created: list[str] = []

    class Watched(highspy.Highs):  # type: ignore[misc]
        def __init__(self) -> None:
            created.append(sys._getframe(1).f_globals.get("__name__", "?"))
            super().__init__()

        def __getattribute__(self, name: str) -> Any:
            if not name.startswith("__"):
                callers.add(sys._getframe(1).f_globals.get("__name__", "?"))
            return super().__getattribute__(name)

    monkeypatch.setattr(highspy, "Highs", Watched)
    wall = WallSpec.from_paper(t=1, m=1, rows=6, f=0.75).to_micro()  # Table 7's Set 14 with 6 rows
    r = micro.solve_nonassociative(wall, lowest=True, directions="+x")
    assert r.converged and r.lowest and r.lowest[0].lps > 0  # the sequence and the descent both ran
    assert created and set(created) <= {"micro.backends.highs"}
    ours = {c for c in callers if not c.startswith("highspy")}  # highspy's own wrapper calls itself
    assert ours == {"micro.backends.highs"}, ours
