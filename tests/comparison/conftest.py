"""Fixtures shared by the comparison tests: one loopback Dask cluster for the sweeps and the report, and a
``compare`` whose non-associative solve fails.

The cluster is started by the first test that asks for it and ended after the last one (not at the end
of the session: an idle scheduler and worker still cost CPU while the rest of the suite runs).
"""

from __future__ import annotations

import contextlib
import importlib
from pathlib import Path
from typing import Any

import pytest
from dask_cluster import cluster


class _Cluster:
    """The cluster of the run, opened once on demand and closed once."""

    def __init__(self) -> None:
        self.address: str | None = None
        self.last: str | None = None  # the node id of the last test that uses it
        self._stack = contextlib.ExitStack()

    def open(self, tmp: Path) -> str:
        if self.address is None:
            self.address = self._stack.enter_context(cluster(tmp))[0]
        return self.address

    def close(self) -> None:
        self._stack.close()


CLUSTER = _Cluster()


def pytest_collection_finish(session: pytest.Session) -> None:
    users = [item.nodeid for item in session.items if "dask_scheduler" in getattr(item, "fixturenames", ())]
    CLUSTER.last = users[-1] if users else None


def pytest_runtest_teardown(item: pytest.Item, nextitem: pytest.Item | None) -> None:
    if item.nodeid == CLUSTER.last:
        CLUSTER.close()


@pytest.fixture(scope="session")
def dask_scheduler(tmp_path_factory: pytest.TempPathFactory, request: pytest.FixtureRequest) -> str:
    """A ``dask.distributed`` scheduler and one worker on 127.0.0.1 (:func:`dask_cluster.cluster`), ended
    after the last test that uses it (or at the end of the session, if that test did not run to its end)."""
    request.addfinalizer(CLUSTER.close)
    return CLUSTER.open(tmp_path_factory.mktemp("dask"))


@pytest.fixture
def failing_nonassociative(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every non-associative solve of ``comparison.compare`` stops after 2 LPs of the vertex sequence (status
    ``max_iterations``); the associative LP runs as it is."""
    import micro

    verdict = importlib.import_module("comparison.domain.verdict")
    real = verdict.solve_micro

    def failing(wall: micro.BlockWall, friction: str, options: Any, **kw: Any) -> Any:
        if friction == "associative":
            return real(wall, friction, options)
        return micro.solve_nonassociative(wall, max_iterations=2, tuning=micro.Tuning(selection="vertex"))

    monkeypatch.setattr(verdict, "solve_micro", failing)
