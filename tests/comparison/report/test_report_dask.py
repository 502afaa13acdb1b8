"""``xcheck report --scheduler``: every micro computation of the report a Dask task, the same report."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.report.timings import TIMING_FILES

REPORTS = Path(__file__).resolve().parents[3] / "reports"


#: Cache entries of each micro method left for the cluster to compute (the smallest walls).
ON_THE_CLUSTER = 4


def _forget_smallest(cache: Path, per_method: int) -> int:
    """Remove from ``cache`` the records (and their mechanisms) of the ``per_method`` smallest walls of each
    micro method; how many were removed."""
    removed = 0
    for method in sorted(p for p in cache.iterdir() if p.is_dir()):
        entries = [(json.loads(f.read_text()), f) for f in method.glob("*.json")]
        for entry, f in sorted(entries, key=lambda e: (e[0]["record"]["result"]["blocks"], e[1].name))[:per_method]:
            (method / entry["mechanism"]["file"]).unlink(missing_ok=True)
            f.unlink()
            removed += 1
    return removed


@pytest.mark.processes  # a cluster's processes, and a second report: the processes tier, not the fast suite
def test_the_quick_report_on_a_dask_cluster_is_the_local_report(
    quick_report_dir: Path, quick_report_cache: Path, dask_scheduler: str, tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """On a loopback cluster (one worker) the report's plan says where it computes, the micro computations
    missing from its cache (the smallest walls of each method, from a copy of the shared report's cache) are
    computed there, and every file but the run times is the shared local report's (``tests/conftest.py``),
    byte for byte: where a result is computed does not change the report. (The whole report computed a
    second time from scratch: ``test_report_reproducible.py``.)"""
    missing = _forget_smallest(quick_report_cache, ON_THE_CLUSTER)
    assert missing == 2 * ON_THE_CLUSTER  # both micro methods
    out = tmp_path / "report"
    argv = ["report", "--quick", "--out", str(out), "--tables", str(REPORTS), "--cache", str(quick_report_cache),
            "--scheduler", dask_scheduler]
    assert main(argv) == 0
    err = capsys.readouterr().err
    plan = next(line for line in err.splitlines() if line.startswith("plan: "))
    assert plan.endswith(f" cached, {missing} to compute on {dask_scheduler}"), plan
    run = json.loads((out / "timings.json").read_text())["run"]
    planned = int(plan.split(" micro computations")[0].rsplit(" ", 1)[1])
    assert run["computed"] == missing and run["cached"] == planned - missing
    names = sorted(p.name for p in quick_report_dir.iterdir())
    assert names == sorted(p.name for p in out.iterdir())
    differ = [n for n in names
              if n not in TIMING_FILES and (quick_report_dir / n).read_bytes() != (out / n).read_bytes()]
    assert not differ, f"files that differ from the local report's: {differ}"


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        (["--scheduler", "tcp://127.0.0.1:1", "--no-cache"], "--scheduler and --no-cache exclude each other"),
        (["--scheduler", "tcp://127.0.0.1:1", "--workers", "1"], "--workers and --scheduler exclude each other"),
        (["--scheduler", "http://127.0.0.1:8786"], "--scheduler must be an address SCHEME://HOST:PORT"),
    ],
)
def test_report_scheduler_options_are_checked_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], words: str
) -> None:
    assert main(["report", "--quick", "--out", str(tmp_path / "r"), "--tables", str(REPORTS), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err, err
    assert not (tmp_path / "r" / "REPORT.md").exists()


def test_report_help_lists_the_scheduler(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["report", "--help"]) == 0
    assert "--scheduler ADDRESS" in capsys.readouterr().out
