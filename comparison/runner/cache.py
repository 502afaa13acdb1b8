"""The on-disk result cache.

A record is stored as JSON (:meth:`Record.to_dict`) under a key made of the
wall, the method and its options, the cache format, and the *code version* of
every package the method runs (a hash of their source files and of the runner),
so that a re-run computes only what changed: editing ``micro`` recomputes the
micro results and keeps the macro ones. A micro mechanism (block velocities)
is stored beside its record, for the figures.

Where the cache lives: ``--cache DIR`` on the command line, else the
environment variable ``XCHECK_CACHE``, else ``$XDG_CACHE_HOME/xcheck``
(``~/.cache/xcheck`` when ``XDG_CACHE_HOME`` is not set); see
:func:`default_cache_dir`. The Python API takes the directory explicitly.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import asdict
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from comparison.runner.methods import PACKAGES, Method
from comparison.runner.records import Mechanism, Record
from comparison.wall import WallSpec

#: Part of every key: bump it when the stored form of a record changes, so that
#: entries of an older form are never misread (2: typed records).
CACHE_FORMAT = 2

_ROOT = Path(__file__).resolve().parents[2]


def default_cache_dir() -> Path:
    """``$XCHECK_CACHE``, else ``$XDG_CACHE_HOME/xcheck``, else ``~/.cache/xcheck``."""
    if os.environ.get("XCHECK_CACHE"):
        return Path(os.environ["XCHECK_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "xcheck"


@cache
def code_version(*packages: str) -> str:
    """Hash of the source of ``packages``, of the runner and of the failure-mode code."""
    h = hashlib.sha256()
    files = [p for pkg in packages for p in sorted((_ROOT / pkg).rglob("*.py"))]
    files += sorted((_ROOT / "comparison" / "runner").glob("*.py")) + [_ROOT / "comparison" / "failure.py"]
    for path in files:
        h.update(path.relative_to(_ROOT).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _wall_key(spec: WallSpec) -> dict[str, Any]:
    d = asdict(spec)
    d.pop("name", None)
    return d


class ResultCache:
    """Records (and micro mechanisms) on disk, one JSON file per (wall, method).

    Args:
        directory: where the entries live (created on the first store).
    """

    def __init__(self, directory: Path) -> None:
        self.directory = Path(directory)

    def path(self, spec: WallSpec, method: Method) -> Path:
        """The file of the record of ``method`` on ``spec``."""
        key = {
            "wall": _wall_key(spec),
            "method": method.key(),
            "code": code_version(*PACKAGES[method.kind]),
            "format": CACHE_FORMAT,
        }
        digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:24]
        return self.directory / method.kind / f"{digest}.json"

    def __contains__(self, item: tuple[WallSpec, Method]) -> bool:
        return self.path(*item).exists()

    def load(self, spec: WallSpec, method: Method) -> Record | None:
        """The stored record, or ``None``."""
        path = self.path(spec, method)
        if not path.exists():
            return None
        return Record.from_dict(json.loads(path.read_text()), cached=True)

    def store(self, spec: WallSpec, record: Record, mechanism: Mechanism | None) -> None:
        """Store ``record`` (and its mechanism) as the entry of ``spec``."""
        path = self.path(spec, record.method)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(record.to_dict(), indent=1))
        if mechanism is not None:
            np.savez_compressed(
                path.with_suffix(".npz"), velocities=mechanism.velocities, direction=np.array(mechanism.direction)
            )

    def mechanism(self, spec: WallSpec, method: Method) -> Mechanism | None:
        """The stored mechanism of a micro record, or ``None``."""
        npz = self.path(spec, method).with_suffix(".npz")
        if not npz.exists():
            return None
        with np.load(npz) as data:
            return Mechanism(data["velocities"], str(data["direction"]))
