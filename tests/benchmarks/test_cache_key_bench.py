"""The result cache key's cost (pytest-benchmark). Run: ``pytest -m benchmark --benchmark-enable
tests/benchmarks/test_cache_key_bench.py``.

Target: a warm key (a new process, the cache folder's memo of each module's hash in place) under 50 ms;
cold (no memo: every module parsed) it is a few hundred milliseconds once per process and cache folder.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from pytest_benchmark.fixture import BenchmarkFixture

from comparison.runner import fingerprint as fp

pytestmark = pytest.mark.benchmark


def _new_process() -> None:
    """What a new process starts from: no file read yet, no fingerprint taken."""
    fp._READ.clear()
    fp.fingerprint.cache_clear()
    fp._dist_info_versions.cache_clear()


@pytest.mark.benchmark(group="cache-key")
@pytest.mark.parametrize("memo", ["warm", "cold"])
def test_cache_key(benchmark: BenchmarkFixture, tmp_path: Path, memo: str) -> None:
    folder = tmp_path / "cache"
    key = fp.code_version(folder)
    if memo == "cold":
        (folder / fp.MEMO_FILE).unlink()

    def one() -> str:
        _new_process()
        if memo == "cold":
            (folder / fp.MEMO_FILE).unlink(missing_ok=True)
        return fp.code_version(folder)

    assert benchmark.pedantic(one, rounds=15 if memo == "warm" else 5, iterations=1) == key
