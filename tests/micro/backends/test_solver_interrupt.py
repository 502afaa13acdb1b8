"""Signals during a solver's compiled code (micro/backends/interrupt.py): the solver is stopped
through its own callback and the signal's handler runs after it returned; nothing unwinds through it.

Each HiGHS case runs in a child process: before the fix a Ctrl-C inside HiGHS' callback left the
model broken and its next run crashed the process (a segmentation fault), which would have taken
the test runner with it. The signal is raised from inside the callback itself, so the case is
deterministic (a Ctrl-C at a random time is the ``processes`` test in tests/comparison/cli). The cases in a
child process are marked ``processes`` (``pytest -m processes``, as ``.ci/run`` runs them).
"""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import warnings

import pytest

from micro.backends.interrupt import SolverStop, deferred_signals

#: A model of the Table 7 Set 12 wall (12 rows) and the StallGuard's count replaced by ``TICK``:
#: each case defines ``TICK`` (called at every simplex interrupt callback) before this runs.
MODEL = """
import signal, sys
# the child's Ctrl-C as a fresh interpreter's, whatever the test process left to inherit (an ignored
# or blocked SIGINT stays so across exec)
INHERITED = (signal.getsignal(signal.SIGINT), signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, []))
signal.signal(signal.SIGINT, signal.default_int_handler)
signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
import numpy as np
from comparison.domain.wall import WallSpec
import micro
from micro.backends import highs as H

lp = micro.assemble(WallSpec.from_paper(t=1.0, m=1 / 3, rows=12, f=0.75).to_micro())
calls = [0]

def tick(self, iteration):
    calls[0] += 1
    TICK(calls[0])
    return False

H.StallGuard.tick = tick
m = H.PersistentHighsModel.of(lp, 1, algorithm="simplex")
m.guard_stalls()
"""


def _child(case: str) -> subprocess.CompletedProcess[str]:
    code = textwrap.dedent(case).replace("MODEL", MODEL)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)


@pytest.mark.processes  # a child process that gets the signal
def test_ctrl_c_inside_highs_stops_the_run_and_raises_after_it() -> None:
    """A Ctrl-C raised inside HiGHS' callback: the run stops there (HiGHS' own
    interrupt), ``KeyboardInterrupt`` comes out of ``run()``, and the same model
    then solves to its optimum (no "Solve error", no crash of the next run)."""
    out = _child("""
        def TICK(n):
            if n == 5:
                signal.raise_signal(signal.SIGINT)
        MODEL
        try:
            m.run()
            print("no interrupt", calls[0], "calls; inherited SIGINT handler and blocked:", INHERITED)
        except KeyboardInterrupt:
            print("interrupted after", calls[0], "calls")
        TICK = lambda n: None
        m.clear_solver()
        m.set_algorithm("ipm", crossover=True)
        again = m.run()
        print(again.status.value, again.x[-1] if again.x is not None else None)
    """)
    assert out.returncode == 0, out.stderr[-2000:]
    lines = out.stdout.splitlines()
    assert lines[0].startswith("interrupted after"), out.stdout
    assert int(lines[0].split()[2]) <= 7  # stopped at once, not at the end of the run
    status, lam = lines[1].split()
    assert status == "optimal" and float(lam) > 0.5


@pytest.mark.processes  # a child process that gets the signal
def test_an_error_inside_the_callback_is_raised_after_highs_returned() -> None:
    out = _child("""
        def TICK(n):
            if n == 3:
                raise RuntimeError("inside the callback")
        MODEL
        try:
            m.run()
        except RuntimeError as exc:
            print("raised:", exc)
        TICK = lambda n: None
        m.clear_solver()
        print(m.run().status.value)
    """)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.splitlines() == ["raised: inside the callback", "optimal"]


@pytest.mark.processes  # a child process that gets the signal
def test_a_signal_with_its_own_handler_waits_for_the_run_and_does_not_stop_it() -> None:
    """A handler other than Ctrl-C's (here SIGUSR1's) is only deferred: the run is not
    interrupted (its result stays what it would have been) and the handler runs once."""
    out = _child("""
        import signal
        seen = []
        signal.signal(signal.SIGUSR1, lambda s, f: seen.append(calls[0]))
        def TICK(n):
            if n == 2:
                signal.raise_signal(signal.SIGUSR1)
        MODEL
        out = m.run()
        print(out.status.value, len(seen), seen[0] == calls[0])
    """)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["optimal", "1", "True"]


def test_deferred_signals_restores_the_handlers_and_runs_the_pending_ones_in_order() -> None:
    seen: list[int] = []

    def handler(signum: int, frame: object) -> None:
        seen.append(signum)

    previous = signal.signal(signal.SIGUSR1, handler)
    previous_int = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        stop = SolverStop()
        with pytest.raises(KeyboardInterrupt), deferred_signals(stop):
            assert signal.getsignal(signal.SIGUSR1) is not handler
            signal.raise_signal(signal.SIGUSR1)
            signal.raise_signal(signal.SIGUSR1)
            assert seen == [] and not stop.requested  # not a Ctrl-C: the solver goes on
            signal.raise_signal(signal.SIGINT)
            assert stop.requested and seen == []  # the solver is asked to stop; nothing raised yet
        assert seen == [signal.SIGUSR1, signal.SIGUSR1] and not stop.requested
        assert signal.getsignal(signal.SIGUSR1) is handler
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGUSR1, previous)
        signal.signal(signal.SIGINT, previous_int)


def test_solver_stop_keeps_the_first_error() -> None:
    stop = SolverStop()
    stop.keep(ValueError("first"))
    stop.keep(KeyError("second"))
    assert stop.requested
    with pytest.raises(ValueError, match="first"):
        stop.raise_kept()
    stop.raise_kept()  # nothing kept any more


def test_the_cvxpy_back_end_solves_clarabel_through_its_interrupt(monkeypatch: pytest.MonkeyPatch) -> None:
    """cvxpy's own Clarabel interface has no termination callback (a Ctrl-C waited for the solve); the back end
    hands the solver cvxpy builds to ``solve_interruptibly``, and gives cvxpy's own answer."""
    import micro
    import micro.backends.cvxpy_ as cv
    from comparison.domain.wall import WallSpec
    from micro.backends.cvxpy_ import CvxpyBackend

    calls: list[str] = []
    through = cv.solve_interruptibly

    def spy(solver: object) -> object:
        calls.append(type(solver).__name__)
        return through(solver)

    monkeypatch.setattr(cv, "solve_interruptibly", spy)
    lp = micro.assemble(WallSpec.from_paper(t=1.0, m=1 / 3, rows=6, f=0.75).to_micro())
    backend = CvxpyBackend(lp)
    ours = backend.solve(+1)
    assert calls and set(calls) == {"DefaultSolver"} and ours.status.value == "optimal"  # a retry: twice
    with warnings.catch_warnings():  # cvxpy's own interface with the same settings, and the same retry
        warnings.simplefilter("ignore")
        backend.problem.solve(solver="CLARABEL", **backend.options)
        if backend.problem.status == "optimal_inaccurate" and backend.retry is not None:
            backend.problem.solve(solver="CLARABEL", **backend.retry)
    assert ours.load_factor == pytest.approx(float(backend.lam.value), rel=1e-9)
