"""The research log's scripts (``docs/research/*.py``) still import against today's package.

A page's figures are kept as measured, but its script is how a reader reproduces them: a script whose
imports name a module that moved fails here rather than in the reader's hands. Importing runs no
experiment (each script's work sits under ``if __name__ == "__main__"``).
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = sorted((ROOT / "docs" / "research").glob("*.py"))


def test_there_are_scripts() -> None:
    assert SCRIPTS


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.name for p in SCRIPTS])
def test_research_script_imports(script: Path) -> None:
    assert 'if __name__ == "__main__":' in script.read_text(encoding="utf-8"), f"{script.name} runs on import"
    spec = importlib.util.spec_from_file_location(script.stem.replace("-", "_"), script)
    assert spec is not None and spec.loader is not None
    spec.loader.exec_module(importlib.util.module_from_spec(spec))


#: A file of the package, its tests or its examples named on a page (not a link between pages).
NAMED = re.compile(r"(?<![\w./])((?:macro|micro|comparison|tests|examples)/[\w./-]+\.(?:py|toml|json|csv))\b")
PAGES = sorted((ROOT / "docs" / "research").glob("*.md"))


@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_files_a_research_page_names_exist_or_say_where_they_went(page: Path) -> None:
    """A page keeps the file names of its date; each one that no longer exists is listed in the page's
    table of files that have since moved or left, with what replaced it."""
    text = page.read_text(encoding="utf-8")
    body, _, moved = text.partition("## Files named here that have since moved or left")
    gone = sorted({f for f in NAMED.findall(body) if not (ROOT / f).exists()})
    unexplained = [f for f in gone if f"| `{f}` |" not in moved]
    assert not unexplained, f"{page.name} names files that no longer exist, without saying what replaced them"
