"""Fixtures shared by the comparison tests: one loopback Dask cluster for the sweeps and the report."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from dask_cluster import cluster


@pytest.fixture(scope="session")
def dask_scheduler(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """A ``dask.distributed`` scheduler and one worker on 127.0.0.1 (:func:`dask_cluster.cluster`)."""
    with cluster(tmp_path_factory.mktemp("dask")) as (address, _, _):
        yield address
