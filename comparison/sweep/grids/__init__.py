"""The grid files of the report's committed sweeps, installed with the package.

``errormap.toml`` and ``table9_bond.toml`` are copies of ``examples/sweeps/``'s (a test holds them
equal): the report's warning for a missing sweep table names a command that works from an installed
wheel as well as from a clone, ``xcheck sweep`` on the file :func:`grid_path` gives.
"""

from __future__ import annotations

from pathlib import Path

#: The folder of the packaged grid files.
FOLDER = Path(__file__).resolve().parent
#: The grids the package carries, by name (the file ``NAME.toml``).
NAMES = ("errormap", "table9_bond")


def grid_path(name: str) -> Path:
    """The installed grid file ``name`` (one of :data:`NAMES`).

    Raises:
        ValueError: ``name`` is not a packaged grid, naming the ones there are.
    """
    if name not in NAMES:
        raise ValueError(f"no packaged grid {name!r}: the package carries {', '.join(NAMES)}")
    return FOLDER / f"{name}.toml"
