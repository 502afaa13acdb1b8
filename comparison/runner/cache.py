"""The on-disk result cache: crash-safe and safe for concurrent runs.

A record is stored as JSON (:meth:`Record.to_dict`) under a key made of the
wall, the method and its options, the cache format, and the *code version* of
every package the method runs (a hash of their source files and of the runner),
so that a re-run computes only what changed: editing ``micro`` recomputes the
micro results and keeps the macro ones. A micro mechanism (block velocities)
is stored beside its record, for the figures.

How an entry is written, so that a crash or a second run never leaves a
misleading one:

* every file is written to a unique temporary file in the same directory,
  flushed to disk and renamed over its final name (``os.replace`` is atomic),
  so a reader sees the whole old file or the whole new one, never a part;
* the mechanism's arrays are written first, under a name that holds the hash
  of their bytes (``<key>.<hash>.npz``, never overwritten by other bytes), and
  the record last, naming that file and its hash: a record on disk implies its
  arrays, and two runs storing the same entry at once each leave a consistent
  pair (the last rename of the record wins);
* a record that cannot be read (truncated, not JSON, of another form) or whose
  arrays are missing or do not match their hash is reported with its path as a
  :class:`CacheWarning` and treated as missing: it is recomputed and replaced;
* a result stopped by a wall-clock limit (status ``time_limit``, or the
  iterated LP's ``time_budget``) is not stored: another run, on another
  machine, would have gone further, so it is recomputed next time.

A run killed mid-write leaves at most a ``.*.tmp`` file, which no reader
opens. Where the cache lives: ``--cache DIR`` on the command line, else the
environment variable ``XCHECK_CACHE``, else ``$XDG_CACHE_HOME/xcheck``
(``~/.cache/xcheck`` when ``XDG_CACHE_HOME`` is not set); see
:func:`default_cache_dir`. The Python API takes the directory explicitly.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import tempfile
import warnings
from dataclasses import asdict
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from comparison.runner.methods import PACKAGES, Method
from comparison.runner.records import MechanismRecord, Record
from comparison.wall import WallSpec

#: Part of every key: bump it when the stored form of a record changes, so that
#: entries of an older form are never misread (2: typed records; 3: the record
#: names its mechanism file and that file's hash; 4: the non-associative record's
#: ``load_factor`` is the value to quote, the iterated LP's ``iterated_load_factor``).
CACHE_FORMAT = 4

#: Statuses and stop reasons of a result cut short by a wall-clock limit: not stored.
WALL_CLOCK_STOPS = frozenset({"time_limit", "time_budget"})

_ROOT = Path(__file__).resolve().parents[2]


class CacheWarning(UserWarning):
    """A cache entry that cannot be read; it is recomputed and replaced."""


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


def write_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a unique temporary file, flushed and renamed.

    A reader sees the old file or the new one, never a part of either; two
    writers each rename a whole file of their own.
    """
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def stopped_by_wall_clock(record: Record) -> bool:
    """True when ``record``'s result was cut short by a wall-clock limit (see :data:`WALL_CLOCK_STOPS`)."""
    nonassoc = record.nonassoc
    return record.status in WALL_CLOCK_STOPS or (nonassoc is not None and nonassoc.stop_reason in WALL_CLOCK_STOPS)


class _Corrupt(Exception):
    """An entry on disk that cannot be read (the message says why)."""


