"""The back ends by name: the default is what the docs say, the names are few and unique, no import cycle."""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path

import pytest
from micro_walls import three_storey_wall

import micro
from micro.backends import registry

ROOT = Path(__file__).resolve().parents[3]


def test_the_default_is_the_one_the_docs_name() -> None:
    docs = (ROOT / "docs" / "micro" / "associative.md").read_text()
    named = re.findall(r"default back end \(`micro.DEFAULT_SOLVER`\) is `([a-z-]+)`", docs)
    assert named == [micro.DEFAULT_SOLVER] == ["normal-ipm"]
    assert inspect.signature(micro.solve_associative).parameters["solver"].default == micro.DEFAULT_SOLVER
    assert inspect.signature(micro.make_backend).parameters["solver"].default == micro.DEFAULT_SOLVER


def test_solve_associative_without_a_solver_runs_the_default() -> None:
    r = micro.solve_associative(three_storey_wall())
    assert r.ok and r.solver == micro.DEFAULT_SOLVER


def test_names_are_few_and_aliases_refused() -> None:
    assert micro.SOLVERS == ("normal-ipm", "clarabel", "highs-ipm", "highs-simplex", "cvxpy")
    assert not set(micro.SOLVERS) & set(registry.EXPERIMENTS)
    lp = micro.assemble(three_storey_wall())
    for alias in ("highs", "cvxpy-clarabel", "ipm"):
        with pytest.raises(ValueError, match=f"solver must be one of normal-ipm, clarabel.*got '{alias}'"):
            micro.make_backend(lp, alias)


@pytest.mark.parametrize("solver", [*micro.SOLVERS, *registry.EXPERIMENTS])
def test_every_back_end_has_its_status_map_and_name(solver: str) -> None:
    be = micro.make_backend(micro.assemble(three_storey_wall()), solver)
    status_map = type(be).STATUS_MAP  # type: ignore[attr-defined]
    assert status_map and all(isinstance(v, micro.Status) for v in status_map.values())
    assert be.name == solver  # the name a result carries is the one asked for


def _imports(path: Path) -> set[str]:
    mods: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module:
            mods.add(node.module)
        elif isinstance(node, ast.Import):
            mods.update(a.name for a in node.names)
    return mods


def test_base_imports_no_back_end() -> None:
    """The registry imports the back ends, which import base; base imports none of them (no cycle)."""
    mods = _imports(ROOT / "micro" / "backends" / "base.py")
    assert not {m for m in mods if m.startswith("micro.backends")}


#: Public classes that still share a name, and where that is being mended (none).
SHARED_NAMES_KNOWN: dict[str, str] = {}


def test_no_two_public_classes_share_a_name() -> None:
    where: dict[str, list[str]] = {}
    for package in ("macro", "micro", "comparison"):
        for path in sorted((ROOT / package).rglob("*.py")):
            for node in ast.parse(path.read_text()).body:
                if isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                    where.setdefault(node.name, []).append(str(path.relative_to(ROOT)))
    shared = {name: paths for name, paths in where.items() if len(paths) > 1 and name not in SHARED_NAMES_KNOWN}
    assert not shared
