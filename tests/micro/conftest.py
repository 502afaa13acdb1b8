"""Shared walls for the micro-model tests."""

from __future__ import annotations

import pytest
from micro_walls import TABLE7, table7_wall

import micro


@pytest.fixture(scope="session")
def table7() -> dict[str, micro.BlockWall]:
    return {name: table7_wall(name) for name in TABLE7}
