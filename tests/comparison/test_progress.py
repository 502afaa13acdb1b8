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
        (NORMAL, io.StringIO(), True, False, False),  # a log or a pipe: the plan and status lines, no bar
        (VERBOSE, io.StringIO(), True, True, False),
    ],
)
def test_what_each_verbosity_shows(verbosity: int, stream: io.StringIO, plan: bool, lines: bool, bar: bool) -> None:
    out = _show(verbosity, stream)
    assert ("plan: 3 computations" in out) is plan
    assert ("wall 2: lambda = 0.5" in out) is lines
    assert ("3/3" in out) is bar  # tqdm's count


class Clock:
    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def test_a_log_gets_a_status_line_every_tenth_or_30_seconds() -> None:
    """Issue 31, item 8: off a terminal ``xcheck report`` printed nothing (25 minutes of nothing under load).
    Without ``-q`` it now prints the plan, a status line each time another 10 % is done or 30 s have
    passed since the last (done, cached, to go, elapsed, ETA), and its summary, on stderr."""
    from comparison.progress import LOG_SECONDS

    stream, clock = io.StringIO(), Clock()
    with Progress(NORMAL, stream, clock=clock, heartbeat=None) as p:
        p.say("plan: 100 computations")
        p.start(100, "micro", cached=40)
        for _ in range(25):  # 1 s each: a line at 10 and 20 done
            clock.now += 1.0
            p.advance("a wall: lambda = 0.5")
        clock.now += LOG_SECONDS + 5  # one slow computation: a line although not another 10 %
        p.advance()
        for _ in range(74):
            clock.now += 0.1
            p.advance()
        p.say("wrote 3 files")
    lines = stream.getvalue().splitlines()
    assert lines[0] == "plan: 100 computations" and lines[-1] == "wrote 3 files"
    status = lines[1:-1]
    assert status[:3] == [
        "micro: 10 of 100 done (10 %), 40 cached, 90 to go; 10 s elapsed, ETA by count 1 min 30 s",
        "micro: 20 of 100 done (20 %), 40 cached, 80 to go; 20 s elapsed, ETA by count 1 min 20 s",
        "micro: 26 of 100 done (26 %), 40 cached, 74 to go; 1 min 00 s elapsed, ETA by count 2 min 51 s",
    ]
    assert status[-1].startswith("micro: 100 of 100 done (100 %), 40 cached, 0 to go; ") and status[-1].endswith(
        "ETA by count 0 s")
    assert len(status) == 11 and "lambda" not in stream.getvalue()  # per-computation lines only when verbose
    quiet = io.StringIO()
    with Progress(QUIET, quiet, clock=clock) as p:
        p.say("plan")
        p.start(10, "micro")
        for _ in range(10):
            p.advance("x")
    assert quiet.getvalue() == ""


def test_durations() -> None:
    from comparison.progress import duration

    assert [duration(s) for s in (0.4, 59.6, 65, 3599, 7380)] == ["0 s", "1 min 00 s", "1 min 05 s", "59 min 59 s",
                                                                     "2 h 03 min"]


def test_a_log_gets_a_status_line_while_one_computation_runs_for_minutes() -> None:
    """The heartbeat: with nothing finishing, a log still gets the status line, marked "nothing finished",
    once LOG_SECONDS have passed since the last line (a full report's log had no line for 10 minutes
    while Sets 9 and 10 ran); nothing before that, and the thread ends with the display."""
    import time

    from comparison.progress import LOG_SECONDS

    stream, clock = io.StringIO(), Clock()
    with Progress(NORMAL, stream, clock=clock, heartbeat=0.01) as p:
        p.start(4, "micro")
        time.sleep(0.1)  # the heartbeat looked several times: less than LOG_SECONDS passed, no line
        assert stream.getvalue() == ""
        clock.now += LOG_SECONDS + 1
        for _ in range(500):  # wait (up to 5 s) for the heartbeat to see the clock
            if "nothing finished" in stream.getvalue():
                break
            time.sleep(0.01)
        thread = p._thread
    lines = stream.getvalue().splitlines()
    assert lines == [
        "micro: 0 of 4 done (0 %), 0 cached, 4 to go; 31 s elapsed, ETA unknown; nothing finished for 31 s"]
    assert thread is not None and not thread.is_alive() and p._thread is None


def test_the_heartbeat_says_nothing_finished_only_when_the_count_did_not_move() -> None:
    """Issue 44, item 3: a log showed ``3 of 88`` then ``5 of 88 ...; still running``, though the words were
    documented as "nothing finished". The heartbeat's line says ``nothing finished for <time since the last
    finish>`` only when no computation finished since the previous line; after the count moved it is the
    plain status line."""
    from comparison.progress import LOG_SECONDS

    stream, clock = io.StringIO(), Clock()
    with Progress(NORMAL, stream, clock=clock, heartbeat=None) as p:
        p.start(88, "micro")
        for _ in range(3):
            p.advance()
        clock.now += LOG_SECONDS
        p.advance()  # 4 of 88, 30 s after the start: a line
        clock.now += 10
        p.advance()  # 5 of 88, no line (neither 10 % nor 30 s)
        clock.now += LOG_SECONDS - 10
        p.beat()  # 30 s after the last line, the count moved since: the plain line
        clock.now += LOG_SECONDS / 2
        p.beat()  # 15 s after that line: nothing
        clock.now += LOG_SECONDS / 2
        p.beat()  # 30 s after it, nothing finished since: said, with the time since the 5th finished
        clock.now += LOG_SECONDS
        p.beat()
    lines = stream.getvalue().splitlines()
    assert [line.split("; ", 1)[0] for line in lines] == ["micro: 4 of 88 done (4 %), 0 cached, 84 to go"] + [
        "micro: 5 of 88 done (5 %), 0 cached, 83 to go"] * 3
    assert [line.rsplit("; ", 1)[1] for line in lines] == [
        "30 s elapsed, ETA by count 10 min 30 s",
        "1 min 00 s elapsed, ETA by count 16 min 36 s",
        "nothing finished for 50 s",
        "nothing finished for 1 min 20 s",
    ]
    assert not any("still running" in line for line in lines)
