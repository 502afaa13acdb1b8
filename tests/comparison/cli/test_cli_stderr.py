"""Standard error carries the plan, the progress and the warnings, never a result: one that cannot be written
never aborts a computation or loses its result, and one closed at the start sends nothing to standard output.

In this process standard error is replaced by a stream whose every write fails as a full device's does
(``ENOSPC``), or by ``None`` (what Python makes of a descriptor 2 closed at the start, ``2>&-``); in a
process of its own (the processes tier) it is a stand-in of ``/dev/full`` made in a temporary folder (a
character device node 1, 7) or a closed descriptor.
"""

from __future__ import annotations

import errno
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from comparison.cli import main

ROOT = Path(__file__).resolve().parents[3]
WALL = ["--rows", "12", "--t", "1", "--m", "1/3", "--f", "0.75"]
RESULT_LINES = ("table: ", "meta: ")


class FullDevice:
    """A text stream every write and flush of which fails as a full device's."""

    def write(self, text: str) -> int:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def flush(self) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def isatty(self) -> bool:
        return False


#: One wall, the macro model and the associative LP: a sweep with one micro computation.
ONE_WALL = """name = "one"
[axes]
t = 1.0
m = "1/3"
rows = 6
f = 0.75

[[method]]
kind = "macro"

[[method]]
kind = "micro-assoc"
solver = "highs-ipm"
"""


def _sweep(tmp_path: Path, micro: bool = True) -> list[str]:
    """Sweep :data:`ONE_WALL` (``micro=False``: its macro cell only, no worker process); the paths printed."""
    grid, out, cache = tmp_path / "one.toml", tmp_path / "out", tmp_path / "cache"
    grid.write_text(ONE_WALL if micro else ONE_WALL.split('[[method]]\nkind = "micro-assoc"')[0])
    argv = ["sweep", str(grid), "--out", str(out), "--cache", str(cache), "--workers", "1", "--no-report"]
    assert main(argv) == 0  # the page (--no-report: not drawn here) is the sweep's tests' business
    assert {p.name for p in out.iterdir()} == {"one.csv", "one.json"}
    assert len(list((cache / "micro-assoc").glob("*.json"))) == micro  # the computed result kept
    return [str(p) for p in (out / "one.csv", out / "one.json")]


@pytest.mark.parametrize("stderr", ["full", "closed"])
def test_a_sweep_whose_standard_error_fails_or_is_closed_keeps_its_results(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, tmp_path: Path, stderr: str
) -> None:
    """``xcheck sweep ... 2>`` a full device, or with standard error closed: every cell computed and kept in
    the cache, the table and metadata written, exit 0, and standard output holds the paths alone."""
    monkeypatch.setattr(sys, "stderr", FullDevice() if stderr == "full" else None)
    paths = _sweep(tmp_path, micro=stderr == "full")  # the micro cell's storing shown once
    out = capsys.readouterr().out
    assert out.splitlines() == [f"{kind}{path}" for kind, path in zip(RESULT_LINES, paths, strict=True)]


@pytest.mark.parametrize("stderr", ["full", "closed"])
def test_micro_verbose_whose_standard_error_fails_or_is_closed_prints_its_result(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, stderr: str
) -> None:
    """``xcheck micro -v`` (one line per LP on standard error) with a full or closed standard error prints its
    result, exit 0, and standard output holds no LP line."""
    monkeypatch.setattr(sys, "stderr", FullDevice() if stderr == "full" else None)
    assert main(["micro", *WALL, "--friction", "nonassociative", "-v"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("lambda = 0.6911") and " vertex LP " not in out, out  # the LP lines go to stderr only


def _stand_in_full(folder: Path) -> Path:
    """A character device node like ``/dev/full`` (1, 7) in ``folder``; the test skips where none can be made."""
    node = folder / "full"
    try:
        os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 7))
        with node.open("w") as fh:
            fh.write("x")
            fh.flush()
    except PermissionError:
        pytest.skip("no device node can be made here (not root, or a nodev file system)")
    except OSError as exc:
        assert exc.errno == errno.ENOSPC
    return node


@pytest.mark.processes  # the console script in a process of its own, its descriptor 2 a device or closed
@pytest.mark.parametrize("stderr", ["full", "closed"])
def test_the_console_with_a_full_or_closed_standard_error(tmp_path: Path, stderr: str) -> None:
    argv = [sys.executable, "-m", "comparison.cli", "micro", *WALL, "--friction", "nonassociative", "-v"]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}  # this checkout's packages, whatever is installed
    if stderr == "full":
        with _stand_in_full(tmp_path).open("w") as full:
            run = subprocess.run(argv, stdout=subprocess.PIPE, stderr=full, text=True, timeout=300, env=env)
    else:
        run = subprocess.run(argv, stdout=subprocess.PIPE, text=True, timeout=300, env=env,
                             preexec_fn=lambda: os.close(2))  # noqa: PLW1509 - a closed descriptor 2 is the case
    assert run.returncode == 0 and run.stdout.startswith("lambda = 0.6911"), run.stdout
    assert " vertex LP " not in run.stdout
