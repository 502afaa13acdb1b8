"""Stability of the iterated non-associative LP.

* :mod:`~comparison.stability.study`: the grid of small walls, the settings,
  and the runs (typed :class:`~comparison.stability.study.StudyRun`);
* :mod:`~comparison.stability.render`: the summary, ``stability.csv``,
  ``stability.md`` and ``stability.png``;
* :mod:`~comparison.stability.lowest` and :mod:`~comparison.stability.lowest_render`: the
  iterated LP against the lowest certified state and the global minimum (``lowest.md``);
* :mod:`~comparison.stability.main`: each study run, then written (``xcheck stability``);
* :mod:`~comparison.stability.table7`: Table 7's walls per setting, bond phase
  and head-joint friction (``table7_nonassoc.md``).
"""

from comparison.stability.main import main_lowest, main_study
from comparison.stability.render import summarise, write_reports
from comparison.stability.study import GRID, SETTINGS, Setting, StudyRun, WallCase, grid_walls, run_study
from comparison.stability.table7 import table7_variants

__all__ = [
    "GRID",
    "SETTINGS",
    "Setting",
    "StudyRun",
    "WallCase",
    "grid_walls",
    "main_lowest",
    "main_study",
    "run_study",
    "summarise",
    "table7_variants",
    "write_reports",
]
