"""``xcheck sweep``: the table, resuming from the cache, memory refusal, and the same table on Dask."""

from __future__ import annotations

import json
import math
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from dask_cluster import cluster, with_group
from quick_report import Sweep

import macro
from comparison.cli import main
from comparison.runner import Runner
from comparison.sweep import COLUMNS, RUN_COLUMNS, cells, load_grid, read_table

ROOT = Path(__file__).resolve().parents[3]
TINY = ROOT / "examples" / "sweeps" / "tiny.toml"


def _sweep(tmp: Path, grid: Path, cache: Path, *extra: str) -> tuple[int, list[dict[str, str]], dict]:
    out = tmp / "out"
    code = main(["sweep", str(grid), "--out", str(out), "--cache", str(cache), "--quiet", *extra])
    name = load_grid(grid).name
    return code, read_table(out / f"{name}.csv"), json.loads((out / f"{name}.json").read_text())


def _results(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    """The table without the columns that depend on the run."""
    return [{k: v for k, v in r.items() if k not in RUN_COLUMNS} for r in rows]


@pytest.fixture(scope="module")
def tiny_local(tiny_sweep: Sweep) -> tuple[Path, list[dict[str, str]], dict]:
    """The tiny grid swept by two local workers from an empty cache (``tests/conftest.py``): its folder (the
    table in ``out/``, the cache in ``cache/``), its rows and its metadata."""
    out = tiny_sweep.out
    return out.parent, read_table(out / "tiny.csv"), json.loads((out / "tiny.json").read_text())


def test_the_table_holds_every_cell_once_with_inputs_and_results(tiny_local) -> None:
    tmp, rows, meta = tiny_local
    plan = cells(load_grid(TINY))
    assert list(rows[0]) == list(COLUMNS)
    assert [int(r["cell"]) for r in rows] == list(range(len(plan))) == list(range(12))
    assert meta["counts"] == {"cells": 12, "macro": 4, "user": 0, "cached": 0, "computed": 8, "failed": 0,
                              "skipped": 0}
    assert meta["grid"]["axes"]["rows"] == [6] and meta["versions"]["numpy"] and meta["machine"]["cpus"]
    assert meta["macro_walls_per_second"] > 0 and len(meta["code"]) == 16
    runner = Runner(None)
    for row, cell in zip(rows, plan, strict=True):
        assert row["kind"] == cell.method.kind and float(row["t"]) == cell.point.t
        assert row["status"] == "optimal" and float(row["seconds"]) >= 0
        if cell.micro:  # the same number as the runner computes in this process
            assert cell.spec is not None
            assert float(row["load_factor"]) == runner.run(cell.spec, cell.method).load_factor
            assert int(row["blocks"]) > 0 and int(row["iterations"]) > 0 and row["first_course"] in ("full", "half")
        else:  # the vectorised macro side agrees with macro.solve
            lam = macro.solve(cell.point.spec().to_macro()).load_factor
            assert float(row["load_factor"]) == pytest.approx(lam, rel=1e-9)
            assert row["mechanism"] and int(row["hinge_storey"]) == 1


def _page(out: Path, name: str) -> tuple[str, dict[str, bytes]]:
    """The page ``name.md`` of ``out`` and the figures it links, by name (each must exist)."""
    text = (out / f"{name}.md").read_text()
    links = re.findall(r"!\[Figure (\d+)\]\(([^)]+)\)", text)
    assert [int(n) for n, _ in links] == list(range(1, len(links) + 1))
    for n, _ in links:
        assert f"**Figure {n}.** " in text
    return text, {name: (out / name).read_bytes() for _, name in links}


def test_the_sweep_writes_its_validation_page(tiny_local) -> None:
    """``xcheck sweep`` leaves ``NAME.md`` beside its table, with the summary, the error map, the scatter,
    the histogram and the time against blocks, each figure numbered and there."""
    tmp, rows, _ = tiny_local
    text, figures = _page(tmp / "out", "tiny")
    assert list(figures) == ["tiny-map.png", "tiny-scatter.png", "tiny-histogram.png", "tiny-time.png"]
    assert all(png.startswith(b"\x89PNG") for png in figures.values())
    assert text.startswith("# Validation: tiny\n") and "## Summary" in text
    assert "* **4 walls** (2 t × 2 m) in 2 bonds each: 8 bonded walls, each compared on its own." in text
    assert "* **8 micro computations** (4 micro-assoc (highs-ipm), 4 micro-assoc (highs-ipm, half first)): " \
        "8 run, 8 with a value, 0 without" in text
    # the summary's numbers, from the table: the macro value above the associative LP on the walls where it is
    diffs = {}
    for r in rows:
        if r["kind"] == "micro-assoc":
            macro = next(m for m in rows if m["kind"] == "macro" and m["wall"] == r["wall"])
            diffs[(r["wall"], r["first_course"])] = float(macro["load_factor"]) / float(r["load_factor"]) - 1
    unsafe = sum(d > 1e-4 for d in diffs.values())
    worst = max(diffs.values())
    assert f"| macro | 8 | {unsafe} ({100 * unsafe / 8:.0f} %) | {sum(d > 0.05 for d in diffs.values())} " in text
    assert f"| {100 * worst:+.1f} % | t = " in text and "Every cell gave a value." in text


def test_a_second_run_reads_everything_from_the_cache(tiny_local) -> None:
    """... and writes the same page, figures included: the page is drawn from the table alone."""
    tmp, rows, _ = tiny_local
    first = _page(tmp / "out", "tiny")
    code, again, meta = _sweep(tmp, TINY, tmp / "cache", "--workers", "1")
    assert code == 0 and meta["counts"]["computed"] == 0 and meta["counts"]["cached"] == 8
    assert _results(again) == _results(rows)
    assert {r["cached"] for r in again if r["kind"] != "macro"} == {"1"}
    assert _page(tmp / "out", "tiny") == first


def test_no_report_writes_the_table_and_no_page(tiny_local, tmp_path: Path, capsys) -> None:
    tmp, _, _ = tiny_local
    code = main(["sweep", str(TINY), "--out", str(tmp_path), "--cache", str(tmp / "cache"), "--no-report"])
    assert code == 0 and "page:" not in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiny.csv", "tiny.json"]


#: Walls that fail in every way a sweep records: 6 rows do not split over 4 storeys (``not_applicable``), the
#: wall t = 1, m = 1 of 39 blocks is above max_blocks (``not_run``), and the user's model raises on t = 2.
FAILING = """
name = "failing"
[axes]
t = [1.0, 2.0]
m = 1
rows = 6
f = 0.75
storeys = [1, 4]
[[method]]
kind = "macro"
[[method]]
kind = "user"
name = "fragile"
function = "fragile43:lam"
[[method]]
kind = "micro-assoc"
solver = "highs-ipm"
max_blocks = 30
"""


def test_a_grid_with_failing_cells_counts_and_lists_them_on_its_page(tiny_local, tmp_path: Path) -> None:
    tmp, _, _ = tiny_local
    (tmp_path / "fragile43.py").write_text(
        "def lam(t, m, rows, f, p, storeys):\n    if t > 1:\n        raise ValueError('t > 1 is beyond me')\n"
        "    return 0.3\n")
    grid = tmp_path / "failing.toml"
    grid.write_text(FAILING)
    code, rows, meta = _sweep(tmp_path, grid, tmp / "cache", "--workers", "1")
    assert code == 1 and meta["counts"]["failed"] == 1 and meta["counts"]["user"] == 2  # the model raised
    status = {(r["method"], r["t"], r["storeys"]): r["status"] for r in rows}
    assert status[("fragile", "2.0", "1")] == "error" and status[("fragile", "1.0", "1")] == "optimal"
    assert status[("micro-assoc (highs-ipm)", "1.0", "1")] == "not_run"
    text, figures = _page(tmp_path / "out", "failing")
    assert "| method | `optimal` | `not_applicable` | `error` | `not_run` |" in text
    assert "| fragile | 1 | 2 | 1 | 0 |" in text and "| micro-assoc (highs-ipm) | 1 | 2 | 0 | 1 |" in text
    assert "8 cells gave no value:" in text
    assert "* `not_applicable` (the parameters make no wall): 6 — t=1 m=1 o=6 f=0.75 p=0 N=4, macro: " in text
    assert "* `error` (the computation raised): 1 — t=2 m=1 o=6 f=0.75 p=0 N=1, fragile: ValueError: t > 1 is " in text
    assert "* `not_run` (above the block limit): 1 — t=1 m=1 o=6 f=0.75 p=0 N=1, micro-assoc (highs-ipm)." in text
    # one wall has both a macro and a micro value: its map, scatter and histogram are drawn; the user's
    # model has none with a micro value (its one value is on the wall above the limit)
    assert "| fragile | 0 | 0 | 0 | 0 | 0 | – | – | – |" in text
    assert list(figures) == ["failing-map.png", "failing-scatter.png", "failing-histogram.png", "failing-time.png"]


def test_a_user_model_gets_its_column_and_figures(tiny_local, tmp_path: Path) -> None:
    """A grid naming ``module:function`` as an extra macro column: the table holds its values and the page
    its row of the summary, its error map and its points in the scatter and histogram."""
    tmp, local, _ = tiny_local
    (tmp_path / "half43.py").write_text("def lam(t, m, rows, f, p, storeys):\n    return min(f, 1 / t) / 2\n")
    grid = tmp_path / "tiny.toml"
    grid.write_text(TINY.read_text().replace('[[method]]\nkind = "micro-assoc"',
                                             '[[method]]\nkind = "user"\nname = "half the bound"\n'
                                             'function = "half43:lam"\n\n[[method]]\nkind = "micro-assoc"'))
    code, rows, meta = _sweep(tmp_path, grid, tmp / "cache", "--workers", "1")
    assert code == 0 and meta["counts"]["cached"] == 8 and meta["counts"]["user"] == 4
    assert meta["grid"]["methods"][1] == {"kind": "user", "name": "half the bound", "function": "half43:lam",
                                          "max_blocks": None}
    mine = [r for r in rows if r["kind"] == "user"]
    assert [float(r["load_factor"]) for r in mine] == [min(0.75, 1 / float(r["t"])) / 2 for r in mine]
    assert all(r["method"] == "half the bound" and r["status"] == "optimal" for r in mine)
    def values(table: list[dict[str, str]]) -> dict[tuple[str, str], str]:
        return {(r["wall"], r["method"]): r["load_factor"] for r in table if r["kind"] != "user"}

    assert values(rows) == values(local)  # the other columns as they were
    text, figures = _page(tmp_path / "out", "tiny")
    assert "Macro columns: `macro`, `half the bound` (`half43:lam`)." in text
    assert "| half the bound | 8 | 0 (0 %) | 0 | 0 | 0 | " in text  # half the bound lies below every micro value
    assert "## Error map: half the bound" in text and "tiny-map-half-the-bound.png" in figures
    assert list(figures) == ["tiny-map.png", "tiny-map-half-the-bound.png", "tiny-scatter.png", "tiny-histogram.png",
                             "tiny-time.png"]


def test_a_user_model_from_the_python_api(tiny_local, tmp_path: Path) -> None:
    """The Python API takes the callable itself."""
    from dataclasses import replace

    from comparison.runner import ResultCache
    from comparison.runner.executor import LocalExecutor
    from comparison.sweep import GridMethod, run_sweep
    from comparison.sweep.usermodel import UserModel
    from comparison.utilities.progress import QUIET, Progress

    tmp, _, _ = tiny_local
    grid = load_grid(TINY)
    grid = replace(grid, methods=(*grid.methods, GridMethod(UserModel("api", lambda t, m, rows, f, p, n: 0.4))))
    with LocalExecutor(1) as executor, Progress(QUIET) as progress:
        done = run_sweep(grid, tmp_path, cache=ResultCache(tmp / "cache"), executor=executor, progress=progress)
    assert done.counts["user"] == 4 and done.page == tmp_path / "tiny.md"
    rows = read_table(done.table)
    assert [r["load_factor"] for r in rows if r["kind"] == "user"] == ["0.4"] * 4
    assert "`api` (`test_sweep:test_a_user_model_from_the_python_api.<locals>.<lambda>`)" in done.page.read_text()


def test_sweeps_that_share_walls_compute_them_once(tiny_local, tmp_path: Path) -> None:
    tmp, rows, _ = tiny_local
    grid = tmp_path / "share.toml"
    grid.write_text(TINY.read_text().replace("t = [1.0, 2.0]", "t = [2.0, 1.5]"))
    code, other, meta = _sweep(tmp_path, grid, tmp / "cache", "--workers", "1")
    assert code == 0
    assert meta["counts"]["cached"] == 4 and meta["counts"]["computed"] == 4  # t = 2 shared, t = 1.5 new
    def shared(table: list[dict[str, str]]) -> list[dict[str, str]]:
        return [{k: v for k, v in r.items() if k != "cell"} for r in _results(table) if r["t"] == "2.0"]

    assert shared(other) == shared(rows)


def test_walls_above_a_workers_memory_are_refused_not_run(tmp_path: Path) -> None:
    code, rows, meta = _sweep(tmp_path, TINY, tmp_path / "cache", "--workers", "1", "--worker-memory", "1e-6")
    assert code == 1 and meta["counts"]["failed"] == 8 and meta["counts"]["computed"] == 0
    micro = [r for r in rows if r["kind"] != "macro"]
    assert {r["status"] for r in micro} == {"refused_memory"} and all(r["load_factor"] == "nan" for r in micro)
    assert "exceeds a worker's" in micro[0]["message"]
    assert {r["status"] for r in rows if r["kind"] == "macro"} == {"optimal"}
    assert not (tmp_path / "cache").exists() or not any((tmp_path / "cache").rglob("*.json"))


# ----------------------------------------------------------------- Dask
def test_a_sweep_on_a_dask_cluster_gives_the_local_table(tiny_local, dask_scheduler: str, tmp_path: Path) -> None:
    _, local, _ = tiny_local
    code, remote, meta = _sweep(tmp_path, TINY, tmp_path / "cache", "--scheduler", dask_scheduler)
    assert code == 0 and meta["executor"]["where"] == dask_scheduler and meta["counts"]["computed"] == 8
    assert meta["executor"]["memory"] == 2_000_000_000
    assert _results(remote) == _results(local)
    assert all(math.isfinite(float(r["load_factor"])) for r in remote)


def test_an_unreachable_scheduler_is_one_line_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("distributed")
    import socket

    with socket.socket() as s:  # a free port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    from comparison.runner.executor import cluster

    saved = cluster.CONNECT_SECONDS
    cluster.CONNECT_SECONDS = 2.0
    try:
        code = main(["sweep", str(TINY), "--out", str(tmp_path), "--scheduler", f"tcp://127.0.0.1:{port}"])
    finally:
        cluster.CONNECT_SECONDS = saved
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--scheduler: no Dask scheduler at" in err, err
    shutil.rmtree(tmp_path, ignore_errors=True)


#: 16 walls of 9-150 blocks on the iterated LP (tenths of a second to seconds each): still running when
#: the scheduler is killed.
SIXTEEN = """
name = "sixteen"
[axes]
t = [0.5, 1.0, 1.5, 2.0]
m = ["1/3", "1/2"]
rows = [6, 12]
f = 0.6
[[method]]
kind = "micro-nonassoc"
"""


@pytest.mark.processes
def test_a_scheduler_killed_mid_sweep_is_one_line_and_no_cell_is_called_worker_died(tmp_path: Path) -> None:
    """A scheduler killed mid-sweep: one line, exit 1, no table (as after a kill of the sweep itself), no cell
    called ``worker_died``; the finished cells are in the cache and a sweep started again computes only the
    rest."""
    grid = tmp_path / "sixteen.toml"
    grid.write_text(SIXTEEN)
    cache, out = tmp_path / "cache", tmp_path / "out"
    with cluster(tmp_path) as (address, scheduler, worker):
        proc = subprocess.Popen(
            [sys.executable, "-m", "comparison.cli", "sweep", str(grid), "--out", str(out), "--cache", str(cache),
             "--quiet", "--scheduler", address], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            deadline = time.monotonic() + 120
            while sum(1 for _ in cache.rglob("*.json")) < 2 and proc.poll() is None and time.monotonic() < deadline:
                time.sleep(0.02)
            with_group(scheduler, signal.SIGKILL)
            _, err = proc.communicate(timeout=60)
        finally:
            if proc.poll() is None:
                proc.kill()
        assert worker.poll() is None  # the worker lived
    lines = err.strip().splitlines()
    assert proc.returncode == 1 and len(lines) == 1, err
    assert lines[0].startswith(f"xcheck: error: --scheduler: the Dask scheduler at {address} went away after ")
    assert not (out / "sixteen.csv").exists()
    kept = sum(1 for _ in cache.rglob("*.json"))
    assert 2 <= kept < 16, "killed too late to test"
    code, rows, meta = _sweep(tmp_path, grid, cache, "--workers", "2")
    assert code == 0 and meta["counts"]["cached"] == kept and meta["counts"]["computed"] == 16 - kept
    assert all(r["status"] != "worker_died" for r in rows)
