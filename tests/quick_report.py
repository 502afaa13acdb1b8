"""The shared quick report's record and its build (the fixtures are in ``tests/conftest.py``)."""

from __future__ import annotations

import contextlib
import io
from dataclasses import dataclass
from pathlib import Path

from comparison.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: The committed report, whose tables (sweeps/errormap.csv, ...) the report's sections read.
REPORTS = ROOT / "reports"


@dataclass(frozen=True)
class QuickReport:
    """One ``xcheck report --quick --verbose`` run from an empty cache.

    Attributes:
        out: the report's directory (``REPORT.md``, ``report.json``, the CSVs and figures).
        cache: the result cache it filled (read it through a copy: :func:`quick_report_cache`).
        stdout: what the command printed on standard output.
        stderr: what it printed on standard error (the plan first, then one line per computation).
    """

    out: Path
    cache: Path
    stdout: str
    stderr: str


def build(root: Path) -> QuickReport:
    """Run ``xcheck report --quick --verbose`` into ``root/report`` with an empty cache ``root/cache``."""
    out, cache = root / "report", root / "cache"
    o, e = io.StringIO(), io.StringIO()
    argv = ["report", "--quick", "--out", str(out), "--tables", str(REPORTS), "--cache", str(cache), "--verbose"]
    with contextlib.redirect_stdout(o), contextlib.redirect_stderr(e):
        code = main(argv)
    assert code == 0, f"xcheck report --quick exited with {code}:\n{e.getvalue()[-3000:]}"
    return QuickReport(out, cache, o.getvalue(), e.getvalue())
