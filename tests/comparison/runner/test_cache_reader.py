"""No file in a cache folder can hang a run or exhaust its memory.

Each entry below is replaced by something that is not a cache file (a FIFO, a directory, a symbolic link to
``/dev/zero`` or in a loop, an unreadable file, a sparse file of 3 GB, a kind folder that is a file): the
read is a :class:`CacheWarning` naming the entry and a recompute, never a traceback, a hang or a read of
the whole thing. A folder of entries is checked with the memory of one, whatever their number.
"""

from __future__ import annotations

import os
import shutil
import signal
import stat
import tracemalloc
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from comparison.domain.wall import WallSpec
from comparison.runner import MICRO_ASSOC, ResultCache, Runner
from comparison.runner import cache as cache_module
from comparison.runner.cache import MAX_MECHANISM_BYTES, MAX_RECORD_BYTES, CacheWarning
from comparison.runner.records import MechanismRecord

SPEC = WallSpec.from_paper(t=1, m=1 / 3, rows=6, f=0.75, name="six rows")
#: A sparse file of this size stands for an entry the reader must not read whole.
SPARSE_BYTES = 3 * 10**9


#: Seconds a read may take before the test calls it a hang.
HANG_SECONDS = 60


@pytest.fixture(autouse=True)
def no_hang() -> Iterator[None]:
    """A read that hangs (a FIFO opened for reading waits for a writer) fails the test instead."""
    def hung(signum: int, frame: object) -> None:
        raise TimeoutError(f"the cache read hung for {HANG_SECONDS} s")

    previous = signal.signal(signal.SIGALRM, hung)
    signal.alarm(HANG_SECONDS)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


@pytest.fixture()
def stored(tmp_path: Path) -> Path:
    """A cache holding the entry of SPEC; returns the record's path."""
    Runner(tmp_path).run(SPEC, MICRO_ASSOC)
    path = ResultCache(tmp_path).path(SPEC, MICRO_ASSOC)
    assert path.is_file()
    return path


def _npz(record: Path) -> Path:
    (npz,) = record.parent.glob("*.npz")
    return npz


def _replace(target: Path, damage: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Put ``damage`` where the file ``target`` was."""
    target.unlink()
    if damage == "fifo":
        os.mkfifo(target)
    elif damage == "directory":
        target.mkdir()
        (target / "inside").write_text("x")
    elif damage == "symlink to /dev/zero":
        target.symlink_to("/dev/zero")
    elif damage == "symlink loop":
        target.symlink_to(target)
    elif damage == "sparse 3 GB":
        with target.open("wb") as fh:
            fh.truncate(SPARSE_BYTES)
    elif damage == "unreadable":
        target.write_text("{}")
        target.chmod(0)
        if os.geteuid() == 0:  # root reads it anyway: the permission error is raised by hand
            real_open = os.open

            def refuse(path: object, *args: object, **kwargs: object) -> int:
                if Path(str(path)) == target:
                    raise PermissionError(13, "Permission denied", str(path))
                return real_open(path, *args, **kwargs)  # type: ignore[arg-type]

            monkeypatch.setattr(os, "open", refuse)
    else:  # pragma: no cover
        raise AssertionError(damage)


DAMAGES = ["fifo", "directory", "symlink to /dev/zero", "symlink loop", "sparse 3 GB", "unreadable"]


def _recomputed(cache_dir: Path, match: str) -> None:
    runner = Runner(cache_dir)
    with pytest.warns(CacheWarning, match=match):
        record = runner.run(SPEC, MICRO_ASSOC)
    assert record.load_factor == pytest.approx(0.75, abs=1e-6) and not record.cached and runner.computed == 1


def _replaced_not_written_through(entry: Path, damage: str) -> None:
    """The recomputed entry took the damaged one's place (a regular file; a directory cannot be renamed
    over), and whatever a link pointed to is untouched (written through, a link to ``/dev/zero`` replaced
    the device node with a file)."""
    assert damage == "directory" or stat.S_ISREG(os.lstat(entry).st_mode)
    assert stat.S_ISCHR(os.stat("/dev/zero").st_mode)


@pytest.mark.parametrize("damage", DAMAGES)
def test_a_record_that_is_not_a_regular_file_is_warned_and_recomputed(
    stored: Path, damage: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A FIFO would hang a plain read, a directory raise, ``/dev/zero`` be read until the kernel kills the
    run, a sparse file be read whole."""
    _replace(stored, damage, monkeypatch)
    _recomputed(stored.parent.parent, str(stored))
    _replaced_not_written_through(stored, damage)