class ResultCache:
    """Records (and micro mechanisms) on disk, one JSON file per (wall, method).

    Args:
        directory: where the entries live (created on the first store).
    """

    def __init__(self, directory: Path) -> None:
        self.directory = Path(directory)
        self.unwritable = False  # a store failed (warned once); later stores are tried again

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
        """True when a readable entry (record and arrays) is stored."""
        return self.entry(*item) is not None

    def entry(self, spec: WallSpec, method: Method) -> tuple[Record, MechanismRecord | None] | None:
        """The stored record and its mechanism, or ``None`` (missing, or unreadable: then warned).

        Warns:
            CacheWarning: the entry exists but cannot be read; the message gives its path and why.
        """
        path = self.path(spec, method)
        try:
            return self._read(path)
        except FileNotFoundError:
            return None
        except _Corrupt as exc:
            warnings.warn(f"cache entry {path} is unreadable ({exc}); recomputing it", CacheWarning, stacklevel=2)
            return None

    def load(self, spec: WallSpec, method: Method) -> Record | None:
        """The stored record, or ``None`` (see :meth:`entry`)."""
        found = self.entry(spec, method)
        return None if found is None else found[0]

    def mechanism(self, spec: WallSpec, method: Method) -> MechanismRecord | None:
        """The stored mechanism of a micro record, or ``None`` (see :meth:`entry`)."""
        found = self.entry(spec, method)
        return None if found is None else found[1]

    def store(self, spec: WallSpec, record: Record, mechanism: MechanismRecord | None) -> bool:
        """Store ``record`` (and its mechanism) as the entry of ``spec``, arrays first, record last.

        Returns:
            False when the record was not stored: its result was cut short by a
            wall-clock limit (:func:`stopped_by_wall_clock`), or the cache cannot
            be written (a full or read-only disk: warned once per cache, a
            :class:`CacheWarning`). The caller keeps such a record for its run:
            a result is never lost because the cache could not take it (a
            report on a full cache disk computed all its results, then exited
            with no report).
        """
        if stopped_by_wall_clock(record):
            return False
        try:
            self._store(spec, record, mechanism)
        except OSError as exc:
            if not self.unwritable:
                warnings.warn(f"cannot write the cache {self.directory} ({exc.strerror or exc}); "
                              "results are kept for this run only", CacheWarning, stacklevel=2)
            self.unwritable = True
            return False
        return True

    def _store(self, spec: WallSpec, record: Record, mechanism: MechanismRecord | None) -> None:
        """:meth:`store`'s writes (arrays first, record last)."""
        path = self.path(spec, record.method)
        path.parent.mkdir(parents=True, exist_ok=True)
        stored: dict[str, Any] = {"format": CACHE_FORMAT, "record": record.to_dict(), "mechanism": None}
        if mechanism is not None:
            buf = io.BytesIO()
            np.savez_compressed(buf, velocities=mechanism.velocities, direction=np.array(mechanism.direction))
            data = buf.getvalue()
            sha = hashlib.sha256(data).hexdigest()
            npz = path.with_name(f"{path.stem}.{sha[:16]}.npz")
            write_atomic(npz, data)
            stored["mechanism"] = {"file": npz.name, "sha256": sha}
        write_atomic(path, json.dumps(stored, indent=1).encode())

    def _read(self, path: Path) -> tuple[Record, MechanismRecord | None]:
        """Read and check one entry.

        Raises:
            FileNotFoundError: no record.
            _Corrupt: a record or arrays that cannot be read.
        """
        raw = path.read_bytes()
        try:
            stored = json.loads(raw)
            if stored.get("format") != CACHE_FORMAT:
                raise _Corrupt(f"format {stored.get('format')!r}, expected {CACHE_FORMAT}")
            record = Record.from_dict(stored["record"], cached=True)
            ref = stored["mechanism"]
        except _Corrupt:
            raise
        except (ValueError, KeyError, TypeError, AttributeError) as exc:  # JSONDecodeError is a ValueError
            raise _Corrupt(f"{type(exc).__name__}: {exc}" if raw else "empty file") from None
        if ref is None:
            return record, None
        return record, self._arrays(path, ref)

    @staticmethod
    def _arrays(path: Path, ref: Any) -> MechanismRecord:
        """The mechanism file a record names, checked against its hash."""
        try:
            npz = path.with_name(ref["file"])
            data = npz.read_bytes()
        except (OSError, KeyError, TypeError) as exc:
            raise _Corrupt(f"its mechanism file cannot be read: {exc}") from None
        if hashlib.sha256(data).hexdigest() != ref.get("sha256"):
            raise _Corrupt(f"its mechanism file {npz.name} does not match the hash the record names")
        with np.load(io.BytesIO(data)) as arrays:
            return MechanismRecord(np.array(arrays["velocities"]), str(arrays["direction"]))
