"""What a long run tells the person watching it: the plan, then its progress, then what it wrote.

Everything goes to stderr (stdout keeps the result). What is shown follows the
verbosity the command line passes down:

* ``QUIET`` (``--quiet``): nothing;
* ``NORMAL`` (the default): the plan, then on a terminal a progress bar with
  counts and ETA (tqdm's), elsewhere (a log, a pipe, CI) a status line each time
  another :data:`LOG_STEP` of the work is done or :data:`LOG_SECONDS` have passed
  since the last line, whichever comes first (done, cached, to go, elapsed,
  ETA), then the closing summary (e.g. the paths written);
* ``VERBOSE`` (``--verbose``): the same, and one line per computation.

While nothing finishes (one computation can run for minutes) a heartbeat
thread keeps the display alive: off a terminal it writes the status line
once :data:`LOG_SECONDS` have passed without one, ending ``nothing finished
for <time since the last computation finished>`` when none finished since the
previous line (otherwise the plain line: the count moved); on a terminal it
refreshes the bar (its elapsed time). Without it a report's log can stay
silent for the minutes its largest walls take.

The ETA weighs each computation by its expected cost (the run passes it to
:meth:`Progress.start` and :meth:`Progress.advance`: the seconds a wall of its
blocks takes, or the time it took last time; see
:func:`comparison.runner.pool.expected_seconds`): the time elapsed times the
cost to go over the cost done. Counting instead, as if every computation took
as long as the average finished one, a report that runs its largest walls
first said "14 of 88 done, ETA 1 h 26 min" two minutes before its end. Where
no cost is known the status line says ``ETA by count``.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable
from typing import TextIO

from tqdm import tqdm

QUIET, NORMAL, VERBOSE = -1, 0, 1

#: Off a terminal, a status line at least each time this share of the work is done ...
LOG_STEP = 0.1
#: ... or this many seconds have passed since the last line, whichever comes first.
LOG_SECONDS = 30.0
#: Real seconds between two looks of the heartbeat thread at the display.
HEARTBEAT_SECONDS = 5.0


def duration(seconds: float) -> str:
    """``"45 s"``, ``"12 min 05 s"``, ``"2 h 03 min"``."""
    s = max(0, round(seconds))
    if s < 60:
        return f"{s} s"
    if s < 3600:
        return f"{s // 60} min {s % 60:02d} s"
    return f"{s // 3600} h {s % 3600 // 60:02d} min"


class Progress:
    """The plan, the progress and the summary of one run; a context manager that closes the bar.

    Args:
        verbosity: :data:`QUIET`, :data:`NORMAL` or :data:`VERBOSE`.
        stream: where to write (default ``sys.stderr``).
        clock: seconds, for the status lines (default ``time.monotonic``).
        heartbeat: real seconds between the heartbeat thread's looks at the
            display (module docstring); ``None``: no heartbeat.
    """

    def __init__(
        self, verbosity: int = NORMAL, stream: TextIO | None = None, clock: Callable[[], float] = time.monotonic,
        heartbeat: float | None = HEARTBEAT_SECONDS,
    ) -> None:
        self.stream = sys.stderr if stream is None else stream
        tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.verbosity = verbosity
        self.show_bar = verbosity >= NORMAL and tty
        self.show_text = verbosity >= NORMAL
        self.show_status = verbosity >= NORMAL and not tty
        self._clock = clock
        self._bar: tqdm | None = None
        self._what, self._total, self._done, self._cached = "", 0, 0, 0
        self._cost_total: float | None = None
        self._cost_done = 0.0
        self._start = self._last = self._finished = 0.0
        self._last_done = 0
        self._heartbeat = heartbeat
        self._lock = threading.RLock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def say(self, text: str) -> None:
        """A line of the plan or of the summary (shown unless quiet)."""
        if not self.show_text:
            return
        with self._lock:
            if self._bar is not None:
                self._bar.write(text, file=self.stream)
            else:
                print(text, file=self.stream, flush=True)

    def start(self, total: int, what: str, cached: int = 0, cost: float | None = None) -> None:
        """Begin ``total`` steps labelled ``what`` (``cached``: the plan's entries already done, for the
        status lines; ``cost``: the steps' expected cost in all, which the ETA weighs by, each step
        then giving its own to :meth:`advance`; ``None``: the ETA counts steps); no bar when there is
        nothing to do."""
        self.close()
        self._what, self._total, self._done, self._cached = what, total, 0, cached
        self._cost_total = cost if cost is not None and cost > 0 else None
        self._cost_done = 0.0
        self._start = self._last = self._finished = self._clock()
        self._last_done = 0
        if self.show_bar and total > 0:
            self._bar = tqdm(total=total, desc=what, unit="run", file=self.stream, dynamic_ncols=True, smoothing=0.1)
        if total > 0 and self._heartbeat is not None and (self.show_bar or self.show_status):
            self._stop.clear()
            self._thread = threading.Thread(target=self._beat, name="xcheck-progress", daemon=True)
            self._thread.start()

    def _beat(self) -> None:
        """The heartbeat (module docstring): until :meth:`close`."""
        assert self._heartbeat is not None
        while not self._stop.wait(self._heartbeat):
            self.beat()

    def beat(self) -> None:
        """One look of the heartbeat at the display: refresh the bar, or off a terminal the status line once
        :data:`LOG_SECONDS` have passed since the last, ending ``nothing finished for ...`` when the count has
        not moved since that line."""
        with self._lock:
            if self._bar is not None:
                self._bar.refresh()
            elif self.show_status and self._done < self._total:
                now = self._clock()
                if now - self._last >= LOG_SECONDS:
                    line = self.status(now)
                    if self._done == self._last_done:
                        line += f"; nothing finished for {duration(now - self._finished)}"
                    self.say(line)
                    self._last, self._last_done = now, self._done

    def advance(self, line: str = "", cost: float | None = None) -> None:
        """One step done; ``line`` says what (printed when verbose), ``cost`` its expected cost (see
        :meth:`start`; ``None``: the average step's)."""
        with self._lock:
            self._advance(line, cost)

    def _advance(self, line: str, cost: float | None) -> None:
        self._done += 1
        if self._cost_total is not None:
            self._cost_done += self._cost_total / max(self._total, 1) if cost is None else max(cost, 0.0)
        now = self._finished = self._clock()
        if self._bar is not None:
            self._bar.update(1)
        if line and self.verbosity >= VERBOSE:
            self.say(line)
        if self.show_status and self._total > 0:
            step = self._done - self._last_done >= LOG_STEP * self._total
            if step or now - self._last >= LOG_SECONDS or self._done >= self._total:
                self.say(self.status(now))
                self._last, self._last_done = now, self._done

    def status(self, now: float | None = None) -> str:
        """``"micro: 12 of 88 done (14 %), 40 cached, 76 to go; 2 min 05 s elapsed, ETA 3 min 40 s"``
        (the ETA: module docstring; ``ETA by count ...`` without costs)."""
        now = self._clock() if now is None else now
        elapsed = now - self._start
        left = max(self._total - self._done, 0)
        if not self._done:
            eta = "unknown"
        elif self._cost_total is not None and self._cost_done > 0:
            to_go = max(self._cost_total - self._cost_done, 0.0) if left else 0.0
            eta = duration(elapsed / self._cost_done * to_go)
        else:
            eta = f"by count {duration(elapsed / self._done * left)}"
        share = 100 * self._done // self._total if self._total else 100
        return (f"{self._what}: {self._done} of {self._total} done ({share} %), {self._cached} cached, {left} to go; "
                f"{duration(elapsed)} elapsed, ETA {eta}")

    def close(self) -> None:
        """Stop the heartbeat; close the bar (it stays on the screen)."""
        if self._thread is not None:
            self._stop.set()
            self._thread.join()
            self._thread = None
        if self._bar is not None:
            self._bar.close()
            self._bar = None
