"""Every text output is written whole or not at all: on a full disk the old file stays and no temporary file
is left (never a cut-short page, a 0-byte JSON or an invalid ``timings.json``).

A full disk is made two ways: a file-size limit on a real ``xcheck sweep`` process (``RLIMIT_FSIZE``: every
write past it fails with ``EFBIG``, as one past a full disk fails with ``ENOSPC``), and ``ENOSPC`` raised
where each writer flushes its file to disk.
"""

from __future__ import annotations

import errno
import json
import os
import resource
import signal
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.report.tables import Table
from comparison.sweep.table import write_meta, write_table
from comparison.utilities.outputs import write_text

ROOT = Path(__file__).resolve().parents[2]
#: Twelve walls, the macro model only: a table of about 2.5 kB, its metadata and page about 1 kB each.
GRID = """name = "full"
[axes]
t = [0.5, 1.0, 2.0]
m = [0.5, 1]
rows = [6, 12]
f = 0.75
[[method]]
kind = "macro"
"""
#: The file-size limit of the sweep process (bytes): below the table, so its write fails.
LIMIT = 1000


def _limited() -> None:
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG, not a signal
    resource.setrlimit(resource.RLIMIT_FSIZE, (LIMIT, LIMIT))


def test_a_sweep_on_a_full_disk_leaves_the_last_whole_outputs_and_no_temporary_file(tmp_path: Path) -> None:
    """A sweep on a full disk leaves the last whole outputs and no temporary file."""
    grid = tmp_path / "full.toml"
    grid.write_text(GRID)
    out = tmp_path / "out"
    assert main(["sweep", str(grid), "--out", str(out), "--cache", str(tmp_path / "c"), "-q"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert set(before) == {"full.csv", "full.json", "full.md"} and min(map(len, before.values())) > LIMIT
    env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONDONTWRITEBYTECODE": "1"}
    done = subprocess.run([sys.executable, "-m", "comparison.cli", "sweep", str(grid), "--out", str(out), "--cache",
                           str(tmp_path / "c"), "-q"], preexec_fn=_limited, capture_output=True, text=True, env=env,
                          cwd=tmp_path, timeout=300)
    assert done.returncode == 1 and done.stderr == f"xcheck: error: cannot write {out / 'full.csv'}: File too large\n"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def _disk_full_at_flush(monkeypatch: pytest.MonkeyPatch) -> None:
    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)


WRITERS = {
    "write_text": lambda path: write_text(path, "new\n"),
    "sweep table": lambda path: write_table([{"cell": 0, "wall": "w"}], path),
    "sweep metadata": lambda path: write_meta({"counts": {"cells": 1}}, path),
    "report table": lambda path: Table("t", "T", ["a", "b"], [[1, 2.5]]).write_csv(path),
}


@pytest.mark.parametrize("writer", list(WRITERS))
def test_each_writer_on_a_full_disk_leaves_the_old_file_and_no_temporary_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, writer: str
) -> None:
    path = tmp_path / "out.txt"
    path.write_text("old\n")
    _disk_full_at_flush(monkeypatch)
    with pytest.raises(OSError, match="No space left on device"):
        WRITERS[writer](path)
    assert path.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_an_output_gets_the_mode_of_a_file_the_process_creates(tmp_path: Path) -> None:
    """The temporary file is private (0600) until renamed; the output is not."""
    mask = os.umask(0o022)
    try:
        path = write_text(tmp_path / "a.md", "x\n")
        plain = tmp_path / "b.md"
        plain.write_text("x\n")
    finally:
        os.umask(mask)
    assert path.stat().st_mode & 0o777 == plain.stat().st_mode & 0o777 == 0o644
    assert json.loads(write_text(tmp_path / "c.json", "[1]").read_text()) == [1]


@pytest.mark.parametrize("through_link", [False, True])
def test_a_target_that_is_not_a_regular_file_is_refused_and_left_as_it_is(tmp_path: Path,
                                                                          through_link: bool) -> None:
    """A rename over a FIFO or a device puts a file in its place (as root, ``--state /dev/null`` replaced the
    device node): the writer refuses such a target, directly or through a link, and leaves it be."""
    from micro.files import write_whole

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    path = fifo
    if through_link:
        path = tmp_path / "link.png"
        path.symlink_to(fifo)
    with pytest.raises(OSError, match="not a regular file: a named pipe"):
        write_whole(path, b"data")
    assert stat.S_ISFIFO(os.stat(fifo).st_mode) and sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["pipe", *(["link.png"] if through_link else [])])


def test_the_cache_replaces_a_link_rather_than_write_through_it(tmp_path: Path) -> None:
    from micro.files import write_whole

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    entry = tmp_path / "entry.json"
    entry.symlink_to(fifo)
    write_whole(entry, b"{}", follow_symlinks=False)
    assert entry.read_bytes() == b"{}" and not entry.is_symlink() and stat.S_ISFIFO(os.stat(fifo).st_mode)
