"""Directories the suite writes into, checked before any work starts.

A report or a study that runs for minutes and then cannot write its files has
wasted the run; :func:`writable_directory` refuses such a directory up front,
with one line naming the parameter.
"""

from __future__ import annotations

import os
from pathlib import Path


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
        existing = next(p for p in (Path(os.path.abspath(directory)), *Path(os.path.abspath(directory)).parents)
                        if p.exists() or p == p.parent)
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
