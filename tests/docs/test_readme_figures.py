"""README.md's findings ("What the comparison shows") are the block generated from the committed report.

The block between the markers of :mod:`comparison.report.readme` must equal what its generator makes from
``reports/`` (``report.json``, ``sweeps/errormap.csv``, ``lowest.csv``): a regenerated report that moves a
figure fails here until ``python -m comparison.report.readme`` rewrites the block, and a hand edit of a
figure fails too. The generator's own rules (how a value, a bound and a count are printed, the facts a
sentence states) are checked on altered copies of the report.
"""

from __future__ import annotations

import difflib
import json
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from comparison.report import readme

ROOT = Path(__file__).resolve().parents[2]
REPORTS = ROOT / "reports"


def test_the_readme_findings_are_the_block_generated_from_the_report() -> None:
    said = readme.block((ROOT / "README.md").read_text(encoding="utf-8"))
    made = readme.findings(REPORTS, ROOT)
    diff = "\n".join(difflib.unified_diff(said.splitlines(), made.splitlines(), "README.md", "generated", lineterm=""))
    assert said == made, f"README.md's findings differ from reports/ (python -m comparison.report.readme):\n{diff}"


def _altered(tmp_path: Path, change: Callable[[dict[str, Any]], None]) -> Path:
    """A copy of ``reports/``'s data with ``change`` applied to its report.json."""
    reports = tmp_path / "reports"
    (reports / "sweeps").mkdir(parents=True)
    shutil.copy(REPORTS / "sweeps" / "errormap.csv", reports / "sweeps" / "errormap.csv")
    shutil.copy(REPORTS / "lowest.csv", reports / "lowest.csv")
    data = json.loads((REPORTS / "report.json").read_text(encoding="utf-8"))
    change(data)
    (reports / "report.json").write_text(json.dumps(data), encoding="utf-8")
    return reports


def _row(data: dict[str, Any], table: str, row: str) -> dict[str, Any]:
    return next(r for r in data["tables"][table] if r["row"] == row)


def test_a_moved_figure_moves_the_block(tmp_path: Path) -> None:
    """A figure of the data moved (Set 11's macro-micro Δ of Table 7, -7.4 -> -9.3) is the block's figure,
    as a bound; nothing else of the block changes."""
    def worse(data: dict[str, Any]) -> None:
        _row(data, "table7", "Set 11")["Δ % macro vs micro-nonassoc (lowest certified)"] = "-9.3"

    before = readme.findings(REPORTS, ROOT)
    after = readme.findings(_altered(tmp_path, worse), ROOT)
    assert "lies within 7.4 % of the micro" in " ".join(before.split())
    assert after == before.replace("within 7.4 %", "within 9.3 %")


def test_a_sentence_the_data_no_longer_bears_out_is_refused(tmp_path: Path) -> None:
    """A second wall beyond Table 7 with the macro λ below the micro one: "below it only Set 10" would be
    false, so the generator refuses, naming the sentence."""
    def second_below(data: dict[str, Any]) -> None:
        row = next(r for r in data["tables"]["all_cases"]
                   if r["row"] not in {"Set 10", "Set 11", "Set 12", "Set 13", "Set 14"}
                   and str(r["Δ % macro vs micro (non-assoc., else assoc.)"]).startswith("+"))
        row["Δ % macro vs micro (non-assoc., else assoc.)"] = "-1.0"

    with pytest.raises(readme.StaleProse, match="below it only"):
        readme.findings(_altered(tmp_path, second_below), ROOT)


@pytest.mark.parametrize(
    ("x", "bound", "value"),
    [(7.4, "7.4", "7.4"), (9.31, "9.4", "9.3"), (25.093, "25.1", "25.1"), (-0.4, "−0.4", "−0.4"), (2.0, "2.0", "2.0")],
)
def test_a_bound_never_lies_below_the_data(x: float, bound: str, value: str) -> None:
    assert readme._bound(x) == bound and readme._num(x, 1) == value


def test_the_block_is_replaced_between_its_markers() -> None:
    text = f"before\n{readme.BEGIN}\nold\n{readme.END}\nafter\n"
    assert readme.replace(text, "new\n") == f"before\n{readme.BEGIN}\nnew\n{readme.END}\nafter\n"
    with pytest.raises(ValueError, match="no block between"):
        readme.block("no markers")


def test_the_command_checks_and_rewrites_the_block(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``python -m comparison.report.readme [--check]`` as the README's marker names it: the committed README
    matches; a copy with a figure edited by hand differs (exit 1) until the command rewrites it."""
    args = ["--reports", str(REPORTS)]
    assert readme.main(["--check", "--readme", str(ROOT / "README.md"), *args]) == 0
    copy = tmp_path / "README.md"
    copy.write_text((ROOT / "README.md").read_text(encoding="utf-8").replace("within 7.4 %", "within 7 %"))
    assert readme.main(["--check", "--readme", str(copy), *args]) == 1
    assert readme.main(["--readme", str(copy), *args]) == 0
    assert copy.read_text(encoding="utf-8") == (ROOT / "README.md").read_text(encoding="utf-8")
    assert "differs from" in capsys.readouterr().out
