"""The progress display: what each verbosity shows on a terminal and elsewhere."""

from __future__ import annotations

import io

import pytest

from comparison.progress import NORMAL, QUIET, VERBOSE, Progress


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _show(verbosity: int, stream: io.StringIO) -> str:
    with Progress(verbosity, stream) as p:
        p.say("plan: 3 computations")
        p.start(3, "micro")
        for i in range(3):
            p.advance(f"wall {i}: lambda = 0.5")
    return stream.getvalue()


@pytest.mark.parametrize(
    ("verbosity", "stream", "plan", "lines", "bar"),
    [
        (QUIET, Terminal(), False, False, False),
        (NORMAL, Terminal(), True, False, True),
        (VERBOSE, Terminal(), True, True, True),
        (QUIET, io.StringIO(), False, False, False),
        (NORMAL, io.StringIO(), False, False, False),  # a log or a pipe: silent unless asked
        (VERBOSE, io.StringIO(), True, True, False),
    ],
)
def test_what_each_verbosity_shows(verbosity: int, stream: io.StringIO, plan: bool, lines: bool, bar: bool) -> None:
    out = _show(verbosity, stream)
    assert ("plan: 3 computations" in out) is plan
    assert ("wall 2: lambda = 0.5" in out) is lines
    assert ("3/3" in out) is bar  # tqdm's count
