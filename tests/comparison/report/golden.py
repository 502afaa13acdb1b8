"""The quick report's golden cells: how they are read, their tolerances, and the script that rewrites them.

``golden_quick.json`` holds, for every number the quick report shows (run times excepted), its value and
its tolerance, keyed ``table / row / column``; text cells are pinned exactly (tolerance ``null``). The
tolerance of a cell is that of its quantity (:func:`tolerance`, from the named constants below).
``test_report_golden.py`` checks a quick report against the file; this script rewrites it, only for a
change meant to move numbers (say why in the commit)::

    python tests/comparison/report/golden.py            # builds a quick report from scratch (about a minute)
    python tests/comparison/report/golden.py --report DIR   # from a quick report already in DIR
    python tests/comparison/report/golden.py --check        # compare only, write nothing (exit 1 if moved)
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from pathlib import Path
from typing import Any

GOLDEN = Path(__file__).with_name("golden_quick.json")
REPORTS = Path(__file__).resolve().parents[3] / "reports"

#: A percentage difference (``Δ %`` columns) is printed to one decimal: half a unit of it, and a hair more.
PERCENT_TOLERANCE = 0.051
#: Failure modes: the crack angle (degrees) is read from a drawn mechanism, to about a degree.
ANGLE_TOLERANCE = 1.0
#: Failure modes: counts of opening and sliding contacts, 2 % of the count (at least one contact).
CONTACT_COUNT_RELATIVE = 0.02
#: The iterated LP's load factors and counts (relative, at least 1 absolute unit of it): it stops when λ
#: settles to about 1e-5, and its descent's states are certified to that.
NONASSOC_RELATIVE = 1e-4
#: Every other number (the macro model's closed forms, the associative LP's optimum; relative, at least
#: 1 absolute unit of it): printed to seven significant digits, solved to about 1e-8.
LP_RELATIVE = 2e-6


def tolerance(table: str, column: str, value: float) -> float | None:
    """The tolerance of a number of ``table``'s ``column`` pinned at ``value``; ``None`` for run times,
    which are not pinned."""
    if "seconds" in column or column.endswith(" s"):
        return None
    if column.startswith("Δ %"):
        return PERCENT_TOLERANCE
    if table == "failure_modes":
        return ANGLE_TOLERANCE if "angle" in column or "α" in column else max(1.0, CONTACT_COUNT_RELATIVE * abs(value))
    if "nonassoc" in column or "nonassoc" in table:
        return NONASSOC_RELATIVE * max(1.0, abs(value))
    return LP_RELATIVE * max(1.0, abs(value))


def _number(v: Any) -> float | None:
    if isinstance(v, bool):
        return None
    if isinstance(v, (int, float)):
        return float(v)
    if isinstance(v, str):
        try:
            return float(v)
        except ValueError:
            return None
    return None


def cells(report: dict[str, Any]) -> dict[str, float | str]:
    """Every cell of ``report.json``'s tables by ``table / row / column``: numbers as floats (``"nan"``
    for a missing one), text as it is."""
    out: dict[str, float | str] = {}
    for table, rows in report["tables"].items():
        for row in rows:
            for column, value in row.items():
                if column == "row":
                    continue
                key = f"{table} / {row['row']} / {column}"
                x = _number(value)
                out[key] = value if x is None and value is not None else ("nan" if x is None or math.isnan(x) else x)
    return out


def pinned(report: dict[str, Any]) -> dict[str, list[Any]]:
    """The golden file's content for ``report``: ``[value, tolerance]`` per pinned cell."""
    out: dict[str, list[Any]] = {}
    for key, v in cells(report).items():
        table, column = key.split(" / ", 1)[0], key.rsplit(" / ", 1)[1]
        if isinstance(v, float):
            tol = tolerance(table, column, v)
            if tol is not None:
                out[key] = [v, tol]
        else:
            out[key] = [v, None]
    return out


def dumps(golden: dict[str, list[Any]]) -> str:
    """The golden file's text: one cell a line, sorted by key."""
    lines = [f"  {json.dumps(k, ensure_ascii=False)}: {json.dumps(v)}" for k, v in sorted(golden.items())]
    return "{\n" + ",\n".join(lines) + "\n}\n"


def moved(report: dict[str, Any], golden: dict[str, list[Any]]) -> list[str]:
    """The cells of ``report`` that moved from ``golden`` beyond their tolerance (or went missing)."""
    got = cells(report)
    problems = []
    for key, (value, tol) in golden.items():
        if key not in got:
            problems.append(f"{key}: missing from the report")
            continue
        cell = got[key]
        if tol is None:
            if cell != value:
                problems.append(f"{key}: {cell!r} != pinned {value!r}")
        elif not isinstance(cell, float) or not abs(cell - value) <= tol:
            problems.append(f"{key}: {cell!r} vs pinned {value!r} ± {tol:g}")
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--report", type=Path, help="a quick report's folder (default: build one from scratch)")
    parser.add_argument("--check", action="store_true", help="compare with the golden file, write nothing")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.report
        if folder is None:
            from comparison.report import build_report

            folder = Path(tmp)
            build_report(folder, quick=True, cache_dir=None, tables_dir=REPORTS)
        report = json.loads((folder / "report.json").read_text())
    if args.check:
        problems = moved(report, json.loads(GOLDEN.read_text()))
        print("\n".join(problems) or "no cell moved")
        return 1 if problems else 0
    GOLDEN.write_text(dumps(pinned(report)))
    print(f"wrote {GOLDEN}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
