"""Task functions for the executor tests (module level, so that worker processes import them by name)."""

from __future__ import annotations

import os
import signal
import time


def square(x: int) -> int:
    """``x * x``."""
    return x * x


def fail(message: str) -> None:
    """Raise ``ValueError(message)``."""
    raise ValueError(message)


def die() -> None:
    """Kill this worker process (as the kernel's out-of-memory killer would)."""
    os.kill(os.getpid(), signal.SIGKILL)


def pid_after(seconds: float) -> int:
    """This worker's process id, after sleeping ``seconds``."""
    time.sleep(seconds)
    return os.getpid()
