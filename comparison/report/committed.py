"""The committed tables the report reads and does not recompute, and the one place it looks for them.

Three sections of the report render tables that take hours to compute and are
committed with it: the error map (``sweeps/errormap.csv``), Table 9's walls with
coarser bonds (``sweeps/table9_bond.csv``) and the lowest collapse load
(``lowest.csv``). The report reads them from one stated directory, its *tables
directory*: ``xcheck report --tables DIR`` (``build_report(tables_dir=...)``), by
default the report's own output directory (``--out``, ``reports`` by default),
where the commands of :data:`MADE_BY` write them. Nothing is read through the
source tree, so an installed package behaves as a clone does. A table that is
not there is said loudly: a warning naming its path and the command that makes
it (``xcheck: warning: ...`` on the command line), and its section of
``REPORT.md`` says it is missing.
"""

from __future__ import annotations

import warnings
from pathlib import Path

#: The error map's sweep table, relative to the tables directory.
ERRORMAP = "sweeps/errormap.csv"
#: Table 9's walls with coarser bonds.
BOND = "sweeps/table9_bond.csv"
#: The lowest collapse load on Table 7's walls (the study's table).
LOWEST = "lowest.csv"
#: The command that writes each table into the tables directory ``DIR``.
MADE_BY = {
    ERRORMAP: "xcheck sweep examples/sweeps/errormap.toml --out DIR/sweeps",
    BOND: "xcheck sweep examples/sweeps/table9_bond.toml --out DIR/sweeps",
    LOWEST: "xcheck stability --lowest --out DIR",
}


class MissingTableWarning(UserWarning):
    """A committed table the report needs is not in its tables directory."""


def committed_table(tables_dir: Path, name: str) -> Path | None:
    """The path of the committed table ``name`` (:data:`ERRORMAP`, :data:`BOND`, :data:`LOWEST`) in
    ``tables_dir``, or ``None`` after a :class:`MissingTableWarning` when it is not there."""
    path = Path(tables_dir) / name
    if path.is_file():
        return path
    make = MADE_BY[name].replace("DIR", str(tables_dir))
    warnings.warn(
        f"the report's table {path} is missing, and its section says so: make it with `{make}`, or give "
        "--tables DIR (build_report(tables_dir=...)) naming the directory that holds it",
        MissingTableWarning,
        stacklevel=2,
    )
    return None
