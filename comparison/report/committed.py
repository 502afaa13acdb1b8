"""The committed tables the report reads and does not recompute, and the one place it looks for them.

Three sections of the report render tables that take hours to compute and are
committed with it: the error map (``sweeps/errormap.csv``), Table 9's walls with
coarser bonds (``sweeps/table9_bond.csv``) and the lowest collapse load
(``lowest.csv``). The report reads them from one stated directory, its *tables
directory*: ``xcheck report --tables DIR`` (``build_report(tables_dir=...)``), by
default the report's own output directory (``--out``, ``reports`` by default),
where the commands of :data:`MADE_BY` write them. Nothing is read through the
source tree, so an installed package behaves as a clone does. A table that is
not there is said loudly: a warning naming its path and the command that makes
it (``xcheck: warning: ...`` on the command line), and its section of
``REPORT.md`` says it is missing.
"""

from __future__ import annotations

import csv
import functools
import io
import json
import math
import os
import shlex
import warnings
from collections.abc import Mapping
from pathlib import Path

from comparison.sweep import grids
from comparison.sweep.table import STATUSES
from comparison.utilities.inputs import read_input_file

#: The error map's sweep table, relative to the tables directory.
ERRORMAP = "sweeps/errormap.csv"
#: Table 9's walls with coarser bonds.
BOND = "sweeps/table9_bond.csv"
#: The lowest collapse load on Table 7's walls (the study's table).
LOWEST = "lowest.csv"
#: The command that writes each table into the tables directory ``DIR``; ``GRIDS`` is the folder of the
#: grid files installed with the package (:mod:`comparison.sweep.grids`, copies of ``examples/sweeps/``), so
#: that the command works from an installed wheel as from a clone.
MADE_BY = {
    ERRORMAP: "xcheck sweep GRIDS/errormap.toml --out DIR/sweeps",
    BOND: "xcheck sweep GRIDS/table9_bond.toml --out DIR/sweeps",
    LOWEST: "xcheck stability --lowest --out DIR",
}


def made_by(name: str, tables_dir: Path | str) -> str:
    """The command of :data:`MADE_BY` that writes the table ``name`` into ``tables_dir``, runnable as printed."""
    return MADE_BY[name].replace("GRIDS", shlex.quote(str(grids.FOLDER))).replace("DIR", shlex.quote(str(tables_dir)))


#: The columns each section reads, and what each must hold: ``"text"``; ``"positive"`` (a positive number),
#: ``"non-negative"`` (zero or more) or ``"ratio"`` (any finite number), each also ``nan`` or empty (no
#: value); ``"count"`` (a non-negative integer, or empty); ``"status"`` (one a sweep writes,
#: :data:`comparison.sweep.table.STATUSES`). Infinite numbers are refused everywhere. A sweep's ``cell``
#: numbers its rows from 0, each once, in order: a row repeated, dropped or moved is refused.
_SWEEP: Mapping[str, str] = {
    **dict.fromkeys(("t", "m", "f"), "positive"),
    "p": "non-negative",
    "load_factor": "positive",
    **dict.fromkeys(("cell", "rows", "storeys", "blocks", "iterations"), "count"),
    **dict.fromkeys(("kind", "first_course"), "text"),
    "status": "status",
}
COLUMNS: Mapping[str, Mapping[str, str]] = {
    ERRORMAP: _SWEEP,
    BOND: _SWEEP,
    LOWEST: {
        **dict.fromkeys(("group", "wall", "global_status"), "text"),
        **dict.fromkeys(("orduna", "lambda_iterated", "lambda_lowest", "global_best"), "positive"),
        **dict.fromkeys(("global_bound", "global_gap", "iterated_seconds", "lowest_seconds", "global_seconds"),
                        "non-negative"),
        **dict.fromkeys(("iterated_over_global", "iterated_over_lowest"), "ratio"),
        "lowest_moves": "count",
    },
}
#: What each kind of column must hold, in words.
RULES = {"positive": "a positive number", "non-negative": "a number >= 0", "ratio": "a finite number",
         "count": "an integer >= 0", "status": "a status a sweep writes (" + ", ".join(sorted(STATUSES)) + ")"}
