"""Where and how the suite writes its files.

A report or a study that runs for minutes and then cannot write its files has
wasted the run; :func:`writable_directory` refuses such a directory up front,
with one line naming the parameter.

Every text output (``.md``, ``.json``, ``.csv``, ``timings.json``; figures go
through :func:`micro.plot.save_figure` the same way) is written whole or not
at all (:func:`write_atomic`, :func:`micro.files.write_whole`): into a
temporary file beside it, flushed to disk, then renamed over its name. A full
disk, a kill or an error mid-write leaves the old file (or none) and no
temporary file: never a cut-short page or a 0-byte JSON.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from micro.files import write_whole


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


#: Write bytes to a path whole or not at all (the suite's one writer, :func:`micro.files.write_whole`).
write_atomic = write_whole


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` whole or not at all (:func:`write_atomic`)."""
    return write_atomic(path, text.encode("utf-8"))


def csv_text(rows: Iterable[Sequence[Any]]) -> str:
    """``rows`` as CSV text, as :func:`csv.writer` writes them into a file opened with ``newline=""``."""
    buf = io.StringIO(newline="")
    csv.writer(buf).writerows(rows)
    return buf.getvalue()
