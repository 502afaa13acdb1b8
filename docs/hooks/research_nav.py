"""MkDocs hook: every dated page of ``docs/research/`` goes into the navigation under "Research log",
newest first, so that a new study needs no edit of ``mkdocs.yml``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

SECTION = "Research log"


def _title(path: Path) -> str:
    """The page's first heading (``# 2026-11-24: The fused wall ...``), else its file name."""
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    return path.stem


def on_config(config: Any) -> Any:
    """Append ``research/*.md`` (but the index) to the "Research log" section of the navigation."""
    docs = Path(config["docs_dir"])
    pages = sorted((p for p in (docs / "research").glob("*.md") if p.name != "index.md"), reverse=True)
    for entry in config["nav"] or []:
        if isinstance(entry, dict) and SECTION in entry:
            entry[SECTION] = ["research/index.md"] + [
                {_title(p): f"research/{p.name}"} for p in pages
            ]
    return config
