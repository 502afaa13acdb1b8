"""Errors about a TOML input file (a scene, a grid) worded with the line of the key or table they are about.

:func:`comparison.utilities.inputs.parse_toml` reads such a file; :class:`TomlSource` keeps its text to
find, for a message, the line of a key (:func:`key_line`) or of a table's header (:func:`table_line`).
"""

from __future__ import annotations

import re
from typing import Generic, TypeVar

__all__ = ["TomlSource", "key_line", "table_line"]

#: The error a :class:`TomlSource` words (``SceneError``, ``GridError``).
E = TypeVar("E", bound=Exception)


def key_line(text: str, table: str, key: str, index: int = 0) -> int | None:
    """Line number (1-based) of ``key`` inside the ``index``-th ``[table]``."""
    current, seen = "", -1
    header = re.compile(r"^\s*\[\[?\s*([A-Za-z0-9_.\-\"]+)\s*\]\]?")
    assign = re.compile(r"^\s*([A-Za-z0-9_\-\"]+)\s*=")
    for number, line in enumerate(text.splitlines(), start=1):
        h = header.match(line)
        if h:
            current = h.group(1).strip('"')
            if current == table:
                seen += 1
            continue
        a = assign.match(line)
        if a and a.group(1).strip('"') == key and current == table and (table == "" or seen == index):
            return number
    return None


def table_line(text: str, table: str, index: int = 0) -> int | None:
    """Line number (1-based) of the ``index``-th ``[table]`` (or ``[[table]]``) header."""
    seen = -1
    for number, line in enumerate(text.splitlines(), start=1):
        if re.match(rf"^\s*\[\[?\s*{re.escape(table)}\s*\]\]?", line):
            seen += 1
            if seen == index:
                return number
    return None


class TomlSource(Generic[E]):
    """The text of a TOML input file, its name and what it is (``kind``: "scene", "grid"), to word an error
    as ``error`` with the line of the key or table it is about."""

    def __init__(self, text: str, source: str, kind: str, error: type[E]) -> None:
        self.text, self.source, self.kind, self._error = text, source, kind, error

    def error(self, msg: str, table: str = "", key: str | None = None, index: int = 0) -> E:
        """``msg`` about ``key`` of the ``index``-th ``[table]`` (the table itself without ``key``), as
        ``"<kind> <source> (line N): msg"``; without the line where it cannot be found."""
        line = key_line(self.text, table, key, index) if key else table_line(self.text, table, index)
        where = f" (line {line})" if line else ""
        return self._error(f"{self.kind} {self.source}{where}: {msg}")
