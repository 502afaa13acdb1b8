"""Stability of the iterated non-associative LP.

* :mod:`~comparison.stability.study`: the grid of small walls, the settings,
  and the runs (typed :class:`~comparison.stability.study.StudyRun`);
* :mod:`~comparison.stability.render`: the summary, ``stability.csv``,
  ``stability.md`` and ``stability.png``;
* :mod:`~comparison.stability.table7`: Table 7's walls per setting, bond phase
  and head-joint friction (``table7_nonassoc.md``).
"""

from comparison.stability.render import summarise, write_reports
from comparison.stability.study import GRID, SETTINGS, Setting, StudyRun, WallCase, grid_walls, main_study, run_study
from comparison.stability.table7 import table7_variants

__all__ = [
    "GRID",
    "SETTINGS",
    "Setting",
    "StudyRun",
    "WallCase",
    "grid_walls",
    "main_study",
    "run_study",
    "summarise",
    "table7_variants",
    "write_reports",
]
