"""Crash safety of the result cache, with real processes (forked from the test's, which solved their walls:
a new interpreter would cost a second of imports each).

* a process SIGKILLed at every step of a store leaves no entry or a whole one
  (a record always with its mechanism);
* truncated, empty or foreign files are warned about with their path and
  recomputed, never raised;
* two processes storing and reading the same entries at once never see a part
  of a file;
* a result stopped by a wall-clock limit is not stored as a final answer (its
  run uses it; the next one computes it again).
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
import signal
import time
import traceback
import warnings
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import numpy as np
import pytest

from comparison.domain.wall import WallSpec
from comparison.runner import MICRO_ASSOC, ResultCache, Runner, prefetch
from comparison.runner.executor import Task, TaskOutcome

SPEC = WallSpec.from_paper(t=1, m=1 / 3, rows=6, f=0.75, name="six rows")

def _forked(child: Callable[[], None], errors: Path) -> int:
    """Run ``child`` in a process forked from this one (its imports paid, its walls solved here), which
    ends with ``os._exit``: 0 when ``child`` returns, 1 with the traceback in ``errors`` when it raises.
    Returns the child's pid."""
    pid = os.fork()
    if pid == 0:  # the child: never back into pytest
        code = 1
        try:
            child()
            code = 0
        except BaseException:
            errors.write_text(traceback.format_exc())
        finally:
            os._exit(code)
    return pid


def _wait(pid: int, timeout: float = 300.0) -> int:
    """The exit code of the forked child ``pid`` (minus the signal that ended it, as :mod:`subprocess`
    gives it); a child alive after ``timeout`` seconds is killed and fails the test."""
    end = time.monotonic() + timeout
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            return os.waitstatus_to_exitcode(status)
        if time.monotonic() > end:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            pytest.fail(f"a forked child ran over {timeout} s")
        time.sleep(0.01)


def _killed_store(directory: Path, hook: str, at: int, record: object, mechanism: object) -> Callable[[], None]:
    """The child that stores SPEC's entry into ``directory`` and SIGKILLs itself at the ``at``-th call of
    ``hook`` (``savez``: :func:`numpy.savez_compressed`; else that function of :mod:`os`)."""

    def child() -> None:
        calls = [0]

        def killer(original: Callable[..., object]) -> Callable[..., object]:
            def wrapped(*args: object, **kwargs: object) -> object:
                calls[0] += 1
                if calls[0] == at:
                    os.kill(os.getpid(), signal.SIGKILL)
                return original(*args, **kwargs)

            return wrapped

        if hook == "savez":
            np.savez_compressed = killer(np.savez_compressed)  # type: ignore[assignment]
        else:
            setattr(os, hook, killer(getattr(os, hook)))
        ResultCache(directory).store(SPEC, record, mechanism)  # type: ignore[arg-type]

    return child


def _writer(directory: Path, entries: list[tuple[WallSpec, object, object]], rounds: int) -> Callable[[], None]:
    """One of two children run at once: each stores the entries of three walls over and over and reads
    them back; a warning, an exception or an incomplete entry fails it."""

    def child() -> None:
        warnings.simplefilter("error")
        cache = ResultCache(directory)
        for i in range(rounds):
            for spec, record, mechanism in entries:
                cache.store(spec, record, mechanism)  # type: ignore[arg-type]
                got = cache.load(spec, MICRO_ASSOC)
                mech = cache.mechanism(spec, MICRO_ASSOC)
                if got is None or got.load_factor != record.load_factor or mech is None:  # type: ignore[attr-defined]
                    raise AssertionError(f"iteration {i}: incomplete entry {got!r} {mech!r}")

    return child


def _entry_is_whole_or_absent(directory: Path) -> None:
    cache = ResultCache(directory)
    record = cache.load(SPEC, MICRO_ASSOC)
    if record is not None:  # a record implies its mechanism
        mechanism = cache.mechanism(SPEC, MICRO_ASSOC)
        assert mechanism is not None and mechanism.velocities.shape == (15, 3)


