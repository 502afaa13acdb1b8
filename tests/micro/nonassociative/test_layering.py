"""The iterated LP and the descent reach their solvers only through ``micro.backends``.

Every HiGHS object a non-associative run creates is watched: it must be made, and each of its methods
called, by ``micro.backends.highs`` (or by highspy's own wrapper), never by ``micro.nonassociative``.
Every Clarabel solver it creates must be made by a module of ``micro.backends``. And no module of the
method imports a solver package at all (read from the source, so that a path the walls below do not
take, such as the proximal projection's Clarabel fallback, is held to the rule as well).
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path
from typing import Any

import clarabel
import highspy
import pytest

import micro
from comparison.domain.wall import WallSpec


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
    highs = {"micro.backends.highs", "micro.backends.highs_runs"}  # the model, and the quiet instance it is
    assert created and set(created) <= highs
    ours = {c for c in callers if not c.startswith("highspy")}  # highspy's own wrapper calls itself
    assert "micro.backends.highs" in ours and ours <= highs, ours


def test_the_non_associative_method_makes_clarabel_solvers_only_in_micro_backends(
        monkeypatch: pytest.MonkeyPatch) -> None:
    makers: list[str] = []
    real = clarabel.DefaultSolver

    def watched(*args: Any) -> Any:
        makers.append(sys._getframe(1).f_globals.get("__name__", "?"))
        return real(*args)

    monkeypatch.setattr(clarabel, "DefaultSolver", watched)
    wall = WallSpec.from_paper(t=1, m=1, rows=6, f=0.75).to_micro()
    r = micro.solve_nonassociative(wall, lowest=False, directions="+x")
    assert r.converged and makers  # the start and the certificate are Clarabel's
    assert {m.rsplit(".", 1)[0] for m in makers} == {"micro.backends"}, makers


#: The solver packages a module of the method may not import (``micro.backends`` wraps them).
SOLVER_PACKAGES = ("highspy", "clarabel", "cvxpy", "pyscipopt")


@pytest.mark.parametrize("package", ["micro/nonassociative"])
def test_no_module_of_the_method_imports_a_solver_package(package: str) -> None:
    root = Path(__file__).resolve().parents[3]
    offending = []
    for path in sorted((root / package).rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            offending += [f"{path.relative_to(root)}: {n}" for n in names if n.split(".")[0] in SOLVER_PACKAGES]
    assert not offending, offending
