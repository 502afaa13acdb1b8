"""The table of tolerances in ``docs/tolerances.md`` names constants that exist, with the values they have.

Each tolerance lives beside its user in the code; the page gathers them. Every row's constant is imported
from the module the row names and compared with the value the row states, so a constant renamed, moved or
changed fails here until the page says so.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "tolerances.md"
ROW = re.compile(r"^\| `(?P<name>[a-z_][\w.]*\.[A-Z][A-Z0-9_]*)` \| (?P<value>[^|]+?) \|")


def rows() -> list[tuple[str, str]]:
    """``(dotted name, stated value)`` of every table row of the page."""
    out = []
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        m = ROW.match(line)
        if m:
            out.append((m["name"], m["value"].strip()))
    return out


ROWS = rows()


def test_the_table_is_read() -> None:
    """The parser sees the table (a page reformatted so that no row matches would check nothing), and no
    constant is listed twice."""
    assert len(ROWS) >= 40
    names = [n for n, _ in ROWS]
    assert len(names) == len(set(names))


@pytest.mark.parametrize(("name", "value"), ROWS, ids=[n for n, _ in ROWS])
def test_tolerance_exists_with_its_stated_value(name: str, value: str) -> None:
    module, constant = name.rsplit(".", 1)
    actual = getattr(importlib.import_module(module), constant, None)
    assert actual is not None, f"{name}: no such constant (moved or renamed? update docs/tolerances.md)"
    assert float(actual) == float(value), f"{name} is {actual!r}, docs/tolerances.md says {value}"
