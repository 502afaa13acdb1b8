"""The stability studies run and written: ``xcheck stability`` and ``xcheck stability --lowest``.

Each study computes in one module (:mod:`~comparison.stability.study`,
:mod:`~comparison.stability.lowest`) and writes in another
(:mod:`~comparison.stability.render`, :mod:`~comparison.stability.lowest_render`);
this module composes the two, so that neither imports the other's partner
back (data flows one way: runs, then files).
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable
from pathlib import Path

from comparison.stability.lowest import run_cases, study_cases
from comparison.stability.lowest_render import write_lowest
from comparison.stability.render import write_reports
from comparison.stability.study import SETTINGS, Setting, grid_walls, run_study
from comparison.utilities.progress import NORMAL, Progress


def main_study(
    out: str | os.PathLike[str] = "reports",
    *,
    processes: int = 2,
    quick: bool = False,
    settings: Iterable[Setting] = SETTINGS,
    verbosity: int = NORMAL,
) -> dict[str, Path]:
    """Run the study and write the reports (``quick``: 12 walls only, for a smoke test).

    ``verbosity`` sets what the progress display shows (see :mod:`comparison.utilities.progress`).
    """
    walls = grid_walls()
    if quick:
        walls = walls[:: max(1, len(walls) // 12)][:12]
    chosen = tuple(settings)
    t0 = time.perf_counter()
    with Progress(verbosity) as progress:
        progress.say(
            f"plan: {len(walls)} walls x {len(chosen)} settings = {len(walls) * len(chosen)} iterated LPs "
            f"in {processes} processes"
        )
        progress.start(len(walls), "walls")
        runs = run_study(walls, chosen, processes=processes, progress=progress)
    return write_reports(runs, Path(out), seconds=time.perf_counter() - t0, processes=processes)


def main_lowest(out: str | os.PathLike[str] = "reports", *, processes: int = 2, quick: bool = False) -> dict[str, Path]:
    """Run the study and write ``lowest.md``, ``lowest.csv`` and ``lowest.png`` to ``out``."""
    t0 = time.perf_counter()
    runs = run_cases(study_cases(quick), processes)
    return write_lowest(runs, Path(out), seconds=time.perf_counter() - t0, processes=processes)
