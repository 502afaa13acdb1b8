"""Input that used to hang: every case answers with one line and exit 2 within seconds.

Numbers with huge exponents (``Fraction`` built ``10**999999999``), a named pipe as a scene or grid
(``open()`` waited for a writer), and ``--scheduler`` pointing at something that is not a Dask
scheduler (Dask waits for its handshake without a limit). Each case is a real ``xcheck`` process
with a time-out (a hang must fail the test, not stall the suite); they run side by side. Marked
``processes``; about 15 s for all on the 2-core development machine.
"""

from __future__ import annotations

import http.server
import os
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
TINY = ROOT / "examples" / "sweeps" / "tiny.toml"
#: Seconds a case may take beyond a command refused at once (started beside it, so that loading the suite
#: on a loaded machine counts alike): the bound for ``--scheduler`` (its check takes 4 s; loading
#: dask.distributed, seconds more on a loaded machine). Without the bounds a closed port costs 20 s or
#: more, a silent server minutes, the huge numbers and the named pipes forever.
EXTRA_SECONDS = 10.0
#: Seconds after which a case still running is a hang.
HANG_SECONDS = 90.0
WALL = ["--rows", "12", "--t", "1", "--m", "1/3", "--f", "0.6"]
GRID_HUGE = """
[axes]
t = ["1e999999999"]
m = "1/3"
rows = 6
f = 0.6
[[method]]
kind = "macro"
"""


def _with(argv: list[str], option: str, value: str) -> list[str]:
    i = argv.index(option)
    return [*argv[: i + 1], value, *argv[i + 2 :]]


@pytest.fixture()
def silent_server() -> Iterator[int]:
    """A TCP server that accepts connections and never sends a byte."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    accepted: list[socket.socket] = []

    def accept() -> None:
        while True:
            try:
                accepted.append(server.accept()[0])
            except OSError:
                return

    threading.Thread(target=accept, daemon=True).start()
    yield server.getsockname()[1]
    server.close()
    for c in accepted:
        c.close()


@pytest.fixture()
def http_server() -> Iterator[int]:
    """An HTTP server (it answers only once it has read a request)."""

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args: object) -> None:
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield server.server_address[1]
    server.shutdown()
    server.server_close()


@pytest.fixture()
def closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.processes
def test_input_that_hung_answers_with_one_line_and_exit_2(
    tmp_path: Path, silent_server: int, http_server: int, closed_port: int
) -> None:
    fifo = tmp_path / "scene.fifo"
    os.mkfifo(fifo)
    grid = tmp_path / "huge.toml"
    grid.write_text(GRID_HUGE)
    out = str(tmp_path / "out")
    sweep = ["sweep", str(TINY), "--out", out, "--scheduler"]
    cases = {
        "--t 1e999999999": ["micro", *_with(WALL, "--t", "1e999999999")],
        "--m 1e-999999999 (macro)": ["macro", *_with(WALL, "--m", "1e-999999999")],
        "--rows 1e999999999": ["micro", *_with(WALL, "--rows", "1e999999999")],
        "report --workers 1e999999999": ["report", "--quick", "--out", out, "--workers", "1e999999999"],
        "stability --workers 1e999999999": ["stability", "--quick", "--out", out, "--workers", "1e999999999"],
        "grid t = ['1e999999999']": ["sweep", str(grid), "--out", out],
        "--scene FIFO": ["micro", "--scene", str(fifo)],
        "grid FIFO": ["sweep", str(fifo), "--out", out],
        "scheduler: silent server": [*sweep, f"tcp://127.0.0.1:{silent_server}"],
        "scheduler: HTTP server": [*sweep, f"tcp://127.0.0.1:{http_server}"],
        "scheduler: closed port": [*sweep, f"tcp://127.0.0.1:{closed_port}"],
        "scheduler: unknown host": [*sweep, "tcp://no-such-host.invalid:8786"],
    }
    cases["baseline: --t x"] = ["micro", *_with(WALL, "--t", "x")]  # refused at once: the time to load the suite
    started = time.monotonic()
    procs = {
        name: subprocess.Popen([sys.executable, "-m", "comparison.cli", *argv], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True)
        for name, argv in cases.items()
    }
    took: dict[str, float] = {}
    try:
        while len(took) < len(procs) and time.monotonic() - started < HANG_SECONDS:
            for name, proc in procs.items():
                if name not in took and proc.poll() is not None:
                    took[name] = time.monotonic() - started
            time.sleep(0.02)
    finally:
        for proc in procs.values():
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    bad = [f"{name}: still running after {HANG_SECONDS:g} s" for name in procs if name not in took]
    for name, seconds in took.items():
        err = procs[name].stderr.read() if procs[name].stderr else ""
        lines = err.strip().splitlines()
        if procs[name].returncode != 2 or len(lines) != 1 or not lines[0].startswith("xcheck: error: "):
            bad.append(f"{name}: exit {procs[name].returncode}, {err.strip()[-500:]!r}")
        elif seconds > took.get("baseline: --t x", 0.0) + EXTRA_SECONDS:
            bad.append(f"{name}: {seconds:.1f} s against {took.get('baseline: --t x', 0.0):.1f} s for the baseline")
    assert not bad, "\n".join(bad)