@pytest.mark.parametrize(
    ("hook", "at"),
    [("savez", 1), ("fsync", 1), ("replace", 1), ("fsync", 2), ("replace", 2)],
    ids=["compressing the arrays", "writing the arrays", "renaming the arrays", "writing the record", "renaming it"],
)
def test_a_store_killed_at_any_step_leaves_no_entry_or_a_whole_one(tmp_path: Path, hook: str, at: int) -> None:
    runner = Runner(None)
    record, mechanism = runner.run(SPEC, MICRO_ASSOC), runner.mechanism(SPEC, MICRO_ASSOC)
    errors = tmp_path.parent / f"{tmp_path.name}-errors.txt"
    code = _wait(_forked(_killed_store(tmp_path, hook, at, record, mechanism), errors))
    assert code in (0, -signal.SIGKILL), errors.read_text() if errors.exists() else code
    _entry_is_whole_or_absent(tmp_path)
    # the next run computes what is missing and stores a whole entry
    with_warnings = Runner(tmp_path)
    assert with_warnings.run(SPEC, MICRO_ASSOC).load_factor == pytest.approx(0.75, abs=1e-6)
    assert ResultCache(tmp_path).mechanism(SPEC, MICRO_ASSOC) is not None


@pytest.fixture()
def stored(tmp_path: Path) -> Path:
    """A cache holding the entry of SPEC; returns the record's path."""
    Runner(tmp_path).run(SPEC, MICRO_ASSOC)
    path = ResultCache(tmp_path).path(SPEC, MICRO_ASSOC)
    assert path.exists()
    return path


def _npz(record_path: Path) -> Path:
    (npz,) = record_path.parent.glob("*.npz")
    return npz


