"""What a long run tells the person watching it: the plan, then a bar with counts and an ETA.

The bar is tqdm's. What is shown follows the verbosity the command line
passes down:

* ``QUIET`` (``--quiet``): nothing;
* ``NORMAL`` (the default): on a terminal the plan, a progress bar with counts
  and ETA and a closing summary; nothing when the output is not a terminal (a
  log, a pipe, CI);
* ``VERBOSE`` (``--verbose``): the plan, one line per computation and the
  summary, terminal or not (and the bar on a terminal).
"""

from __future__ import annotations

import sys
from typing import TextIO

from tqdm import tqdm

QUIET, NORMAL, VERBOSE = -1, 0, 1


class Progress:
    """The plan, a bar and lines for one run; a context manager that closes the bar.

    Args:
        verbosity: :data:`QUIET`, :data:`NORMAL` or :data:`VERBOSE`.
        stream: where to write (default ``sys.stderr``).
    """

    def __init__(self, verbosity: int = NORMAL, stream: TextIO | None = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.verbosity = verbosity
        self.show_bar = verbosity >= NORMAL and tty
        self.show_text = verbosity >= VERBOSE or self.show_bar
        self._bar: tqdm | None = None

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def say(self, text: str) -> None:
        """A line of the plan or of the summary (shown on a terminal, or when verbose)."""
        if not self.show_text:
            return
        if self._bar is not None:
            self._bar.write(text, file=self.stream)
        else:
            print(text, file=self.stream, flush=True)

    def start(self, total: int, what: str) -> None:
        """Open a bar of ``total`` steps labelled ``what`` (none when there is nothing to do)."""
        self.close()
        if self.show_bar and total > 0:
            self._bar = tqdm(total=total, desc=what, unit="run", file=self.stream, dynamic_ncols=True, smoothing=0.1)

    def advance(self, line: str = "") -> None:
        """One step done; ``line`` says what (printed when verbose)."""
        if self._bar is not None:
            self._bar.update(1)
        if line and self.verbosity >= VERBOSE:
            self.say(line)

    def close(self) -> None:
        """Close the bar (it stays on the screen)."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
