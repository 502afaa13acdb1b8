"""What one long solve tells the person watching it (``xcheck compare``): a line per model, then the LPs.

The non-associative method of a wall of thousands of blocks runs for minutes; without a word on stderr a
user cannot tell a slow solve from a hung one. :class:`SolveProgress` is the ``progress`` of
:func:`comparison.compare`: it prints each model's line as it comes (the macro model, the associative LP),
then, while the non-associative method works, a status line at its first LP and then at most every
:data:`LINE_SECONDS`: the LPs so far, the last load factor, the stage and the time so far. It names no
expected time: the blocks do not predict it (a 7,230-block wall of square blocks takes about a minute by the
reduced wall, a 7,575-block fan of thin blocks more than ten; ``docs/speed.md``), and a wrong estimate
misleads more than none. Everything goes to stderr; ``-q`` passes no progress at all. The clock only paces
the display: no number of the result depends on it.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, TextIO

from comparison.utilities.progress import duration

if TYPE_CHECKING:  # pragma: no cover - typing only
    from micro.nonassociative import LPProgress

#: Seconds between two status lines of the non-associative method.
LINE_SECONDS = 10.0


class SolveProgress:
    """The progress lines of one :func:`comparison.compare` (module docstring).

    Args:
        blocks: the micro wall's blocks.
        stream: where the lines go (``None``: stderr).
        clock: the display's clock (``time.monotonic``; a test passes its own).
    """

    def __init__(self, blocks: int, stream: TextIO | None = None, clock: Callable[[], float] | None = None) -> None:
        self.blocks = blocks
        self.stream = stream
        self.clock = clock or time.monotonic
        self.lps = 0
        self.load_factor = math.nan
        self.started: float | None = None
        self.last_line = -math.inf

    def _print(self, text: str) -> None:
        print(text, file=self.stream if self.stream is not None else sys.stderr, flush=True)

    def __call__(self, event: str | LPProgress) -> None:
        """A model's line (``str``), or one LP of the non-associative method."""
        if isinstance(event, str):
            self._print(f"  {event}")
            return
        now = self.clock()
        if self.started is None:
            self.started = now - float(event.seconds)
        self.lps += 1
        if math.isfinite(event.load_factor):
            self.load_factor = float(event.load_factor)
        if self.lps == 1 or now - self.last_line >= LINE_SECONDS:
            self.last_line = now
            self._print(self.line(event, now - self.started))

    def line(self, event: LPProgress, elapsed: float) -> str:
        """The status line after ``event``, ``elapsed`` seconds into the method."""
        lam = f"lambda = {self.load_factor:.6f}" if math.isfinite(self.load_factor) else "no lambda yet"
        return (f"  non-associative: {self.lps} LP{'s' if self.lps != 1 else ''}, {lam} ({event.direction}, "
                f"{event.stage}), {duration(elapsed)} so far")
