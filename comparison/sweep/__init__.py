"""Sweeps: the macro and micro models over a grid of walls, at scale.

* :mod:`~comparison.sweep.grid`: the grid file (axes, bonds, methods, limits);
* :mod:`~comparison.sweep.plan`: the cells, one per (wall, method, bond);
* :mod:`~comparison.sweep.run`: :func:`run_sweep`, the macro side vectorised,
  the micro side on an executor (local processes or Dask) through the cache;
* :mod:`~comparison.sweep.table`: the CSV table and its JSON metadata.
"""

from comparison.sweep.grid import Grid, GridError, GridMethod, load_grid, parse_grid
from comparison.sweep.plan import Cell, WallPoint, cells
from comparison.sweep.run import SweepRun, run_sweep
from comparison.sweep.table import COLUMNS, RUN_COLUMNS, read_table

__all__ = [
    "COLUMNS",
    "RUN_COLUMNS",
    "Cell",
    "Grid",
    "GridError",
    "GridMethod",
    "SweepRun",
    "WallPoint",
    "cells",
    "load_grid",
    "parse_grid",
    "read_table",
    "run_sweep",
]
