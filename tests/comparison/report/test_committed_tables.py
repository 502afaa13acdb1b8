"""``xcheck report --tables DIR`` refuses a committed table it cannot read whole, with one line naming the
file and the line, before any work: a truncated table read silently would make REPORT.md quote a row cut
mid-number, and binary junk or wrong columns must not end in a traceback (``UnicodeDecodeError``,
``KeyError``)."""

from __future__ import annotations

import contextlib
import io
import re
import shutil
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.report import build_report
from comparison.report.committed import BOND, ERRORMAP, LOWEST, BadTable, check_tables, read_committed
from comparison.report.errormap import load
from comparison.sweep.figures import error_map

REPORTS = Path(__file__).resolve().parents[3] / "reports"


def _tables(tmp_path: Path, name: str, content: bytes, meta: bool = False) -> Path:
    """A tables directory holding ``content`` as the table ``name`` (and the sweep's metadata when ``meta``)."""
    tables = tmp_path / "tables"
    (tables / "sweeps").mkdir(parents=True)
    (tables / name).write_bytes(content)
    if meta:
        shutil.copy(REPORTS / name.replace(".csv", ".json"), tables / name.replace(".csv", ".json"))
    return tables


def _report(tables: Path, out: Path) -> tuple[int, str, str]:
    o, e = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(o), contextlib.redirect_stderr(e):
        code = main(["report", "--quick", "--no-cache", "--tables", str(tables), "--out", str(out), "-q"])
    return code, o.getvalue(), e.getvalue()


def _cut(name: str, size: int) -> bytes:
    return (REPORTS / name).read_bytes()[:size]


def _full(name: str) -> list[bytes]:
    return (REPORTS / name).read_bytes().splitlines(keepends=True)


def _lines(name: str, n: int) -> bytes:
    return b"".join((REPORTS / name).read_bytes().splitlines(keepends=True)[:n])


CASES = {
    "cut mid-number": (ERRORMAP, _cut(ERRORMAP, 20_000), False,
                       r"sweeps/errormap.csv: the last line is cut short \(no line break at the end of the file\); "
                       r"remake it with `xcheck sweep .*/comparison/sweep/grids/errormap.toml --out .*/tables/sweeps`"),
    "cut at a line": (ERRORMAP, _lines(ERRORMAP, 40), True,
                      r"sweeps/errormap.csv: 39 rows where its metadata \(errormap.json\) counts 750 cells "
                      r"\(a truncated table\)"),
    "a row cut short": (BOND, _lines(BOND, 3) + b"1,t=1,1.0,0.333\n" + _lines(BOND, 40)[len(_lines(BOND, 3)):],
                        False, r"sweeps/table9_bond.csv:4: 4 fields where the header has 38 \(a truncated or "
                               r"damaged table\)"),
    "binary junk": (LOWEST, bytes(range(256)) * 4, False,
                    r"lowest.csv: not a text table \(byte 128 is not UTF-8\); remake it with `xcheck stability "
                    r"--lowest --out .*tables`"),
    "wrong columns": (ERRORMAP, b"a,b\n1,2\n", False,
                      r"sweeps/errormap.csv:1: no column 't', 'm', 'f', 'p', 'load_factor', 'cell', 'rows', "
                      r"'storeys', 'blocks', 'iterations', 'kind', 'first_course', 'status' \(the header has 2 "
                      r"columns\)"),
    "header only": (LOWEST, _lines(LOWEST, 1), False, r"lowest.csv: no rows under the header"),
    "a row repeated": (ERRORMAP, b"".join(_full(ERRORMAP)[:2] + _full(ERRORMAP)[1:2] + _full(ERRORMAP)[3:]), True,
                       r"sweeps/errormap.csv:3: cell '0' where cell 1 comes \(the cells are numbered from 0, each "
                       r"once, in order: a row repeated, dropped or moved\)"),
    "a status no sweep writes": (ERRORMAP, (REPORTS / ERRORMAP).read_bytes().replace(b",optimal,", b",banana,", 1),
                                 True, r"sweeps/errormap.csv:2: status must be a status a sweep writes \(converged, "
                                       r".*\), got 'banana'"),
    "not a number": (ERRORMAP, _lines(ERRORMAP, 2).replace(b",0.4,0.25,12,", b",0.4,0.25,twelve,"), False,
                     r"sweeps/errormap.csv:2: rows must be an integer >= 0, got 'twelve'"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_a_damaged_committed_table_is_one_line_and_exit_2_before_any_work(case: str, tmp_path: Path) -> None:
    name, content, meta, match = CASES[case]
    tables = _tables(tmp_path, name, content, meta)
    code, out, err = _report(tables, tmp_path / "out")
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("xcheck: error: --tables: ") and re.search(match, err), err
    assert not (tmp_path / "out").exists()  # nothing computed, nothing written, no folder made
    with pytest.raises(BadTable):
        build_report(tmp_path / "api", quick=True, cache_dir=None, tables_dir=tables)
    assert not (tmp_path / "api" / "REPORT.md").exists()


def test_the_committed_tables_read_whole() -> None:
    check_tables(REPORTS)
    assert len(read_committed(REPORTS, ERRORMAP)) == 750 and len(read_committed(REPORTS, LOWEST)) == 178


def test_a_table_cut_at_a_line_without_its_metadata_still_draws(tmp_path: Path) -> None:
    """Without the metadata to count against, a table cut at a line break is read as it is: its section
    quotes what it holds, and the figure of a grid with one column no longer fails in ``contour``."""
    tables = _tables(tmp_path, ERRORMAP, _lines(ERRORMAP, 40))
    walls = load(tables / ERRORMAP)
    drawn = error_map(walls, "macro", tmp_path / "e.png")
    assert drawn is not None and drawn.stat().st_size > 0