#: The largest committed table read (bytes): a sweep's table has at most 100,000 rows
#: (:data:`comparison.sweep.grid.MAX_CELLS`) of about 300 bytes, 30 MB; the committed error map is 0.17 MB.
MAX_TABLE_BYTES = 64 << 20
#: The largest sweep metadata read (bytes): the committed ones are under 2 kB.
MAX_META_BYTES = 1 << 20


class BadTable(ValueError):
    """A committed table that cannot be read whole; the message names the file, the line and how to remake it."""


def _bad_cell(kind: str, text: str) -> bool:
    """True when ``text`` is not what a column of ``kind`` holds (:data:`COLUMNS`)."""
    if kind == "status":
        return text not in STATUSES
    if kind == "text" or not text:
        return False
    try:
        x = float(text)
    except ValueError:
        return True
    if math.isnan(x):
        return kind == "count"
    if not math.isfinite(x):
        return True
    if kind == "count":
        return not (x.is_integer() and x >= 0)
    return (kind == "positive" and x <= 0) or (kind == "non-negative" and x < 0)


def read_committed(tables_dir: Path, name: str) -> list[dict[str, str]]:
    """The rows of the committed table ``name`` (:data:`ERRORMAP`, :data:`BOND`, :data:`LOWEST`) of
    ``tables_dir``, checked whole.

    Raises:
        BadTable: not a regular file (a directory, a FIFO, a device such as ``/dev/zero``), larger than
            :data:`MAX_TABLE_BYTES`, not UTF-8 text (binary junk), not ending with a line break (cut
            short), without a column its section reads, without rows, a row with another number of
            fields than the header, a value outside its column's rule (:data:`RULES`: ``inf``, a negative
            ``t``), fewer or more rows than its metadata counts (a sweep) or than the study has walls
            (``lowest.csv``); the message names the file and the line.
    """
    path = Path(tables_dir) / name
    remake = f"remake it with `{made_by(name, tables_dir)}`"
    try:
        data = read_input_file(path, MAX_TABLE_BYTES)
    except OSError as exc:
        raise BadTable(f"{path}: cannot be read ({exc.strerror or exc}); {remake}") from None
    if len(data) > MAX_TABLE_BYTES:
        raise BadTable(f"{path}: larger than the {MAX_TABLE_BYTES:,} bytes a committed table may have; {remake}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BadTable(f"{path}: not a text table (byte {exc.start} is not UTF-8); {remake}") from None
    if not text.endswith("\n"):
        raise BadTable(f"{path}: the last line is cut short (no line break at the end of the file); {remake}")
    try:
        lines = list(csv.reader(io.StringIO(text, newline="")))
    except csv.Error as exc:
        raise BadTable(f"{path}: not a CSV table ({exc}); {remake}") from None
    header, rows = (lines[0], lines[1:]) if lines else ([], [])
    missing = [c for c in COLUMNS[name] if c not in header]
    if missing:
        raise BadTable(f"{path}:1: no column {', '.join(repr(c) for c in missing)} (the header has "
                       f"{len(header)} columns); {remake}")
    if not rows:
        raise BadTable(f"{path}: no rows under the header; {remake}")
    out = []
    for i, row in enumerate(rows, start=2):
        if len(row) != len(header):
            raise BadTable(f"{path}:{i}: {len(row)} fields where the header has {len(header)} (a truncated or "
                           f"damaged table); {remake}")
        record = dict(zip(header, row, strict=True))
        bad = [c for c, kind in COLUMNS[name].items() if _bad_cell(kind, record[c])]
        if bad:
            raise BadTable(f"{path}:{i}: {bad[0]} must be {RULES[COLUMNS[name][bad[0]]]}, got {record[bad[0]]!r}; "
                           f"{remake}")
        if "cell" in COLUMNS[name] and record["cell"] != str(i - 2):
            raise BadTable(f"{path}:{i}: cell {record['cell']!r} where cell {i - 2} comes (the cells are numbered "
                           f"from 0, each once, in order: a row repeated, dropped or moved); {remake}")
        out.append(record)
    _whole(path, name, out, remake)
    return out


def _whole(path: Path, name: str, rows: list[dict[str, str]], remake: str) -> None:
    """A table cut at a line break still reads: a sweep's metadata (``errormap.json`` beside
    ``errormap.csv``, written by the same run) counts its cells, and the lowest-load study has a known
    number of walls (:func:`_study_walls`).

    Warns:
        UncountedTableWarning: a sweep table without its metadata (its rows cannot be counted).

    Raises:
        BadTable: metadata that cannot be read, or fewer or more rows than it counts (than the study has).
    """
    if name == LOWEST:
        counts = _study_walls()
        if len(rows) not in counts:
            expected = " or ".join(f"{n} ({which})" for n, which in sorted(counts.items(), reverse=True))
            raise BadTable(f"{path}: {len(rows)} rows where the study has {expected} walls (a truncated "
                           f"table); {remake}")
        return
    meta = path.with_suffix(".json")
    if not os.path.lexists(meta):
        warnings.warn(f"{path}: its metadata {meta.name} is missing, so its rows cannot be counted (a table cut "
                      f"at a line break would read as whole); {remake}", UncountedTableWarning, stacklevel=3)
        return
    try:
        cells = json.loads(read_input_file(meta, MAX_META_BYTES))["counts"]["cells"]
        if isinstance(cells, bool) or not isinstance(cells, int):
            raise TypeError(f"counts.cells is {cells!r}")
    except (OSError, ValueError, KeyError, TypeError, RecursionError) as exc:
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else f"{type(exc).__name__}: {exc}"
        raise BadTable(f"{meta}: the metadata of {path.name} cannot be read ({why[:200]}); {remake}") from None
    if cells != len(rows):
        raise BadTable(f"{path}: {len(rows)} rows where its metadata ({meta.name}) counts {cells} cells (a "
                       f"truncated table); {remake}")


@functools.cache
def _study_walls() -> dict[int, str]:
    """The rows of a whole ``lowest.csv``: the study's walls, in full and with ``--quick``."""
    from comparison.stability.lowest import study_cases

    return {len(study_cases()): "the study", len(study_cases(quick=True)): "the study with --quick"}


def check_tables(tables_dir: Path) -> None:
    """Read every committed table that is in ``tables_dir`` whole, before any work (a missing one is left to
    :func:`committed_table`'s warning).

    Raises:
        BadTable: a table that is there but cannot be read (:func:`read_committed`).
    """
    for name in MADE_BY:
        if os.path.lexists(Path(tables_dir) / name):  # there in any form: a FIFO or a directory is refused
            read_committed(tables_dir, name)


class MissingTableWarning(UserWarning):
    """A committed table the report needs is not in its tables directory."""


class UncountedTableWarning(UserWarning):
    """A committed sweep table without the metadata that counts its rows."""


def missing(tables_dir: Path | str, name: str) -> str:
    """The sentence a section of ``REPORT.md`` says in place of the committed table ``name`` that is not in
    ``tables_dir``: the path looked for, as the warning names it, and the command that makes it."""
    return f"The table `{Path(tables_dir) / name}` is missing: make it with `{made_by(name, tables_dir)}`."


def committed_table(tables_dir: Path, name: str) -> Path | None:
    """The path of the committed table ``name`` (:data:`ERRORMAP`, :data:`BOND`, :data:`LOWEST`) in
    ``tables_dir``, or ``None`` after a :class:`MissingTableWarning` when it is not there."""
    path = Path(tables_dir) / name
    if path.is_file():
        return path
    make = made_by(name, tables_dir)
    warnings.warn(
        f"the report's table {path} is missing, and its section says so: make it with `{make}`, or give "
        "--tables DIR (build_report(tables_dir=...)) naming the directory that holds it",
        MissingTableWarning,
        stacklevel=2,
    )
    return None
