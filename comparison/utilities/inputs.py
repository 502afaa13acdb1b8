"""Files the suite reads (scenes, grids, walls files): regular files only, refused at once otherwise.

The reader is :func:`micro.files.read_input_file` (``micro`` reads state files with it too): it opens
without blocking and refuses a named pipe, a directory or a device with an ``OSError`` whose
``strerror`` says what it is.
"""

from __future__ import annotations

from micro.files import read_input_file

__all__ = ["read_input_file"]
