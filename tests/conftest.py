"""The quick report, built once per pytest run and shared by every test that reads it.

Building ``xcheck report --quick`` computes about a hundred micro solves; the tests that read a quick
report (its cells against the golden values, its files, the command line's first run, the documentation's
``report --quick`` example, the Dask and reproducibility comparisons) read this one build instead of making
their own. It is built as a user builds it: by the command line, from an empty result cache, with the
committed tables of ``reports/``, verbose, its standard output and error kept for the tests of what the
command prints on a first run. Tests that run the report again (from the cache, on a cluster, without a
cache) start from a copy of its cache (:func:`quick_report_cache`) or compare their output with its files.

Likewise the sweep of the documentation's own-walls example (:func:`own_walls_sweep`), whose page the docs
quote and whose command the docs' examples run, and the tiny sweep (:func:`tiny_sweep`) that the sweep tests
read and the README's example runs: computed once, their caches seed the examples' cache.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

# pytest puts this folder (``tests/``) first on ``sys.path`` to import this file; its subfolders are named
# like the packages (``tests/comparison``, ``tests/micro``), so a process the tests start (a report's worker,
# spawned with the parent's ``sys.path``) found ``tests/comparison`` for ``comparison``
# ("No module named 'comparison.runner.executor'"): the repository goes before it.
_REPO = str(Path(__file__).resolve().parents[1])
if sys.path[0] != _REPO:
    sys.path.insert(0, _REPO)

from quick_report import OWN_WALLS, TINY, QuickReport, Sweep, build, sweep  # noqa: E402

#: ``pytester``: the pytest plugin's tests run a downstream project's pytest in their own process.
pytest_plugins = ("pytester",)


@pytest.fixture(scope="session")
def quick_report(tmp_path_factory: pytest.TempPathFactory) -> QuickReport:
    """The quick report, computed once per run from an empty cache (see the module docstring)."""
    return build(tmp_path_factory.mktemp("quick-report"))


@pytest.fixture(scope="session")
def quick_report_dir(quick_report: QuickReport) -> Path:
    """The shared quick report's directory."""
    return quick_report.out


@pytest.fixture
def quick_report_cache(quick_report: QuickReport, tmp_path: Path) -> Path:
    """A copy of the shared quick report's result cache, for a test's own runs (every quick computation
    cached; the shared cache itself stays as the build left it)."""
    copy = tmp_path / "quick-cache"
    shutil.copytree(quick_report.cache, copy)
    return copy


@pytest.fixture(scope="session")
def own_walls_sweep(tmp_path_factory: pytest.TempPathFactory) -> Sweep:
    """``xcheck sweep examples/own-walls/walls.toml --workers 1``, computed once per run from an empty cache."""
    return sweep(OWN_WALLS, tmp_path_factory.mktemp("own-walls"), "--workers", "1")


@pytest.fixture(scope="session")
def tiny_sweep(tmp_path_factory: pytest.TempPathFactory) -> Sweep:
    """``xcheck sweep examples/sweeps/tiny.toml --workers 1``, computed once per run from an empty cache (the
    sweep tests add to its cache; one worker process: its 8 small walls are not worth a second one's start)."""
    return sweep(TINY, tmp_path_factory.mktemp("tiny"), "--workers", "1")