@pytest.mark.parametrize("damage", DAMAGES)
def test_a_mechanism_that_is_not_a_regular_file_is_warned_and_recomputed(
    stored: Path, damage: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    _replace(_npz(stored), damage, monkeypatch)
    _recomputed(stored.parent.parent, str(stored))
    _replaced_not_written_through(_npz(stored), damage)


def test_a_kind_folder_that_is_a_file_is_warned_and_recomputed(stored: Path) -> None:
    folder = stored.parent
    shutil.rmtree(folder)
    folder.write_text("not a folder")
    runner = Runner(folder.parent)
    with pytest.warns(CacheWarning, match=f"{stored}.*Not a directory"):
        record = runner.run(SPEC, MICRO_ASSOC)
    assert record.load_factor == pytest.approx(0.75, abs=1e-6) and runner.computed == 1


def test_a_record_over_its_size_cap_is_refused(stored: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cache_module, "MAX_RECORD_BYTES", stored.stat().st_size - 1)
    _recomputed(stored.parent.parent, "more than the")
    assert MAX_RECORD_BYTES >= 1 << 20 and MAX_MECHANISM_BYTES >= 1 << 26


def test_a_deeply_nested_record_is_warned_not_a_traceback(stored: Path) -> None:
    stored.write_bytes(b"[" * 200_000 + b"]" * 200_000)
    _recomputed(stored.parent.parent, "RecursionError")


def test_arrays_that_would_unpack_beyond_the_cap_are_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A mechanism file whose hash matches its record but which unpacks beyond the cap (a small file of
    zeros that inflates) is refused before it is unpacked."""
    record = Runner(None).run(SPEC, MICRO_ASSOC)
    cache = ResultCache(tmp_path)
    cache.store(SPEC, record, MechanismRecord(np.zeros((200_000, 3)), "+x"))
    path = cache.path(SPEC, MICRO_ASSOC)
    assert _npz(path).stat().st_size < 100_000  # zeros compress
    monkeypatch.setattr(cache_module, "MAX_MECHANISM_BYTES", 1_000_000)
    with pytest.warns(CacheWarning, match="unpacks to"):
        assert cache.entry(SPEC, MICRO_ASSOC) is None


#: Entries in the folder of the bounded-memory test, the blocks of the mechanism each names, and the most
#: the checks of all of them may hold at once (bytes, as ``tracemalloc`` counts Python's allocations): one
#: entry's worth, while the entries hold 40 times as much together.
ENTRIES = 200
BLOCKS = 10_000
PEAK_BOUND = 2_000_000


def test_a_folder_of_entries_is_checked_with_the_memory_of_one(tmp_path: Path) -> None:
    record = Runner(None).run(SPEC, MICRO_ASSOC)
    velocities = np.random.default_rng(0).standard_normal((BLOCKS, 3))  # random: the file stays large
    cache = ResultCache(tmp_path)
    cache.store(SPEC, record, MechanismRecord(velocities, "+x"))
    first = cache.path(SPEC, MICRO_ASSOC)
    data, npz = first.read_bytes(), _npz(first)
    specs = [WallSpec.from_paper(t=1 + i / ENTRIES, m=1 / 3, rows=6, f=0.75) for i in range(ENTRIES)]
    for spec in specs:  # the same entry under every key (each record names the one mechanism file)
        cache.path(spec, MICRO_ASSOC).write_bytes(data)
    assert ENTRIES * (npz.stat().st_size + velocities.nbytes) > 40 * PEAK_BOUND
    tracemalloc.start()
    try:
        found = sum((spec, MICRO_ASSOC) in cache for spec in specs)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert found == ENTRIES and peak < PEAK_BOUND, f"{peak:,} bytes held at most"
