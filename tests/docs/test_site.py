"""The documentation reads as its Markdown meant: every table has rows, every heading stands apart.

``mkdocs build --strict`` catches broken links and docstrings, not Markdown that renders wrong: a blank
line after a table's delimiter row renders a table whose only row is empty, its rows left as a paragraph
of ``|`` text. This test parses every HTML page of the site: the one ``.ci/run`` built
(``XCHECK_SITE=site``), else one built here where MkDocs is installed (the ``docs`` extra); without
either it is skipped. A heading written on the line right after a paragraph renders, but reads as part
of it in the source and in other renderers: the pages' Markdown is checked for that.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: A line of a Markdown table left as paragraph text.
TABLE_ROW_TEXT = re.compile(r"(^|\n)\s*\|.*\|\s*($|\n)")


class _Page(HTMLParser):
    """Collects the problems of one page: tables without a non-empty body row, table rows left as text."""

    def __init__(self) -> None:
        super().__init__()
        self.problems: list[str] = []
        self._tables: list[int] = []  # per open table: body rows with some text
        self._in_thead = self._in_code = 0
        self._row: list[str] | None = None
        self._p_text: list[str] | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "table":
            self._tables.append(0)
        elif tag == "thead":
            self._in_thead += 1
        elif tag == "tr" and self._tables and not self._in_thead:
            self._row = []
        elif tag == "p":
            self._p_text = []
        elif tag in ("code", "pre"):
            self._in_code += 1

    def handle_endtag(self, tag: str) -> None:
        if tag == "table" and self._tables:
            if self._tables.pop() == 0:
                self.problems.append("a table with no non-empty body row")
        elif tag == "thead":
            self._in_thead -= 1
        elif tag == "tr" and self._row is not None:
            self._tables[-1] += bool("".join(self._row).strip())
            self._row = None
        elif tag == "p" and self._p_text is not None:
            text = "".join(self._p_text)
            if TABLE_ROW_TEXT.search(text):
                self.problems.append(f"table rows left as a paragraph: {text.strip()[:80]!r}")
            self._p_text = None
        elif tag in ("code", "pre"):
            self._in_code -= 1

    def handle_data(self, data: str) -> None:
        if self._row is not None:
            self._row.append(data)
        if self._p_text is not None:
            self._p_text.append(data)


def problems(html: str) -> list[str]:
    """What renders wrong in one HTML page (empty tables, headings left in paragraphs)."""
    page = _Page()
    page.feed(html)
    return page.problems


def glued_headings(markdown: str) -> list[int]:
    """The lines (1-based) of headings written right after a line of text, outside code fences."""
    found, fenced, previous = [], False, ""
    for number, line in enumerate(markdown.splitlines(), 1):
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and re.match(r"#{1,6} ", line) and previous.strip() and not previous.startswith("<!--"):
            found.append(number)
        previous = "" if line.startswith("```") else line
    return found


def test_the_checks_find_the_faults_of_the_old_back_end_table() -> None:
    """Two faults a page's table can have as Python-Markdown renders it (a blank line after the delimiter
    row: a table without rows, and its rows as a paragraph) are reported; the corrected forms are not."""
    empty = ("<table><thead><tr><th>back end</th><th>what it is</th></tr></thead>"
             "<tbody><tr><td></td><td></td></tr></tbody></table>"
             "<p>| <code>highs-ipm</code> | HiGHS interior point |\n| <code>clarabel</code> | Clarabel |</p>")
    good = ("<table><thead><tr><th>a</th></tr></thead><tbody><tr><td>1</td></tr></tbody></table>"
            "<p>a paragraph with a <code>|x|</code> in it</p>")
    found = problems(empty)
    assert found[0] == "a table with no non-empty body row" and len(found) == 2
    assert found[1].startswith("table rows left as a paragraph: '| highs-ipm | HiGHS interior point |")
    assert problems(good) == []
    assert glued_headings("Speed: see the page.\n## The default back end\n") == [2]
    assert glued_headings("Speed.\n\n## Heading\n```sh\n# a comment\n## not a heading\n```\n") == []


def test_no_heading_is_glued_to_the_text_before_it() -> None:
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    glued = {str(p.relative_to(ROOT)): lines for p in pages if (lines := glued_headings(p.read_text()))}
    assert not glued


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    given = os.environ.get("XCHECK_SITE")
    if given:
        return Path(given) if Path(given).is_absolute() else ROOT / given
    if shutil.which("mkdocs") is None and not (Path(sys.executable).parent / "mkdocs").exists():
        pytest.skip("MkDocs is not installed (the docs extra); .ci/run checks the site it builds")
    out = tmp_path_factory.mktemp("site")
    mkdocs = Path(sys.executable).parent / "mkdocs"
    subprocess.run([str(mkdocs) if mkdocs.exists() else "mkdocs", "build", "--strict", "--quiet", "--site-dir",
                    str(out)], cwd=ROOT, check=True, capture_output=True)
    return out


def test_every_page_of_the_site_renders_its_tables_and_headings(site: Path) -> None:
    pages = sorted(site.rglob("*.html"))
    assert len(pages) > 10, f"no site at {site}"
    found = {str(p.relative_to(site)): problems(p.read_text(encoding="utf-8")) for p in pages}
    assert not {k: v for k, v in found.items() if v}
