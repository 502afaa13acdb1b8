"""``xcheck report --scheduler``: every micro computation of the report a Dask task, the same report."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.report.timings import TIMING_FILES

REPORTS = Path(__file__).resolve().parents[3] / "reports"


def test_the_quick_report_on_a_dask_cluster_is_the_local_report(
    quick_report_dir: Path, dask_scheduler: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """On a loopback cluster (one worker) the report's plan says where it computes, every micro computation
    of the plan is computed there, and every file but the run times is the shared local report's
    (``tests/conftest.py``), byte for byte: where a result is computed does not change it."""
    out = tmp_path / "report"
    argv = ["report", "--quick", "--out", str(out), "--tables", str(REPORTS), "--cache", str(tmp_path / "cache"),
            "--scheduler", dask_scheduler]
    assert main(argv) == 0
    err = capsys.readouterr().err
    plan = next(line for line in err.splitlines() if line.startswith("plan: "))
    assert plan.endswith(f"0 cached, {plan.split(' micro computations')[0].rsplit(' ', 1)[1]} to compute on "
                         f"{dask_scheduler}"), plan
    run = json.loads((out / "timings.json").read_text())["run"]
    assert run["computed"] > 80 and run["cached"] == 0
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
