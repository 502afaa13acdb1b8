"""The downstream example's README table is the one its generator makes from the shipped references."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_downstream_readme_table_is_generated() -> None:
    """``examples/downstream/README.md`` holds between its markers exactly what ``readme_table.table()``
    makes from ``references.json``: a regenerated reference (the value to quote moving from the iterated
    LP to the lowest certified state, say) cannot leave the README's numbers behind."""
    spec = importlib.util.spec_from_file_location("readme_table", ROOT / "examples" / "downstream" / "readme_table.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    text = (ROOT / "examples" / "downstream" / "README.md").read_text(encoding="utf-8")
    assert module.block(text) == module.table()
