"""How a HiGHS run is watched and kept quiet: the stall guard, the one callback of a run, a silent instance.

:class:`StallGuard` counts a guarded run's simplex interrupt callbacks and :class:`RunCallback`, the one
callback of a :class:`~micro.backends.highs.PersistentHighsModel`, interrupts the run when the guard fires
or a Ctrl-C arrived; :func:`quiet_highs` makes an instance that prints nothing. Split from
:mod:`micro.backends.highs` (the model and the one-shot back end), which imports them.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
import threading
from typing import TYPE_CHECKING, Any

from micro.backends.interrupt import SolverStop

if TYPE_CHECKING:
    import highspy

#: A guarded run (:meth:`PersistentHighsModel.guard_stalls`) is interrupted
#: when HiGHS calls its simplex interrupt callback this often without the
#: iteration count advancing. On scheme (b)'s infeasible third LP of the
#: 1,230-block wall single iterations took 800-1,333 calls each, seconds of work
#: from iteration ~23,970 ("possibly singular basis"), against at most 7 calls
#: per iteration in every normal run; HiGHS' ``objective_bound`` did not stop it.
STALL_CALLS = 100


class StallGuard:
    """Counts the simplex interrupt callbacks of a guarded model per simplex
    iteration and fires at :data:`STALL_CALLS` (:class:`RunCallback` then
    interrupts the run), or, with :attr:`excess` set, once the calls beyond
    one per iteration add up to it over the run. Counts, not seconds: the
    same run stops at the same iteration on every machine.

    Attributes:
        excess: the most callbacks beyond one per iteration a run may make
            (``None``: no such limit; :meth:`PersistentHighsModel.limit_excess_calls`).
    """

    def __init__(self, calls: int = STALL_CALLS) -> None:
        self.calls = calls
        self.excess: int | None = None
        self.reset()

    def reset(self) -> None:
        """Before a run."""
        self.iteration, self.count, self.fired, self.extra = -1, 0, False, 0

    def tick(self, iteration: int) -> bool:
        """One simplex interrupt callback at simplex iteration ``iteration``: whether the guard has fired."""
        if iteration != self.iteration:
            self.iteration, self.count = iteration, 0
        else:
            self.extra += 1
        self.count += 1
        self.fired = (self.fired or self.count >= self.calls
                      or (self.excess is not None and self.extra > self.excess))
        return self.fired


class RunCallback:
    """The one HiGHS callback of a :class:`PersistentHighsModel` (its simplex
    and interior-point interrupt callbacks): interrupts the run when a Ctrl-C
    arrived (:attr:`stop`, :func:`~micro.backends.interrupt.deferred_signals`)
    or the model's :class:`StallGuard` fired on a simplex iteration. It never
    raises (:mod:`micro.backends.interrupt`: an exception unwound through
    HiGHS left the model broken and the next run crashed the process).

    Args:
        simplex_type: HiGHS' code of the simplex interrupt callback (the guard counts those calls only).

    Attributes:
        guard: the stall guard (``None``: none).
        stop: the run's stop request and any error kept from the callback.
    """

    def __init__(self, simplex_type: int) -> None:
        self.simplex_type = simplex_type
        self.guard: StallGuard | None = None
        self.stop = SolverStop()

    def __call__(self, kind: Any, message: str, data_out: Any, data_in: Any, user_data: Any) -> None:
        try:
            guard = self.guard
            fired = (guard is not None and int(kind) == self.simplex_type
                     and guard.tick(int(data_out.simplex_iteration_count)))
            # set every call: HiGHS keeps the flag, and a flag left set from an
            # interrupted run interrupted every later run of the model at once
            data_in.user_interrupt = self.stop.requested or fired
        except BaseException as exc:  # anything at all: HiGHS must never see it
            self.stop.keep(exc)
            with contextlib.suppress(BaseException):
                data_in.user_interrupt = True


#: Serialises :func:`quiet_highs`' swaps of file descriptor 1 between threads.
_STDOUT_LOCK = threading.Lock()


def quiet_highs() -> highspy.Highs:
    """A new ``highspy.Highs`` with its output off.

    highspy 1.16 prints its banner (two lines) on the process's standard
    output when it builds its first instance, before any option can be set:
    it broke ``xcheck micro --json`` (one JSON line on stdout). The
    instance is built with file descriptor 1 pointed at the null device
    (C-level output; a Python-level redirect does not see it), the C
    buffers flushed before it is restored.
    """
    import highspy

    with _STDOUT_LOCK:  # two threads swapping descriptor 1 at once could leave it on the null device
        sys.stdout.flush()
        saved = os.dup(1)
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, 1)
            h = highspy.Highs()
            h.setOptionValue("output_flag", False)
        finally:
            _flush_c_stdout()
            os.dup2(saved, 1)
            os.close(saved)
            os.close(null)
    return h


def _flush_c_stdout() -> None:
    """``fflush(NULL)``: what HiGHS wrote on descriptor 1 goes out before it is restored."""
    with contextlib.suppress(OSError, AttributeError):  # no C library to ask (not seen on Linux or macOS)
        ctypes.CDLL(None).fflush(None)
