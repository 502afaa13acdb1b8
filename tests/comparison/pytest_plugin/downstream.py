"""A downstream project's pytest run, as the plugin's tests start it: in a process of its own, or in the
test's process through :class:`pytest.Pytester` (``runpytest_inprocess``).

Both load the plugin as a downstream project does, by its ``pytest11`` entry point, in a fresh pytest
session (its own configuration, plugin manager and stash) started in a folder of the test's; a process costs
about a second of imports (numpy, numba, the packages) that the test's process has already paid. A run that
changes the interpreter for good (a ``conftest.py`` that patches ``Path.write_text``) takes a process; so does
one run of each file, which shows the plugin loading in an interpreter of its own.
"""

from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

#: The options of every downstream run (no cache folder written; no reordering of the tests).
ARGS = ("-q", "-p", "no:cacheprovider", "-p", "no:randomly")


@dataclass(frozen=True)
class Run:
    """A finished run: its exit code and what it printed."""

    returncode: int
    stdout: str
    stderr: str


def in_a_process(folder: Path, *args: str) -> Run:
    """``python -m pytest ARGS`` in ``folder``, with the result cache ``folder/cache``."""
    run = subprocess.run(
        [sys.executable, "-m", "pytest", *ARGS, *args], cwd=folder, capture_output=True, text=True, timeout=120,
        env={**os.environ, "XCHECK_CACHE": str(folder / "cache")},
    )  # fmt: skip
    return Run(run.returncode, run.stdout, run.stderr)


def in_this_process(pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch, *args: str) -> Run:
    """The same run in ``pytester.path``, in this process, with the result cache ``pytester.path/cache``."""
    monkeypatch.setenv("XCHECK_CACHE", str(pytester.path / "cache"))
    run = pytester.runpytest_inprocess(*ARGS, *args)
    out, err = ("".join(f"{line}\n" for line in lines) for lines in (run.outlines, run.errlines))
    return Run(int(run.ret), out, err)
