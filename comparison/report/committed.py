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
import io
import json
import math
import shlex
import warnings
from collections.abc import Mapping
from pathlib import Path

from comparison.sweep import grids

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


#: The columns each section reads, and what each must hold: ``"text"``, ``"number"`` (a float, ``nan`` or
#: empty) or ``"count"`` (an integer or empty).
_SWEEP: Mapping[str, str] = {
    **dict.fromkeys(("t", "m", "f", "p", "load_factor"), "number"),
    **dict.fromkeys(("rows", "storeys", "blocks", "iterations"), "count"),
    **dict.fromkeys(("kind", "status", "first_course"), "text"),
}
COLUMNS: Mapping[str, Mapping[str, str]] = {
    ERRORMAP: _SWEEP,
    BOND: _SWEEP,
    LOWEST: {
        **dict.fromkeys(("group", "wall", "global_status"), "text"),
        **dict.fromkeys(("orduna", "lambda_iterated", "lambda_lowest", "global_best", "global_bound", "global_gap",
                         "iterated_seconds", "lowest_seconds", "global_seconds", "iterated_over_global",
                         "iterated_over_lowest"), "number"),
        "lowest_moves": "count",
    },
}


class BadTable(ValueError):
    """A committed table that cannot be read whole; the message names the file, the line and how to remake it."""


def _bad_cell(kind: str, text: str) -> bool:
    if kind == "text" or not text:
        return False
    try:
        x = float(text)
    except ValueError:
        return True
    return kind == "count" and not (math.isfinite(x) and x.is_integer())


def read_committed(tables_dir: Path, name: str) -> list[dict[str, str]]:
    """The rows of the committed table ``name`` (:data:`ERRORMAP`, :data:`BOND`, :data:`LOWEST`) of
    ``tables_dir``, checked whole.

    Raises:
        BadTable: not UTF-8 text (binary junk), not ending with a line break (cut short), without a
            column its section reads, without rows, a row with another number of fields than the
            header, or a number or count that is none; the message names the file and the line.
    """
    path = Path(tables_dir) / name
    remake = f"remake it with `{made_by(name, tables_dir)}`"
    try:
        text = path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BadTable(f"{path}: not a text table (byte {exc.start} is not UTF-8); {remake}") from None
    except OSError as exc:
        raise BadTable(f"{path}: cannot be read ({exc.strerror or exc})") from None
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
            what = "an integer" if COLUMNS[name][bad[0]] == "count" else "a number"
            raise BadTable(f"{path}:{i}: {bad[0]} must be {what}, got {record[bad[0]]!r}; {remake}")
        out.append(record)
    _whole(path, name, out, remake)
    return out


def _whole(path: Path, name: str, rows: list[dict[str, str]], remake: str) -> None:
    """A sweep table cut at a line break still reads: its metadata (``errormap.json`` beside
    ``errormap.csv``, written by the same run) counts its cells.

    Raises:
        BadTable: fewer or more rows than the metadata's cells.
    """
    if COLUMNS[name] is not _SWEEP:
        return
    meta = path.with_suffix(".json")
    try:
        cells = json.loads(meta.read_text(encoding="utf-8"))["counts"]["cells"]
    except (OSError, ValueError, KeyError, TypeError):
        return  # no metadata beside it: nothing to count against
    if isinstance(cells, int) and cells != len(rows):
        raise BadTable(f"{path}: {len(rows)} rows where its metadata ({meta.name}) counts {cells} cells (a "
                       f"truncated table); {remake}")


def check_tables(tables_dir: Path) -> None:
    """Read every committed table that is in ``tables_dir`` whole, before any work (a missing one is left to
    :func:`committed_table`'s warning).

    Raises:
        BadTable: a table that is there but cannot be read (:func:`read_committed`).
    """
    for name in MADE_BY:
        if (Path(tables_dir) / name).is_file():
            read_committed(tables_dir, name)


class MissingTableWarning(UserWarning):
    """A committed table the report needs is not in its tables directory."""


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
