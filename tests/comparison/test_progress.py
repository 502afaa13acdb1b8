"""The progress display: what each verbosity shows on a terminal and elsewhere."""

from __future__ import annotations

import io

import pytest

from comparison.utilities.progress import NORMAL, QUIET, VERBOSE, Progress


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
    """Off a terminal, without ``-q``, a long run prints the plan, a status line each time another 10 % is
    done or 30 s have passed since the last (done, cached, to go, elapsed, ETA), and its summary, on stderr:
    a log shows the run is alive."""
    from comparison.utilities.progress import LOG_SECONDS

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
    from comparison.utilities.progress import duration

    assert [duration(s) for s in (0.4, 59.6, 65, 3599, 7380)] == ["0 s", "1 min 00 s", "1 min 05 s", "59 min 59 s",
                                                                     "2 h 03 min"]


def test_a_log_gets_a_status_line_while_one_computation_runs_for_minutes() -> None:
    """The heartbeat: with nothing finishing, a log still gets the status line, marked "nothing finished",
    once LOG_SECONDS have passed since the last line (a full report's log had no line for 10 minutes
    while Sets 9 and 10 ran); nothing before that, and the thread ends with the display."""
    import time

    from comparison.utilities.progress import LOG_SECONDS

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
    """The heartbeat's line says ``nothing finished for <time since the last finish>`` only when no
    computation finished since the previous line; after the count moved it is the plain status line (so
    the words mean what the docs say)."""
    from comparison.utilities.progress import LOG_SECONDS

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


def test_the_eta_weighs_each_computation_by_its_expected_cost() -> None:
    """A report runs its largest walls first, so an ETA by count overestimates the rest. Fed 14 computations
    of cost 100 (done first, 100 s each) and 74 of cost 1, the weighted ETA is the cost to go at the rate so
    far (74 s), where the count would give 7,400 s."""
    stream, clock = io.StringIO(), Clock()
    costs = [100.0] * 14 + [1.0] * 74
    with Progress(NORMAL, stream, clock=clock, heartbeat=None) as p:
        p.start(len(costs), "micro", cost=sum(costs))
        for cost in costs[:14]:
            clock.now += cost
            p.advance(cost=cost)
        line = p.status()
        for cost in costs[14:]:
            clock.now += cost
            p.advance(cost=cost)
        last = p.status()
    assert line == "micro: 14 of 88 done (15 %), 0 cached, 74 to go; 23 min 20 s elapsed, ETA 1 min 14 s"
    assert last.endswith("24 min 34 s elapsed, ETA 0 s")
    # the same run counted: what an ETA by count says of it
    counted = Progress(NORMAL, io.StringIO(), clock=clock, heartbeat=None)
    counted.start(88, "micro")
    counted._done, counted._start = 14, clock.now - 1400
    assert counted.status(clock.now).endswith("ETA by count 2 h 03 min")


def test_prefetch_weighs_the_eta_by_blocks_or_by_the_time_a_computation_took_before(tmp_path) -> None:
    """The cost of a computation is the seconds a wall of its blocks is expected to take
    (:func:`~comparison.runner.pool.expected_seconds`), or the time it took before where the run knows it;
    the largest start first and the display is started on their sum."""
    from collections.abc import Iterator, Sequence

    from comparison.domain.wall import WallSpec
    from comparison.runner import MICRO_ASSOC, MICRO_NONASSOC, ResultCache, prefetch
    from comparison.runner.executor import Task, TaskOutcome
    from comparison.runner.pool import expected_seconds

    big = WallSpec.from_paper(t=1, m=1 / 3, rows=60, f=0.6, p=0, storeys=3, name="big")
    small = [WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75 + k / 100, p=0, storeys=1, name=f"s{k}")
             for k in range(20)]
    assert expected_seconds(big, MICRO_NONASSOC) > 10 * expected_seconds(big, MICRO_ASSOC)
    assert expected_seconds(big, MICRO_ASSOC) > 30 * expected_seconds(small[0], MICRO_ASSOC)
    stream, clock = io.StringIO(), Clock()

    class Serial:
        """One worker, largest first, each task taking its expected cost on the clock; every task fails
        (nothing to store)."""

        workers, memory_per_worker, where = 1, None, "test"
        seen: list[Task] = []

        def run(self, tasks: Sequence[Task]) -> Iterator[TaskOutcome]:
            for task in sorted(tasks, key=lambda t: t.cost, reverse=True):
                self.seen.append(task)
                clock.now += task.cost
                yield TaskOutcome(task, "failed", error="x")

    items = [(s, MICRO_ASSOC) for s in small] + [(big, MICRO_NONASSOC)]
    with Progress(NORMAL, stream, clock=clock, heartbeat=None) as p:
        done = prefetch(ResultCache(tmp_path), items, Serial(), p, cached=3,  # type: ignore[arg-type]
                        known={(small[0], MICRO_ASSOC): 1000.0})
    assert len(done.failures) == 21
    assert [t.key for t in Serial.seen[:2]] == [(small[0], MICRO_ASSOC), (big, MICRO_NONASSOC)]
    assert Serial.seen[0].cost == 1000.0 and Serial.seen[1].cost == expected_seconds(big, MICRO_NONASSOC)
    lines = stream.getvalue().splitlines()
    # after the first (1,000 s, as it took before): the rest is expected to take 18 s, not 20 x 1,000 s
    assert lines[0] == "micro: 1 of 21 done (4 %), 3 cached, 20 to go; 16 min 40 s elapsed, ETA 18 s"
    assert lines[1] == "micro: 4 of 21 done (19 %), 3 cached, 17 to go; 16 min 58 s elapsed, ETA 0 s"
