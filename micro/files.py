"""Files the suite reads and writes: read only regular files, refused at once otherwise; write whole or not at all.

``open()`` of a named pipe waits for a writer: ``xcheck micro --scene FIFO``
and ``xcheck sweep FIFO`` blocked forever. :func:`read_input_file` opens
without blocking, looks at what it opened, and refuses anything but a
regular file (a pipe, a directory, a device such as ``/dev/zero``, which
would never end) with an ``OSError`` whose ``strerror`` says what it is, so
that the callers' "cannot read (...)" lines name it. It lives in ``micro``
(the package below ``comparison``) so that :mod:`micro.state` reads a state
file with it; ``comparison.utilities.inputs`` gives it to the scenes and grids.

:func:`write_whole` writes a new file beside the target and renames it over
the target: a disk that fills up (or any error) leaves the old file or no
file, never a cut one (figures, collapse states).
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import uuid
from pathlib import Path

#: What a file that is not a regular one is, by its ``stat`` mode test.
_KINDS = (
    (stat.S_ISFIFO, "a named pipe"),
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


#: Bytes read at a time when a file is read up to a cap.
_CHUNK = 1 << 20


def read_input_file(path: str | os.PathLike[str], max_bytes: int | None = None, *,
                    follow_symlinks: bool = True) -> bytes:
    """The bytes of the regular file ``path`` (at most ``max_bytes + 1`` of them, so that a caller
    can tell a file longer than ``max_bytes``; a sparse file of gigabytes costs no more).

    Args:
        follow_symlinks: False to refuse a symbolic link as the last part of ``path`` (``ELOOP``), for
            folders the suite writes itself and never links (the result cache).

    Raises:
        OSError: the file cannot be opened or read, or is not a regular file
            (``strerror``: ``"not a regular file: a named pipe"`` and the like).
    """
    nofollow = 0 if follow_symlinks else getattr(os, "O_NOFOLLOW", 0)
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | nofollow | getattr(os, "O_CLOEXEC", 0))
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            kind = next((name for test, name in _KINDS if test(mode)), "a special file")
            raise OSError(errno.EINVAL, f"not a regular file: {kind}", str(Path(path)))
        os.set_blocking(fd, True)
        with os.fdopen(fd, "rb") as fh:
            fd = -1  # the file object closes it
            if max_bytes is None:
                return fh.read()
            # in chunks: ``read(max_bytes + 1)`` would allocate the whole cap for a file of a few bytes
            chunks, size = [], 0
            while size <= max_bytes:
                chunk = fh.read(min(_CHUNK, max_bytes + 1 - size))
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
            return b"".join(chunks)
    finally:
        if fd >= 0:
            os.close(fd)


def write_whole(path: str | os.PathLike[str], data: bytes, *, follow_symlinks: bool = True) -> Path:
    """Write ``data`` to ``path`` whole or not at all: a new temporary file beside it, renamed over it.

    The temporary file is created with mode 0o666 less the umask (as ``open`` would) and removed on any
    error; an ``OSError`` names ``path``, not the temporary file. A symbolic link is written through, as
    ``open()`` writes it: the file it points to is replaced (the temporary file beside that one) and the
    link stays, where a rename over the link replaced the link with a file (``--plot link.png``).

    Only a regular file (or a name that does not exist yet) is ever replaced: a rename over a device, a
    FIFO or a directory would put a file in its place (run as root, ``--state /dev/null`` or a cache
    entry linked to ``/dev/zero`` replaced the device node), so such a target is refused with
    ``OSError`` ("not a regular file: a character device").

    Args:
        follow_symlinks: ``False`` to replace a symbolic link itself rather than the file it points to,
            for folders the suite writes itself and never links (the result cache): a link, a FIFO or a
            device node there is damage, and the new entry takes its place (the rename replaces the name
            in that folder, never what a link pointed to).

    Returns:
        The written path.
    """
    out = Path(path)
    target = Path(os.path.realpath(out)) if follow_symlinks and out.is_symlink() else out
    try:
        mode = os.lstat(target).st_mode
    except FileNotFoundError:
        mode = None
    if follow_symlinks and mode is not None and not stat.S_ISREG(mode):
        kind = next((name for test, name in _KINDS if test(mode)), "a special file")
        raise OSError(errno.EINVAL, f"not a regular file: {kind}", str(out))
    tmp = target.with_name(f".{target.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        _write_new(tmp, data)
        os.replace(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError) and exc.errno is not None:  # named as the file asked for, not the temporary
            raise OSError(exc.errno, exc.strerror, str(out)) from None
        raise
    return out


def _write_new(path: Path, data: bytes) -> None:
    """Create ``path`` (it must not exist) holding ``data``, flushed to disk (so that a crash after the
    rename leaves the new file whole, and a full disk is seen here); mode 0o666 less the umask."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)
    with os.fdopen(fd, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())
