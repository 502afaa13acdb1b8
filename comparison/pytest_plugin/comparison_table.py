"""The percentage table of a user's method against the references, in the style of the paper's Tables 7-9.

One row per (wall, method): the user's λ, then for each reference its λ and the
difference in percent (the user's value against the reference, one decimal,
as the paper prints it). Written as markdown (``.md``) or CSV (``.csv``); its
columns also feed ``pytest-regressions``' ``num_regression`` to guard the
user's own numbers.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from comparison.domain.cases import PaperCase
from comparison.pytest_plugin.references import (
    MissingReference,
    References,
    case_label,
    checked_name,
    received_number,
)

#: The references a table compares against unless told otherwise: our two micro LPs, Orduña's
#: micro values (Table 7) and the paper's macro model.
DEFAULT_AGAINST = ("micro-nonassoc", "micro-assoc", "orduna-micro", "paper")


@dataclass
class ComparisonTable:
    """The user's values, collected test by test, against the references.

    Attributes:
        references: the reference cells.
        against: the reference methods, one column pair each.
        entries: ``(wall, method, λ)`` in the order added.
    """

    references: References
    against: Sequence[str] = DEFAULT_AGAINST
    entries: list[tuple[PaperCase | str, str, float]] = field(default_factory=list)

    def add(self, wall: PaperCase | str, value: float, method: str = "yours") -> None:
        """Record ``method``'s load factor ``value`` on ``wall``.

        Raises:
            TypeError: ``value`` is not a number (``None``, ``"0.5"``), naming the wall, the method and what
                was received (:func:`~comparison.pytest_plugin.references.received_number`); ``wall`` or
                ``method`` of the wrong type (``None``), naming it.
        """
        label, method = case_label(wall), checked_name("method", method)
        self.entries.append((wall, method, received_number(f"{label} / {method}: xcheck_table.add", value)))

    def _reference(self, wall: PaperCase | str, method: str) -> float | None:
        try:
            return self.references.value(wall, method)
        except MissingReference:
            return None

    def header(self) -> list[str]:
        """Column names."""
        out = ["wall", "method", "λ"]
        for ref in self.against:
            out += [f"{ref} λ", f"Δ % vs {ref}"]
        return out

    def rows(self) -> list[list[Any]]:
        """One row per entry (``None`` where a reference has no value)."""
        out = []
        for wall, method, value in self.entries:
            row: list[Any] = [case_label(wall), method, value]
            for ref in self.against:
                r = self._reference(wall, ref)
                row += [r, None if r is None or not math.isfinite(value) else round(100 * (value - r) / r, 1)]
            out.append(row)
        return out

    def columns(self) -> dict[str, list[float]]:
        """The numeric columns (``NaN`` for no value), e.g. for ``num_regression.check``."""
        rows = self.rows()
        return {h: [math.nan if r[i] is None else r[i] for r in rows] for i, h in enumerate(self.header()) if i >= 2}

    def markdown(self) -> str:
        """The table in markdown."""
        head = self.header()
        lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
        for row in self.rows():
            lines.append("| " + " | ".join(_cell(c, h) for c, h in zip(row, head, strict=True)) + " |")
        return "\n".join(lines)

    def csv(self) -> str:
        """The table as CSV (empty cells for no value)."""
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(self.header())
        w.writerows([["" if c is None else c for c in r] for r in self.rows()])
        return buf.getvalue()

    def write(self, path: str | Path) -> Path:
        """Write the table: CSV for a ``.csv`` path, markdown otherwise.

        A regular file is written whole or not at all (a temporary file renamed over it), so that a full disk
        leaves no truncated table; a device (``/dev/stdout``) is written directly.

        Raises:
            OSError: the table could not be written (the file is then as it was).
        """
        p = Path(path)
        text = self.csv() if p.suffix.lower() == ".csv" else self.markdown() + "\n"
        if p.exists() and not p.is_file():
            p.write_text(text, encoding="utf-8")
            return p
        tmp = p.with_name(f".{p.name}.{os.getpid()}.tmp")
        try:
            tmp.write_text(text, encoding="utf-8")
            tmp.replace(p)
        finally:
            tmp.unlink(missing_ok=True)
        return p


def _cell(c: Any, header: str) -> str:
    if c is None:
        return "–"
    if isinstance(c, float):
        return f"{c:+.1f}" if header.startswith("Δ") else f"{c:.4f}"
    return str(c)
