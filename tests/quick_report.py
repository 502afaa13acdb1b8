"""The runs shared by the suite, their records and builds (the fixtures are in ``tests/conftest.py``)."""

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


#: The grid of the documentation's own-walls example (``docs/getting-started.md``, ``docs/sweeps.md``).
OWN_WALLS = ROOT / "examples" / "own-walls" / "walls.toml"
#: The tiny grid of the README's sweep example and of the sweep tests.
TINY = ROOT / "examples" / "sweeps" / "tiny.toml"


@dataclass(frozen=True)
class Sweep:
    """One ``xcheck sweep`` run from an empty cache: its output folder and the cache it filled."""

    out: Path
    cache: Path


def sweep(grid: Path, root: Path, *extra: str) -> Sweep:
    """Run ``xcheck sweep GRID -q EXTRA`` into ``root/out`` with an empty cache ``root/cache``."""
    out, cache = root / "out", root / "cache"
    code = main(["sweep", str(grid), "--out", str(out), "--cache", str(cache), "-q", *extra])
    assert code == 0, f"xcheck sweep {grid} exited with {code}"
    return Sweep(out, cache)
