"""The report's sections behind one protocol: a name, a render step, the files it writes.

``REPORT.md`` is its sections' texts in order, ``report.json`` their records under their names
(:class:`Section`). :func:`render` is the one place that numbers the figures: each section is given
the number of its first figure and says which figures it drew, so the next one numbers on. The
sections are the report's body (tables, its own figures, findings and the text around them:
:class:`Body`) and the three read from committed tables the report does not recompute
(:class:`ErrorMap`, :class:`Bond`, :class:`Lowest`; :mod:`comparison.report.committed`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

from comparison.report import bond, errormap, figures, lowest
from comparison.report.computed import Results
from comparison.report.figures import Figure
from comparison.report.findings import findings
from comparison.report.mechanisms import mechanism_figures
from comparison.report.scaling import scaling_figure
from comparison.report.tables import Table
from comparison.report.text import document


@dataclass(frozen=True)
class Rendered:
    """What a section rendered into the report's folder.

    Attributes:
        text: its markdown in ``REPORT.md``.
        figures: the numbered figures it drew, in their order (file names in the folder).
        files: every file it wrote into the folder (its figures among them).
        record: its entry of ``report.json`` under the section's name (``None``: no entry).
    """

    text: str
    figures: tuple[str, ...] = ()
    files: tuple[str, ...] = ()
    record: Any = None


class Section(Protocol):
    """One section of the report."""

    @property
    def name(self) -> str:
        """Its key in ``report.json`` (for its :attr:`Rendered.record`)."""
        ...

    def render(self, out: Path, first_figure: int) -> Rendered:
        """Write the section's files into ``out``, its figures numbered from ``first_figure``."""
        ...


@dataclass(frozen=True)
class Body:
    """The report's own section: the tables computed by this run (one CSV each), their figures, the
    findings and the text around them (:func:`comparison.report.text.document`)."""

    res: Results
    tables: Mapping[str, Table]
    meta: Mapping[str, Any]
    name: str = "tables"

    def render(self, out: Path, first_figure: int) -> Rendered:
        hist = figures.histories_figure(self.res, out / "histories.png")
        scaling = scaling_figure(self.res, out / "scaling.png")
        drawn: list[Figure] = [
            figures.sensitivity_figure(self.res, out / "sensitivity.png"),
            figures.speed_figure(self.res, out / "speed_accuracy.png"),
            *([] if hist is None else [hist]),
            *([] if scaling is None else [scaling]),
            *mechanism_figures(self.res, out),
        ]
        for tb in self.tables.values():
            tb.write_csv(out / f"{tb.name}.csv")
        text = document(self.res, self.tables, findings(self.res), drawn, self.meta, first_figure=first_figure)
        names = tuple(f.name for f in drawn)
        csvs = tuple(f"{tb.name}.csv" for tb in self.tables.values())
        return Rendered(text, names, names + csvs, {k: v.records() for k, v in self.tables.items()})


@dataclass(frozen=True)
class ErrorMap:
    """The error map from the committed sweep table (:mod:`comparison.report.errormap`; ``None``: missing)."""

    table: Path | None
    missing: str = ""
    name: str = "errormap"

    def render(self, out: Path, first_figure: int) -> Rendered:
        text, numbers = errormap.write(out, self.table, number=first_figure, missing=self.missing)
        drawn = tuple(numbers.get("figures", ()))
        return Rendered(text, drawn, drawn, numbers)


@dataclass(frozen=True)
class Bond:
    """Table 9's walls with coarser bonds, from the committed sweep table (:mod:`comparison.report.bond`)."""

    table: Path | None
    missing: str = ""
    name: str = "table9_bond"

    def render(self, out: Path, first_figure: int) -> Rendered:
        text, rows = bond.section(self.table, self.missing)
        return Rendered(text, record=rows)


@dataclass(frozen=True)
class Lowest:
    """Table 7 with the lowest collapse load, from the committed study (:mod:`comparison.report.lowest`);
    no entry in ``report.json`` (its numbers are the committed table's)."""

    table: Path | None
    missing: str = ""
    name: str = "lowest"

    def render(self, out: Path, first_figure: int) -> Rendered:
        text = lowest.section(self.table, out=out, number_=first_figure, missing=self.missing)
        drawn = ("lowest.png",) if self.table is not None and self.table.exists() else ()  # drawn with its rows
        return Rendered(text, drawn, drawn)


def render(sections: Iterable[Section], out: Path) -> tuple[str, dict[str, Any]]:
    """Render ``sections`` in order into ``out``, numbering their figures on from 1: ``REPORT.md``'s text
    (the sections' texts, one blank line apart) and ``report.json``'s entries by section name."""
    texts: list[str] = []
    records: dict[str, Any] = {}
    number = 1
    for section in sections:
        done = section.render(out, number)
        number += len(done.figures)
        texts.append(done.text)
        if done.record is not None:
            records[section.name] = done.record
    return "\n".join(texts), records