@pytest.mark.parametrize(
    "damage",
    ["truncated record", "empty record", "record not JSON", "record of another form", "truncated arrays", "no arrays"],
)
def test_a_damaged_entry_is_warned_with_its_path_and_recomputed(stored: Path, damage: str) -> None:
    data = stored.read_bytes()
    if damage == "truncated record":
        stored.write_bytes(data[: len(data) // 2])
    elif damage == "empty record":
        stored.write_bytes(b"")
    elif damage == "record not JSON":
        stored.write_bytes(b"\x00\xff binary")
    elif damage == "record of another form":
        stored.write_text(json.dumps({"wall": "x"}))
    elif damage == "truncated arrays":
        npz = _npz(stored)
        npz.write_bytes(npz.read_bytes()[:100])
    else:
        _npz(stored).unlink()
    runner = Runner(stored.parent.parent)
    with pytest.warns(UserWarning, match=re.escape(str(stored))):
        rec = runner.run(SPEC, MICRO_ASSOC)
    assert rec.load_factor == pytest.approx(0.75, abs=1e-6) and not rec.cached
    assert runner.computed == 1 and runner.mechanism(SPEC, MICRO_ASSOC) is not None
    # replaced by a whole entry: read back without a warning
    again = Runner(stored.parent.parent)
    assert again.run(SPEC, MICRO_ASSOC).cached and again.mechanism(SPEC, MICRO_ASSOC) is not None


def test_two_processes_storing_and_reading_one_cache(tmp_path: Path) -> None:
    specs = [WallSpec.from_paper(t=1, m=1 / 3, rows=r, f=0.75) for r in (3, 6, 9)]
    runner = Runner(None)
    entries = [(s, runner.run(s, MICRO_ASSOC), runner.mechanism(s, MICRO_ASSOC)) for s in specs]
    cache = tmp_path / "cache"
    errors = [tmp_path / f"errors-{k}.txt" for k in range(2)]
    pids = [_forked(_writer(cache, entries, 150), e) for e in errors]  # type: ignore[arg-type]
    codes = [_wait(pid) for pid in pids]
    for code, e in zip(codes, errors, strict=True):
        assert code == 0, e.read_text()[-2000:] if e.exists() else code
    assert not list(cache.rglob("*.tmp"))


def test_a_result_stopped_by_the_clock_is_not_stored(tmp_path: Path) -> None:
    runner = Runner(None)
    record = runner.run(SPEC, MICRO_ASSOC)
    assert record.micro is not None
    stopped = dataclasses.replace(record, result=dataclasses.replace(record.micro, status="time_limit"))
    cache = ResultCache(tmp_path)
    cache.store(SPEC, stopped, runner.mechanism(SPEC, MICRO_ASSOC))
    assert cache.load(SPEC, MICRO_ASSOC) is None
    cache.store(SPEC, record, runner.mechanism(SPEC, MICRO_ASSOC))
    loaded = cache.load(SPEC, MICRO_ASSOC)
    assert loaded is not None and loaded.result == record.result


def test_a_stored_mechanism_reads_back_equal(tmp_path: Path) -> None:
    runner = Runner(tmp_path)
    runner.run(SPEC, MICRO_ASSOC)
    mine = runner.mechanism(SPEC, MICRO_ASSOC)
    back = ResultCache(tmp_path).mechanism(SPEC, MICRO_ASSOC)
    assert mine is not None and back is not None and back.direction == mine.direction
    np.testing.assert_array_equal(back.velocities, mine.velocities)


class _Returns:
    """An executor that returns ``entry`` for every task (a result computed elsewhere)."""

    workers, memory_per_worker, where = 1, None, "test"

    def __init__(self, entry: object) -> None:
        self.entry = entry

    def run(self, tasks: Sequence[Task]) -> Iterator[TaskOutcome]:
        for task in tasks:
            yield TaskOutcome(task, "done", self.entry)


def test_a_result_stopped_by_the_clock_is_used_by_its_run_but_not_stored(tmp_path: Path) -> None:
    record = Runner(None).run(SPEC, MICRO_ASSOC)
    assert record.micro is not None
    stopped = dataclasses.replace(record, result=dataclasses.replace(record.micro, status="time_limit"))
    runner = Runner(tmp_path)
    assert runner.cache is not None
    done = prefetch(runner.cache, [(SPEC, MICRO_ASSOC)], _Returns((stopped, None)))  # type: ignore[arg-type]
    assert done.computed == 1 and list(done.unstored) == [(SPEC, MICRO_ASSOC)]
    assert (SPEC, MICRO_ASSOC) not in runner.cache
    runner.keep(done.unstored)
    assert runner.run(SPEC, MICRO_ASSOC) is stopped and runner.computed == 0  # not computed a second time


def test_a_cache_that_cannot_be_written_warns_once_and_its_run_keeps_every_result(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A full or read-only cache disk (here: every write fails with ENOSPC): one warning, and the records
    stay with the run, which writes its report."""
    import errno

    from comparison.runner import MACRO
    from comparison.runner import cache as cache_module

    entry = Runner(None)._entry(SPEC, MICRO_ASSOC)

    def full(path: Path, data: bytes, **_: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(cache_module, "write_atomic", full)
    runner = Runner(tmp_path)
    assert runner.cache is not None
    with pytest.warns(cache_module.CacheWarning, match="cannot write the cache .*No space left on device") as seen:
        done = prefetch(runner.cache, [(SPEC, MICRO_ASSOC)], _Returns(entry))  # type: ignore[arg-type]
        runner.keep(done.unstored)
        macro_record = runner.run(SPEC, MACRO)  # computed here, its store fails too: no second warning
    assert len(seen) == 1
    assert done.computed == 1 and list(done.unstored) == [(SPEC, MICRO_ASSOC)]
    assert runner.run(SPEC, MICRO_ASSOC) is entry[0] and runner.computed == 1  # the macro one only
    assert macro_record.load_factor > 0 and runner.run(SPEC, MACRO) is macro_record
