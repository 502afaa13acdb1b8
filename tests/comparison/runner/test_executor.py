"""The local executor: outcomes per task (done, failed, lost, refused), largest first, workers ended."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import psutil
import pytest
from executor_tasks import die, fail, pid_after, square

from comparison.runner.executor import LocalExecutor, Task

HERE = Path(__file__).parent


def test_outcomes_largest_first_failures_recorded_and_workers_ended() -> None:
    """One outcome per task, largest first; a task that raises, dies or does not fit never aborts the run."""
    tasks = [
        Task("ok", square, (7,), cost=1),
        Task("raises", fail, ("bad wall",), cost=2),
        Task("dies", die, (), cost=5),
        Task("huge", square, (1,), cost=9, memory=10**9),
        Task("pid", pid_after, (0.0,), cost=4),
        Task("after", square, (3,), cost=0),
    ]
    with LocalExecutor(1, memory_per_worker=10**6) as ex:
        outcomes = list(ex.run(tasks))
    by_key = {o.task.key: o for o in outcomes}
    assert [o.task.key for o in outcomes] == ["huge", "dies", "pid", "raises", "ok", "after"]
    assert by_key["ok"].kind == "done" and by_key["ok"].value == 49 and by_key["after"].value == 9
    assert by_key["raises"].kind == "failed" and "ValueError: bad wall" in by_key["raises"].error
    assert by_key["dies"].kind == "lost" and "signal 9" in by_key["dies"].error
    assert by_key["huge"].kind == "refused" and "exceeds a worker's" in by_key["huge"].error
    assert not by_key["huge"].ok and by_key["huge"].seconds == 0
    worker = by_key["pid"].value
    assert worker != os.getpid()
    assert not _gone([psutil.Process(worker)] if psutil.pid_exists(worker) else [], timeout=5)


def _descendants(pid: int, at_least: int, timeout: float = 60.0) -> list[psutil.Process]:
    """The descendants of ``pid`` once there are ``at_least`` of them."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        kids = psutil.Process(pid).children(recursive=True)
        if len(kids) >= at_least:
            return kids
        time.sleep(0.05)
    raise AssertionError(f"process {pid} never had {at_least} descendants")


def _gone(procs: list[psutil.Process], timeout: float = 10.0) -> list[psutil.Process]:
    """Those of ``procs`` still alive after ``timeout`` seconds."""
    _, alive = psutil.wait_procs(procs, timeout=timeout)
    return [p for p in alive if p.status() != psutil.STATUS_ZOMBIE]


@pytest.mark.processes
def test_workers_exit_when_the_parent_is_killed(tmp_path: Path) -> None:
    """SIGKILL the parent (no chance to clean up): its workers notice and exit, no orphan stays."""
    script = tmp_path / "parent.py"
    script.write_text(
        textwrap.dedent(
            f"""
            import sys
            sys.path.insert(0, {str(HERE)!r})
            from executor_tasks import pid_after
            from comparison.runner.executor import LocalExecutor, Task
            if __name__ == "__main__":
                with LocalExecutor(2) as ex:
                    for o in ex.run([Task(i, pid_after, (60.0,)) for i in range(2)]):
                        pass
            """
        )
    )
    proc = subprocess.Popen([sys.executable, str(script)])
    try:
        kids = _descendants(proc.pid, 3)  # the fork server and two workers
        time.sleep(0.5)
        proc.send_signal(signal.SIGKILL)
        proc.wait(10)
        assert not _gone(kids), "workers outlived their killed parent"
    finally:
        proc.kill()
