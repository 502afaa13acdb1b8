"""A loopback ``dask.distributed`` cluster for the tests that run sweeps and reports on Dask."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest


def _start(args: list[str], log: Path) -> subprocess.Popen[bytes]:
    with log.open("wb") as fh:
        return subprocess.Popen(args, stdout=fh, stderr=subprocess.STDOUT, start_new_session=True)


@contextlib.contextmanager
def cluster(tmp: Path) -> Iterator[tuple[str, subprocess.Popen[bytes], subprocess.Popen[bytes]]]:
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


def with_group(proc: subprocess.Popen[bytes], sig: int) -> None:
    """Send ``sig`` to ``proc``'s process group (it was started in a session of its own)."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, sig)
