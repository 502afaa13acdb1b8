"""The back ends by name: the default is what the docs say, the names are few and unique, no import cycle."""

from __future__ import annotations

import ast
import dataclasses
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


def test_names_are_the_registrys_and_aliases_refused() -> None:
    assert tuple(registry._SOLVERS) == micro.SOLVERS and micro.SOLVERS[0] == micro.DEFAULT_SOLVER
    assert not set(micro.SOLVERS) & set(registry.EXPERIMENTS)
    lp = micro.assemble(three_storey_wall())
    for alias in ("highs", "cvxpy-clarabel", "ipm"):
        with pytest.raises(ValueError, match=f"solver must be one of {', '.join(micro.SOLVERS)}; got '{alias}'"):
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


def test_a_back_end_module_is_imported_when_chosen() -> None:
    """Importing the package imports no one-shot back end's module; making one imports its module."""
    import subprocess
    import sys

    code = ("import sys, micro; lazy = ('micro.backends.cvxpy_', 'micro.backends.normal_ipm', "
            "'micro.backends.clarabel_kinematic'); print(sorted(m for m in lazy if m in sys.modules)); "
            "micro.make_backend(micro.assemble(micro.build_wall(length=2.0, block_length=1.0, block_height=0.5, "
            "rows=(2,), thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=0.6)), 'normal-ipm'); "
            "print('micro.backends.normal_ipm' in sys.modules, 'cvxpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split("\n")
    assert out[:2] == ["[]", "True False"]


@pytest.mark.parametrize("solver", ["cvxpy", "cvxpy-highs"])
def test_without_cvxpy_its_back_ends_say_which_extra_to_install(solver: str,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """cvxpy is an optional extra: without it (simulated: an import of it fails) the back end is refused
    in one line naming the extra, and the others still run."""
    import sys

    from micro.backends.cvxpy_ import CvxpyBackend

    monkeypatch.setitem(sys.modules, "cvxpy", None)
    lp = micro.assemble(three_storey_wall())
    message = r"^solver '" + solver + r"' needs cvxpy: pip install 'xcheck-masonry\[cvxpy\]'$"
    assert registry.missing_extra(solver) and not registry.missing_extra("clarabel")
    with pytest.raises(ValueError, match=message):
        micro.make_backend(lp, solver)
    with pytest.raises(ModuleNotFoundError, match=r"^the cvxpy back end needs cvxpy: pip install"):
        CvxpyBackend(lp)
    assert micro.solve_associative(three_storey_wall(), solver="highs-ipm").ok


def test_the_cli_refuses_the_cvxpy_back_end_without_cvxpy_in_one_line(monkeypatch: pytest.MonkeyPatch,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    import sys

    from comparison.cli import main

    monkeypatch.setitem(sys.modules, "cvxpy", None)
    code = main(["micro", "--t", "1", "--m", "1", "--rows", "3", "--f", "0.6", "--solver", "cvxpy"])
    err = capsys.readouterr().err
    assert code == 2 and err == "xcheck: error: solver 'cvxpy' needs cvxpy: pip install 'xcheck-masonry[cvxpy]'\n"


def test_the_report_runs_the_cvxpy_back_end_where_it_is_installed(monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    from comparison.report.plan import build_plan

    assert build_plan(quick=True).solvers == micro.SOLVERS  # every back end of the registry, cvxpy included
    monkeypatch.setitem(sys.modules, "cvxpy", None)
    assert build_plan(quick=True).solvers == tuple(s for s in micro.SOLVERS if s != "cvxpy")


def test_the_full_report_times_what_the_registry_says(monkeypatch: pytest.MonkeyPatch) -> None:
    """A back end is its module and its registry entry: the report reads which back ends it times from the
    registry (here a new one, registered for the test), never a list of its own."""
    from comparison.report.plan import build_plan

    entry = registry._SOLVERS["normal-ipm"]
    monkeypatch.setitem(registry._SOLVERS, "new-one", entry)
    monkeypatch.setitem(registry._SOLVERS, "quick-one", dataclasses.replace(entry, timed="quick"))
    full, quick = build_plan().solvers, build_plan(quick=True).solvers
    assert "new-one" in full and "new-one" in quick and "quick-one" in quick and "quick-one" not in full
    assert "highs-simplex" in quick and "highs-simplex" not in full
