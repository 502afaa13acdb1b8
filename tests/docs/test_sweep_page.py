"""The validation page the docs show is the one the example grid gives.

``docs/getting-started.md`` walks through ``examples/own-walls/`` (its grid and model shown as they are
in the files; its command is run by ``test_examples``), and ``docs/sweeps.md`` quotes the page's summary
table and shows two of its figures (``docs/figures/``). Here the example's sweep is run and its page
read: the quoted rows are the page's, and the figures the docs show are the page's figures.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from quick_report import Sweep

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "own-walls"
FIGURES = ("own-walls-map-wedge.png", "own-walls-scatter.png")


def _blocks(page: str, language: str) -> list[str]:
    text = (ROOT / "docs" / page).read_text(encoding="utf-8")
    return [m.group(1) for m in re.finditer(rf"^```{language}\n(.*?)^```", text, re.S | re.M)]


def test_getting_started_shows_the_example_as_it_is() -> None:
    assert (EXAMPLE / "walls.toml").read_text() in _blocks("getting-started.md", "toml")
    assert (EXAMPLE / "wedge.py").read_text() in _blocks("getting-started.md", "python")
    assert "xcheck sweep examples/own-walls/walls.toml --out validation" in _blocks("getting-started.md", "sh")[-1]


@pytest.fixture(scope="module")
def page(own_walls_sweep: Sweep) -> Path:
    """The folder of the example's sweep and page (run once per pytest run: ``tests/conftest.py``)."""
    return own_walls_sweep.out


def test_the_summary_the_docs_quote_is_the_pages(page: Path) -> None:
    text = (page / "own-walls.md").read_text()
    quoted = [b for b in _blocks("sweeps.md", "text") if b.startswith("| macro column |")]
    assert len(quoted) == 1
    for line in quoted[0].splitlines():
        assert line in text.splitlines(), f"docs/sweeps.md quotes a row the page does not have: {line}"


def test_the_figures_the_docs_show_are_the_pages(page: Path) -> None:
    """The same figures: the same size in pixels, and the page links them (regenerate ``docs/figures/`` from
    the page when this fails)."""
    import matplotlib.image as mpimg

    sweeps = (ROOT / "docs" / "sweeps.md").read_text()
    text = (page / "own-walls.md").read_text()
    for name in FIGURES:
        assert f"(figures/{name})" in sweeps and f"]({name})" in text
        assert mpimg.imread(ROOT / "docs" / "figures" / name).shape == mpimg.imread(page / name).shape, name
