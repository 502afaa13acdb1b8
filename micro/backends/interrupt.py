"""Signals during a solver's compiled code: the solver is stopped through its own callback, never unwound.

HiGHS and Clarabel call back into Python while they solve (HiGHS' simplex
and interior-point interrupt callbacks, Clarabel's termination callback).
Python runs its signal handlers in the main thread between bytecodes, so a
Ctrl-C during a solve raised ``KeyboardInterrupt`` INSIDE such a callback,
and the exception unwound through the solver's C++ frames: HiGHS caught it,
reported "Solve error", and the next run of the same model crashed the
process (a segmentation fault, highspy 1.16; seen as Ctrl-C segfaulting
``xcheck micro --friction nonassociative``). Without a callback the handler
waited for the solve to end (minutes on a large wall).

:func:`deferred_signals` wraps one call into a solver: every signal with a
Python handler is only recorded while the solver runs; a recorded Ctrl-C
(a handler that raises ``KeyboardInterrupt``) sets :attr:`SolverStop.requested`,
which the solver's callback reads to stop the solver its own way; once the
solver has returned, the recorded handlers run (Ctrl-C raises
``KeyboardInterrupt`` there, in Python code). A callback never raises: an
error inside it is kept (:meth:`SolverStop.keep`) and raised again after the
solver returned (:meth:`SolverStop.raise_kept`).
"""

from __future__ import annotations

import _signal  # the C module under ``signal``: its functions without the enum wrapping (below)
import signal
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any

Handler = Callable[[int, FrameType | None], Any]

#: The signals a handler can be set for. :func:`deferred_signals` reads every one's handler through
#: ``_signal``: ``signal.getsignal`` converts to enums, around every LP a cost near a warm LP's own; ``_signal``
#: reads all 62 a few hundred times faster (docs/speed.md).
_SIGNALS = tuple(int(s) for s in signal.valid_signals())


class SolverStop:
    """What a solver's callback reads (:attr:`requested`) and where it leaves an error.

    Attributes:
        requested: a Ctrl-C arrived during the solve; the callback stops the solver.
        error: an exception raised inside the callback, raised again after the solve.
    """

    def __init__(self) -> None:
        self.requested = False
        self.error: BaseException | None = None

    def keep(self, exc: BaseException) -> None:
        """Keep an exception raised inside the callback; the solver is stopped."""
        if self.error is None:
            self.error = exc
        self.requested = True

    def raise_kept(self) -> None:
        """Raise the exception kept by :meth:`keep`, if any (after the solver returned)."""
        exc, self.error = self.error, None
        if exc is not None:
            raise exc


def _stops_the_solver(handler: Handler) -> bool:
    """Whether ``handler`` ends the program's work (Python's Ctrl-C handler raises ``KeyboardInterrupt``)."""
    return handler is signal.default_int_handler


@contextmanager
def deferred_signals(stop: SolverStop) -> Iterator[None]:
    """Around one call into a solver (module docstring): every signal with a
    Python handler is recorded, a Ctrl-C also sets ``stop.requested``; the
    recorded handlers run when the call returns, in the order the signals came.

    In a thread other than the main one nothing changes: Python runs signal
    handlers in the main thread only, so none can run inside a callback there.
    """
    stop.requested = False
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    saved: dict[int, Handler] = {}
    pending: list[tuple[int, FrameType | None]] = []

    def record(signum: int, frame: FrameType | None) -> None:
        pending.append((signum, frame))
        if _stops_the_solver(saved[signum]):
            stop.requested = True

    try:
        for signum in _SIGNALS:
            handler = _signal.getsignal(signum)
            if callable(handler):
                saved[signum] = handler
                _signal.signal(signum, record)
        yield
    finally:
        for signum, handler in saved.items():
            _signal.signal(signum, handler)
        stop.requested = False
        for signum, frame in pending:
            saved[signum](signum, frame)
