"""``quiet_highs``: HiGHS instances built without their banner, stdout intact after."""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import pytest

from micro.backends.highs_runs import quiet_highs


def test_threads_building_instances_leave_stdout_working(capfd: pytest.CaptureFixture[str]) -> None:
    """Eight threads build 32 instances at once; descriptor 1 is back on the
    real stdout afterwards (what is written to it arrives), and nothing of
    HiGHS' banner was written."""
    with ThreadPoolExecutor(8) as pool:
        made = list(pool.map(lambda _: quiet_highs(), range(32)))
    assert len(made) == 32
    os.write(1, b"still here\n")
    out = capfd.readouterr().out
    assert "still here" in out and "Running HiGHS" not in out
