"""The on-disk result cache: crash-safe and safe for concurrent runs.

A record is stored as JSON (:meth:`Record.to_dict`) under a key made of the
wall, the method and its options, the cache format, and the fingerprint of what
the computation runs (:func:`~comparison.runner.fingerprint.code_version`: what
every repository module it imports *does*, the versions of the packages they
import, Python's minor version), so that an entry is served only where the code
would compute it again. A docstring, comment or formatting edit keeps every
cached result; any other edit of a module the computation imports (a constant,
a statement, a renamed or moved module), another solver version or another
Python recomputes them. A micro mechanism (block velocities) is stored beside
its record, for the figures.

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

How an entry is read, so that no file in the cache folder can hang a run or
exhaust its memory (a cache folder is shared, synced, restored from backups):

* a file is opened without following a symbolic link and without blocking
  (:func:`comparison.utilities.inputs.read_input_file`), and only a regular file is read:
  a FIFO, a directory, a device, a symbolic link (to ``/dev/zero``, or a loop),
  an unreadable file or a kind folder that is a file is a :class:`CacheWarning`
  and a recompute, like a truncated entry;
* a record file is read only up to :data:`MAX_RECORD_BYTES`, a mechanism file
  up to :data:`MAX_MECHANISM_BYTES` (its arrays, unpacked, likewise, checked
  before they are unpacked): a larger file (a 3 GB sparse file) is refused the
  same way after that many bytes.

Reading an entry therefore holds at most one record file, one mechanism file
and its arrays at a time (:data:`MAX_RECORD_BYTES` + 2 x
:data:`MAX_MECHANISM_BYTES`, 129 MiB, as a hard bound; real entries are
hundreds of times smaller), and nothing is kept between reads: checking a folder of
thousands of entries takes the memory of one (no folder is ever listed).

A run killed mid-write leaves at most a ``.*.tmp`` file, which no reader
opens. Where the cache lives: ``--cache DIR`` on the command line, else the
environment variable ``XCHECK_CACHE``, else ``$XDG_CACHE_HOME/xcheck``
(``~/.cache/xcheck`` when ``XDG_CACHE_HOME`` is not set); see
:func:`default_cache_dir`. The Python API takes the directory explicitly.
"""

from __future__ import annotations

import errno
import hashlib
import io
import json
import os
import warnings
import zipfile
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from comparison.domain.wall import WallSpec
from comparison.runner.fingerprint import code_version
from comparison.runner.methods import Method
from comparison.runner.records import MechanismRecord, Record
from comparison.utilities.inputs import read_input_file
from comparison.utilities.outputs import write_atomic

#: Part of every key: bump it when the stored form of a record changes, so that
#: entries of an older form are never misread (2: typed records; 3: the record
#: names its mechanism file and that file's hash; 4: the non-associative record's
#: ``load_factor`` is the value to quote, the iterated LP's ``iterated_load_factor``).
CACHE_FORMAT = 4

#: The largest record file read (bytes). A record is scalars and the load factor of every LP of the
#: iterated sequence, a few kB (the research page on the cache and outputs (docs/research/) measures them): a cap
#: hundreds of times the largest refuses no real entry and bounds what a read holds.
MAX_RECORD_BYTES = 1 << 20
#: The largest mechanism file read, and the most its arrays may unpack to (bytes): 24 bytes a block,
#: 0.17 MB for the report's largest wall (7,575 blocks); 64 MiB is 2.8 million blocks, far beyond what
#: the micro methods solve.
MAX_MECHANISM_BYTES = 64 << 20

#: Statuses and stop reasons of a result cut short by a wall-clock limit: not stored.
WALL_CLOCK_STOPS = frozenset({"time_limit", "time_budget"})

class CacheWarning(UserWarning):
    """A cache entry that cannot be read; it is recomputed and replaced."""


