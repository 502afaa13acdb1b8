"""Where and how the suite writes its files.

A report or a study that runs for minutes and then cannot write its files has
wasted the run; :func:`writable_directory` refuses such a directory up front,
with one line naming the parameter.

Every text output (``.md``, ``.json``, ``.csv``, ``timings.json``; figures go
through :func:`micro.plot.save_figure` the same way) is written whole or not
at all (:func:`write_atomic`): into a temporary file beside it, flushed to
disk, then renamed over its name. A full disk, a kill or an error mid-write
leaves the old file (or none) and no temporary file: never a cut-short page or
a 0-byte JSON.
"""

from __future__ import annotations

import contextlib
import csv
import functools
import io
import os
import tempfile
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any


def writable_directory(name: str, path: str | os.PathLike[str], *, create: bool = True) -> Path:
    """``path`` as a directory this process can write into, created (with its parents) if missing.

    Args:
        name: the parameter, as the caller spells it (``--out``, ``cache_dir``).
        path: the directory.
        create: False to check only, creating nothing (a command checks every input before it makes a
            folder, so that bad input leaves nothing behind): the directory, or the nearest folder above
            it that exists, must be a directory this process can write into.

    Raises:
        ValueError: ``"{name}: cannot write to {path!r} (reason)"``: the path
            is a file, or cannot be created or written; ``"{name} must name a
            directory, got ''"`` for an empty string (which would mean the
            working directory).
    """
    if isinstance(path, str) and not path.strip():
        raise ValueError(f"{name} must name a directory, got {path!r}")
    directory = Path(path)
    if directory.exists() and not directory.is_dir():
        raise ValueError(f"{name}: cannot write to {str(directory)!r} (it is a file, not a directory)")
    if not create:
        absolute = Path(os.path.abspath(directory))
        existing = next(p for p in (absolute, *absolute.parents) if os.path.exists(p) or p == p.parent)
        if not existing.is_dir():
            raise ValueError(f"{name}: cannot write to {str(directory)!r} ({str(existing)!r} is a file, not a "
                             "directory)")
        if not os.access(existing, os.W_OK | os.X_OK):
            raise ValueError(f"{name}: cannot write to {str(directory)!r} (permission denied)")
        return directory
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"{name}: cannot write to {str(directory)!r} ({exc.strerror or exc})") from None
    if not os.access(directory, os.W_OK | os.X_OK):
        raise ValueError(f"{name}: cannot write to {str(directory)!r} (permission denied)")
    return directory


def write_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` through a unique temporary file in the same folder, flushed and renamed.

    A reader sees the old file or the new one, never a part of either; two writers each rename a whole
    file of their own; on any failure (a full disk: ``ENOSPC``) the temporary file is removed and the
    error raised.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, _file_mode())  # a temporary file is private (0600); the output is not
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return path


@functools.cache
def _file_mode() -> int:
    """The mode ``open()`` gives a new file: ``0o666`` less the process's umask (read once)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` whole or not at all (:func:`write_atomic`)."""
    return write_atomic(path, text.encode("utf-8"))


def csv_text(rows: Iterable[Sequence[Any]]) -> str:
    """``rows`` as CSV text, as :func:`csv.writer` writes them into a file opened with ``newline=""``."""
    buf = io.StringIO(newline="")
    csv.writer(buf).writerows(rows)
    return buf.getvalue()
