"""Files the suite reads (scenes, grids, walls files): regular files only, refused at once otherwise.

The reader is :func:`micro.files.read_input_file` (``micro`` reads state files with it too): it opens
without blocking and refuses a named pipe, a directory or a device with an ``OSError`` whose
``strerror`` says what it is. :func:`parse_toml` reads the text of a TOML file (a scene, a grid, a
walls file) in one place, so that every way it can be malformed is one line.
"""

from __future__ import annotations

import tomllib
from typing import Any

from micro.files import read_input_file

__all__ = ["parse_toml", "read_input_file"]


def parse_toml(text: str) -> dict[str, Any]:
    """The TOML document ``text``.

    Raises:
        ValueError: ``text`` is not TOML, with the parser's reason and line; or it nests arrays or tables
            so deep that the parser runs out of stack (``a = [[[...]]]`` 1,500 deep): a
            :class:`RecursionError` would end the program with a traceback.
    """
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"malformed TOML: {exc}") from None
    except RecursionError:
        raise ValueError("malformed TOML: arrays or tables nested too deep to read") from None