def default_cache_dir() -> Path:
    """``$XCHECK_CACHE``, else ``$XDG_CACHE_HOME/xcheck``, else ``~/.cache/xcheck``."""
    if os.environ.get("XCHECK_CACHE"):
        return Path(os.environ["XCHECK_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "xcheck"


def _wall_key(spec: WallSpec) -> dict[str, Any]:
    d = asdict(spec)
    d.pop("name", None)
    return d


def stopped_by_wall_clock(record: Record) -> bool:
    """True when ``record``'s result was cut short by a wall-clock limit (see :data:`WALL_CLOCK_STOPS`)."""
    nonassoc = record.nonassoc
    return record.status in WALL_CLOCK_STOPS or (nonassoc is not None and nonassoc.stop_reason in WALL_CLOCK_STOPS)


class _Corrupt(Exception):
    """An entry on disk that cannot be read (the message says why)."""


def _read_capped(path: Path, limit: int) -> bytes:
    """The bytes of the regular file ``path``, not through a symbolic link, read without blocking and at
    most ``limit`` (+ 1) of them.

    Raises:
        FileNotFoundError: no such file.
        OSError: it cannot be opened, is a symbolic link or is not a regular file (the message says which).
        _Corrupt: larger than ``limit``.
    """
    data = read_input_file(path, limit, follow_symlinks=False)
    if len(data) > limit:
        raise _Corrupt(f"more than the {limit:,} bytes a cache file may have")
    return data


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
            "code": code_version(self.directory),
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
        except OSError as exc:  # unreadable, a symbolic link, a kind folder that is a file
            why = "a symbolic link, which the cache never writes" if exc.errno == errno.ELOOP else exc.strerror
            warnings.warn(f"cache entry {path} cannot be opened ({why or exc}); recomputing it",
                          CacheWarning, stacklevel=2)
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
            write_atomic(npz, data, follow_symlinks=False)
            stored["mechanism"] = {"file": npz.name, "sha256": sha}
        write_atomic(path, json.dumps(stored, indent=1).encode(), follow_symlinks=False)

    def _read(self, path: Path) -> tuple[Record, MechanismRecord | None]:
        """Read and check one entry.

        Raises:
            FileNotFoundError: no record.
            OSError: a record that cannot be opened (no permission, a symbolic link, a folder on the path
                that is a file).
            _Corrupt: a record or arrays that cannot be read (not a regular file, too large, damaged).
        """
        raw = _read_capped(path, MAX_RECORD_BYTES)
        try:
            stored = json.loads(raw)
            if stored.get("format") != CACHE_FORMAT:
                raise _Corrupt(f"format {stored.get('format')!r}, expected {CACHE_FORMAT}")
            record = Record.from_dict(stored["record"], cached=True)
            ref = stored["mechanism"]
        except _Corrupt:
            raise
        except Exception as exc:  # noqa: BLE001 - whatever a damaged record raises (JSON, nesting, fields)
            raise _Corrupt(f"{type(exc).__name__}: {exc}"[:300] if raw else "empty file") from None
        if ref is None:
            return record, None
        return record, self._arrays(path, ref)

    @staticmethod
    def _arrays(path: Path, ref: Any) -> MechanismRecord:
        """The mechanism file a record names, checked against its hash."""
        try:
            npz = path.with_name(ref["file"])
            if npz.parent != path.parent:
                raise _Corrupt(f"its mechanism file {ref['file']!r} is not beside it")
            data = _read_capped(npz, MAX_MECHANISM_BYTES)
        except (OSError, KeyError, TypeError, ValueError) as exc:
            raise _Corrupt(f"its mechanism file cannot be read: {exc}") from None
        if hashlib.sha256(data).hexdigest() != ref.get("sha256"):
            raise _Corrupt(f"its mechanism file {npz.name} does not match the hash the record names")
        try:
            with zipfile.ZipFile(io.BytesIO(data)) as archive:
                unpacked = sum(info.file_size for info in archive.infolist())
            if unpacked > MAX_MECHANISM_BYTES:
                raise _Corrupt(f"its mechanism file {npz.name} unpacks to {unpacked:,} bytes, more than "
                               f"the {MAX_MECHANISM_BYTES:,} read")
            with np.load(io.BytesIO(data)) as arrays:
                return MechanismRecord(np.array(arrays["velocities"]), str(arrays["direction"]))
        except _Corrupt:
            raise
        except Exception as exc:  # noqa: BLE001 - whatever damaged arrays raise
            raise _Corrupt(f"its mechanism file {npz.name} cannot be read: {type(exc).__name__}: {exc}") from None

