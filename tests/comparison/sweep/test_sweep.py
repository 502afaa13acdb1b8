"""``xcheck sweep``: the table, resuming from the cache, memory refusal, and the same table on Dask."""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

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
def tiny_local(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[dict[str, str]], dict]:
    tmp = tmp_path_factory.mktemp("tiny")
    code, rows, meta = _sweep(tmp, TINY, tmp / "cache", "--workers", "2")
    assert code == 0
    return tmp, rows, meta


def test_the_table_holds_every_cell_once_with_inputs_and_results(tiny_local) -> None:
    tmp, rows, meta = tiny_local
    plan = cells(load_grid(TINY))
    assert list(rows[0]) == list(COLUMNS)
    assert [int(r["cell"]) for r in rows] == list(range(len(plan))) == list(range(12))
    assert meta["counts"] == {"cells": 12, "macro": 4, "cached": 0, "computed": 8, "failed": 0, "skipped": 0}
    assert meta["grid"]["axes"]["rows"] == [6] and meta["versions"]["numpy"] and meta["machine"]["cpus"]
    assert meta["macro_walls_per_second"] > 0 and meta["code"]["micro"]
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


def test_a_second_run_reads_everything_from_the_cache(tiny_local) -> None:
    tmp, rows, _ = tiny_local
    code, again, meta = _sweep(tmp, TINY, tmp / "cache", "--workers", "1")
    assert code == 0 and meta["counts"]["computed"] == 0 and meta["counts"]["cached"] == 8
    assert _results(again) == _results(rows)
    assert {r["cached"] for r in again if r["kind"] != "macro"} == {"1"}


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
def _start(args: list[str], log: Path) -> subprocess.Popen[bytes]:
    with log.open("wb") as fh:
        return subprocess.Popen(args, stdout=fh, stderr=subprocess.STDOUT, start_new_session=True)


@contextlib.contextmanager
def _cluster(tmp: Path) -> Iterator[tuple[str, subprocess.Popen[bytes], subprocess.Popen[bytes]]]:
    """A ``dask.distributed`` scheduler and one worker (two processes with its nanny) on 127.0.0.1:
    ``(address, scheduler, worker)``, each process in a session of its own; ended on exit."""
    pytest.importorskip("distributed")
    from distributed import Client

    info = tmp / "scheduler.json"
    dask = [sys.executable, "-m", "dask"]
    common = ["--no-dashboard", "--host", "127.0.0.1"]
    procs = [_start([*dask, "scheduler", "--port", "0", "--scheduler-file", str(info), *common], tmp / "s.log")]
    try:
        deadline = time.monotonic() + 120
        while not info.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        address = json.loads(info.read_text())["address"]
        worker = ["worker", address, "--nthreads", "1", "--nworkers", "1", "--memory-limit", "2GB", *common]
        procs.append(_start([*dask, *worker], tmp / "w.log"))
        with Client(address, timeout=120) as client:
            client.wait_for_workers(1, timeout=120)
        yield address, procs[0], procs[1]
    finally:
        for p in reversed(procs):
            with_group(p, signal.SIGTERM)
        for p in reversed(procs):
            try:
                p.wait(30)
            except subprocess.TimeoutExpired:
                with_group(p, signal.SIGKILL)
                p.wait(30)


@pytest.fixture(scope="module")
def dask_scheduler(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """A ``dask.distributed`` scheduler and one worker on 127.0.0.1 (:func:`_cluster`)."""
    with _cluster(tmp_path_factory.mktemp("dask")) as (address, _, _):
        yield address


def with_group(proc: subprocess.Popen[bytes], sig: int) -> None:
    """Send ``sig`` to ``proc``'s process group (it was started in a session of its own)."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, sig)


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
    """Before: the client's reconnection tracebacks, and the unfinished cells in the table as
    ``worker_died`` although the worker lived. After: one line, exit 1, no table (as after a kill of the
    sweep itself); the finished cells are in the cache and a sweep started again computes only the rest."""
    grid = tmp_path / "sixteen.toml"
    grid.write_text(SIXTEEN)
    cache, out = tmp_path / "cache", tmp_path / "out"
    with _cluster(tmp_path) as (address, scheduler, worker):
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
