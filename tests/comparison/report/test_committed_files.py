"""``xcheck report --tables DIR`` refuses, in one line naming the file (and the line) with exit 2 before any
work, a committed table that is not a regular file, that holds a value no run writes, or that cannot be
counted whole; a sweep table without its metadata is a warning (its rows cannot be counted).

Each case starts from a copy of the committed tables (``reports/``) with one thing damaged.
"""

from __future__ import annotations

import contextlib
import csv
import io
import os
import re
import shutil
import signal
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.report.committed import BOND, ERRORMAP, LOWEST, BadTable, UncountedTableWarning, check_tables

REPORTS = Path(__file__).resolve().parents[3] / "reports"
#: Seconds a check may take before the test calls it a hang (a FIFO opened for reading waits for a writer).
HANG_SECONDS = 60


@pytest.fixture(autouse=True)
def no_hang() -> Iterator[None]:
    def hung(signum: int, frame: object) -> None:
        raise TimeoutError(f"reading the tables hung for {HANG_SECONDS} s")

    previous = signal.signal(signal.SIGALRM, hung)
    signal.alarm(HANG_SECONDS)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _copy(tmp_path: Path) -> Path:
    tables = tmp_path / "tables"
    (tables / "sweeps").mkdir(parents=True)
    for name in (ERRORMAP, BOND, LOWEST, "sweeps/errormap.json", "sweeps/table9_bond.json"):
        shutil.copy(REPORTS / name, tables / name)
    return tables


def _set(name: str, column: str, value: str, row: int = 1) -> Callable[[Path], None]:
    """Put ``value`` in ``column`` of data row ``row`` (line ``row + 1``) of the table ``name``."""
    def damage(tables: Path) -> None:
        path = tables / name
        lines = list(csv.reader(io.StringIO(path.read_text(), newline="")))
        lines[row][lines[0].index(column)] = value
        with path.open("w", newline="") as fh:
            csv.writer(fh, lineterminator="\n").writerows(lines)
    return damage


def _keep_lines(name: str, n: int) -> Callable[[Path], None]:
    def damage(tables: Path) -> None:
        path = tables / name
        path.write_bytes(b"".join(path.read_bytes().splitlines(keepends=True)[:n]))
    return damage


def _replace_by(name: str, what: str) -> Callable[[Path], None]:
    def damage(tables: Path) -> None:
        path = tables / name
        path.unlink()
        if what == "directory":
            path.mkdir()
        elif what == "fifo":
            os.mkfifo(path)
        elif what == "/dev/zero":
            path.symlink_to("/dev/zero")
        elif what == "loop":
            path.symlink_to(path)
        else:
            path.write_bytes(what.encode())
    return damage


#: Damage, and what the one line must say (after the file's path).
REFUSED: dict[str, tuple[Callable[[Path], None], str]] = {
    "errormap cut to 500 lines": (_keep_lines(ERRORMAP, 500),
                                  r"errormap.csv: 499 rows where its metadata \(errormap.json\) counts 750 cells"),
    "errormap.json damaged": (_replace_by("sweeps/errormap.json", '{"counts": {'),
                              r"errormap.json: the metadata of errormap.csv cannot be read \(JSONDecodeError"),
    "errormap.json without counts": (_replace_by("sweeps/errormap.json", '{"counts": {"cells": "750"}}'),
                                     r"errormap.json: the metadata of errormap.csv cannot be read \(TypeError"),
    "errormap.json a directory": (_replace_by("sweeps/errormap.json", "directory"),
                                  r"errormap.json: the metadata of errormap.csv cannot be read \(not a regular"),
    "lowest cut to 100 lines": (_keep_lines(LOWEST, 100),
                                r"lowest.csv: 99 rows where the study has 178 \(the study\) or 12 \(the study with "
                                r"--quick\) walls"),
    "lowest a directory": (_replace_by(LOWEST, "directory"), r"lowest.csv: cannot be read \(not a regular file: a "
                                                             r"directory\)"),
    "lowest a FIFO": (_replace_by(LOWEST, "fifo"), r"lowest.csv: cannot be read \(not a regular file: a named pipe\)"),
    "lowest /dev/zero": (_replace_by(LOWEST, "/dev/zero"),
                         r"lowest.csv: cannot be read \(not a regular file: a character device\)"),
    "lowest a symlink loop": (_replace_by(LOWEST, "loop"), r"lowest.csv: cannot be read \(Too many levels"),
    "load_factor=1e999999999": (_set(ERRORMAP, "load_factor", "1e999999999"),
                                r"errormap.csv:2: load_factor must be a positive number, got '1e999999999'"),
    "load_factor=-5": (_set(BOND, "load_factor", "-5", row=3),
                       r"table9_bond.csv:4: load_factor must be a positive number, got '-5'"),
    "t=-1": (_set(ERRORMAP, "t", "-1", row=7), r"errormap.csv:8: t must be a positive number, got '-1'"),
    "lambda_lowest=inf": (_set(LOWEST, "lambda_lowest", "inf", row=5),
                          r"lowest.csv:6: lambda_lowest must be a positive number, got 'inf'"),
    "negative seconds": (_set(LOWEST, "global_seconds", "-0.5"),
                         r"lowest.csv:2: global_seconds must be a number >= 0, got '-0.5'"),
}


def _report(tables: Path, out: Path) -> tuple[int, str, str]:
    o, e = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(o), contextlib.redirect_stderr(e):
        code = main(["report", "--quick", "--no-cache", "--tables", str(tables), "--out", str(out), "-q"])
    return code, o.getvalue(), e.getvalue()


@pytest.mark.parametrize("case", list(REFUSED))
def test_a_table_that_cannot_be_read_whole_is_refused_in_one_line(tmp_path: Path, case: str) -> None:
    """A committed table that cannot be read whole (cut short, a directory, a FIFO, a device, an infinite or
    negative value) is refused in one line naming it, exit 2."""
    damage, words = REFUSED[case]
    tables = _copy(tmp_path)
    damage(tables)
    with pytest.raises(BadTable, match=words):
        check_tables(tables)
    code, out, err = _report(tables, tmp_path / "out")
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("xcheck: error: --tables: ") and re.search(words, err), err
    assert not (tmp_path / "out").exists()


def test_a_sweep_table_without_its_metadata_is_a_warning(tmp_path: Path) -> None:
    tables = _copy(tmp_path)
    (tables / "sweeps" / "errormap.json").unlink()
    with pytest.warns(UncountedTableWarning, match=r"errormap.csv: its metadata errormap.json is missing, so its "
                                                   r"rows cannot be counted"):
        check_tables(tables)


def test_the_committed_tables_pass_every_rule() -> None:
    check_tables(REPORTS)
