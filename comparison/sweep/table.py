"""The sweep's table: one CSV row per cell, every input and result, and its JSON metadata.

CSV, not Parquet: on a table of 10,000 rows of these columns the CSV is 3.0 MB
(0.9 MB gzipped), written and read back by the standard library; Parquet makes
it 0.9 MB and writes it faster, but needs ``pyarrow``, a 55 MB wheel (170 MB
installed), to save disk space nobody misses at this size, while a CSV opens in
every tool (the times: docs/speed.md, "What the code's choices rest on").
Floats are written exactly (``repr``), so a table read back gives the same
numbers; ``nan`` is a NaN, an empty field a value that does not apply.
"""

from __future__ import annotations

import csv
import json
import math
import os
import platform
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from comparison.sweep.plan import NOT_APPLICABLE, NOT_RUN
from comparison.utilities.outputs import csv_text, write_text
from macro.solve import STATUSES as MACRO_STATUSES
from micro.backends.base import Status
from micro.nonassociative.nonassociative_result import STATUSES as ITERATED_STATUSES

#: The table's columns, in order. ``load_factor`` is the value to quote and the one compared with the macro
#: model, of the wall as built: for the non-associative method the lowest certified collapse state
#: (``quoted`` says which), its iterated LP's own value in ``iterated_load_factor``, and ``lowest_stop``
#: whether the descent finished. ``half_blocks`` is the wall's length in half blocks (not a whole number:
#: its courses end as ``ends`` says). Where a local mechanism governs (a sliver's, ``local_mechanism`` says
#: what moves), ``held_load_factor`` is the same analysis with the slivers held, a different wall reported
#: beside it (``docs/micro/walls.md``).
COLUMNS = (
    "cell",
    "wall",
    "t",
    "m",
    "rows",
    "f",
    "p",
    "storeys",
    "method",
    "kind",
    "solver",
    "scheme",
    "first_course",
    "head_joints",
    "ends",
    "half_blocks",
    "blocks",
    "load_factor",
    "quoted",
    "iterated_load_factor",
    "lowest_stop",
    "held_load_factor",
    "local_mechanism",
    "status",
    "iterations",
    "direction",
    "associative_load_factor",
    "band_lo",
    "band_hi",
    "mechanism_band_lo",
    "mechanism_band_hi",
    "rocking_load_factor",
    "alpha_c_deg",
    "hinge_storey",
    "mechanism",
    "seconds",
    "cached",
    "message",
)
#: Columns that depend on the run, not on the cell: when and where it was computed.
RUN_COLUMNS = ("seconds", "cached")

#: The status of a cell whose computation gave no record, by the executor's outcome.
FAILURE_STATUS = {"failed": "error", "lost": "worker_died", "refused": "refused_memory"}
#: Every status a row can hold: the macro model's, the associative LP's back ends', the iterated LP's, a
#: cell not computed (:data:`~comparison.sweep.plan.NOT_APPLICABLE`, ``NOT_RUN``), a computation that gave
#: no record (:data:`FAILURE_STATUS`) and a user model's ``failed`` (no load factor) or ``error``.
STATUSES = frozenset({*MACRO_STATUSES, *(s.value for s in Status), *ITERATED_STATUSES, NOT_APPLICABLE, NOT_RUN,
                      *FAILURE_STATUS.values(), "failed"})

def _text(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else repr(value)
    return str(value)


def write_table(rows: Iterable[Mapping[str, Any]], path: Path) -> Path:
    """Write ``rows`` (dicts keyed by :data:`COLUMNS`; missing keys are empty) as CSV, whole or not at all."""
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_text(path, csv_text([COLUMNS, *([_text(row.get(c)) for c in COLUMNS] for row in rows)]))


def read_table(path: Path) -> list[dict[str, str]]:
    """The rows of a sweep table, as strings keyed by column."""
    with Path(path).open(newline="") as fh:
        return list(csv.DictReader(fh))


def number(text: str) -> float:
    """A table field as a float (NaN when empty)."""
    return float(text) if text else math.nan


def machine() -> dict[str, Any]:
    """The machine the sweep ran on."""
    return {
        "python": platform.python_version(),
        "platform": platform.platform(),
        "machine": platform.machine(),
        "processor": platform.processor(),
        "cpus": os.cpu_count(),
    }


def write_meta(meta: Mapping[str, Any], path: Path) -> Path:
    """Write the metadata as JSON, whole or not at all."""
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_text(path, json.dumps(meta, indent=1, default=str) + "\n")
