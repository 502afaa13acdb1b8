"""The report's sections behind one protocol: figures numbered on in one place, records under their names."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from comparison.report import sections
from comparison.report.sections import Bond, ErrorMap, Lowest, Rendered, render


@dataclass(frozen=True)
class Fake:
    """A section drawing ``drawn`` figures and keeping ``record``; it writes the numbers it was given."""

    name: str
    drawn: int
    record: object = None

    def render(self, out: Path, first_figure: int) -> Rendered:
        figures = tuple(f"{self.name}-{i}.png" for i in range(self.drawn))
        numbers = ", ".join(str(first_figure + i) for i in range(self.drawn))
        return Rendered(f"{self.name}: figures {numbers}\n", figures, figures, self.record)


def test_each_section_numbers_its_figures_on_from_the_last() -> None:
    text, records = render([Fake("a", 2, {"x": 1}), Fake("b", 0, []), Fake("c", 3), Fake("d", 1, 0)], Path("."))
    assert text == "a: figures 1, 2\n\nb: figures \n\nc: figures 3, 4, 5\n\nd: figures 6\n"
    assert records == {"a": {"x": 1}, "b": [], "d": 0}  # c keeps no record; an empty one is kept


def test_the_committed_sections_without_their_tables_say_so_and_draw_nothing(tmp_path: Path) -> None:
    """A missing committed table: each section says so, draws nothing (the next figure keeps its number) and
    keeps the record report.json has always held for it."""
    done = {s.name: s.render(tmp_path, 9) for s in (ErrorMap(None), Bond(None), Lowest(tmp_path / "none.csv"))}
    assert all("missing" in d.text and d.figures == () and d.files == () for d in done.values())
    assert [d.record for d in done.values()] == [{}, [], None]
    assert not any(tmp_path.iterdir())


def test_the_report_is_the_body_and_the_three_committed_sections_in_order(quick_report_dir: Path) -> None:
    """report.json holds the run's meta, then each section's record under its name, in the sections' order;
    REPORT.md their texts in that order."""
    report = json.loads((quick_report_dir / "report.json").read_text())
    assert list(report) == ["meta", sections.Body.name, ErrorMap.name, Bond.name]
    text = (quick_report_dir / "REPORT.md").read_text()
    headings = ["## Findings", "## Error map", "## Table 9's walls with coarser bonds", "## Table 7: iterated LP"]
    at = [text.find(h) for h in headings]
    assert -1 not in at and at == sorted(at), dict(zip(headings, at, strict=True))


def test_a_missing_table_is_named_in_the_report_as_the_warning_names_it(tmp_path: Path) -> None:
    """A missing committed table: its section of REPORT.md names the path looked for (the ``--tables``
    folder) and the command that makes it, as the warning does."""
    import warnings

    from comparison.report.committed import BOND, ERRORMAP, LOWEST, committed_table, made_by, missing

    tables = tmp_path / "my-tables"
    for cls, name in ((ErrorMap, ERRORMAP), (Bond, BOND), (Lowest, LOWEST)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            found = committed_table(tables, name)
        path = str(tables / name)
        assert found is None and path in str(caught[0].message)
        text = cls(found, missing(tables, name)).render(tmp_path / "out", 1).text  # type: ignore[operator]
        assert f"`{path}` is missing: make it with `{made_by(name, tables)}`" in text and "reports/" not in text
