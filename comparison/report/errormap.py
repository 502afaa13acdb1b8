"""The error map: where the macro model is unsafe, from the committed sweep table.

The section is the validation page ``xcheck sweep`` writes for any grid
(:func:`comparison.sweep.page.render`), drawn from the committed sweep table
``sweeps/errormap.csv`` of the report's tables directory
(:mod:`comparison.report.committed`; written by ``xcheck sweep
examples/sweeps/errormap.toml --out reports/sweeps``; the report does not
recompute it) as a section of ``REPORT.md``, its figures numbered on from the
report's: the summary and the cells without a value, the error map over
``(t, m)`` (one panel per number of rows and storeys), the macro-against-micro
scatter, the histogram of the differences, the worst walls and the micro
computations' time against their blocks. One code path: a change to the page
changes this section.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from comparison.sweep.page import render
from comparison.sweep.table import read_table
from comparison.sweep.wall_comparisons import Wall, walls

#: The committed table, as the section names it.
SOURCE = "reports/sweeps/errormap.csv"
#: The section's heading.
TITLE = "Error map: where the macro model is unsafe"
#: The paper's macro model's column, whose numbers ``report.json`` keeps.
MACRO = "macro"


def load(path: Path) -> list[Wall]:
    """The walls of a sweep table with their macro and micro load factors
    (:func:`comparison.sweep.wall_comparisons.walls`)."""
    return walls(read_table(path))


def write(out: Path, table: Path | None, number: int | None = None, missing: str = "") -> tuple[str, dict[str, Any]]:
    """Draw the section's figures (``errormap-*.png``) into ``out``; the section's markdown and its numbers
    (for ``report.json``: the macro model's ``summary`` and ``worst`` walls, the cells by method and
    ``statuses``, the ``figures`` drawn).

    Without the committed table (``None``: :func:`~comparison.report.committed.committed_table` warned)
    the section says so (``missing``: the sentence naming the path looked for,
    :func:`~comparison.report.committed.missing`) and nothing is drawn. ``number``: the number of its first
    figure in the report.
    """
    if table is None or not table.exists():
        return f"## Error map\n\n{missing or 'The committed sweep table is missing.'}\n", {}
    intro = (
        f"From the committed sweep `{SOURCE}` (`xcheck sweep examples/sweeps/errormap.toml --out reports/sweeps`; "
        "the report reads it and does not recompute it), drawn as `xcheck sweep` draws the validation page of "
        "any grid."
    )
    page = render(read_table(table), out, title=TITLE, intro=intro, prefix="errormap", source=SOURCE, level=2,
                  first_figure=1 if number is None else number)
    numbers = {
        "summary": page.numbers["columns"].get(MACRO, {}),
        "worst": page.numbers["worst"].get(MACRO, []),
        "statuses": page.numbers["statuses"],
        "figures": [p.name for p in page.figures],
    }
    return page.text, numbers
