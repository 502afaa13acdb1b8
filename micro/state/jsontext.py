"""Strict JSON for the state files: no ``NaN``, no key twice in an object, and the line of any field.

Python's reader keeps the last copy of a repeated key where another reader may keep the first, so that two
programs would read two different states from one file: :func:`loads` refuses a repeated key, naming it
and its line. :func:`line_of` finds the line of a field (``blocks[12].weight``) in the text, so that a
reader's message names the line a person opens the file at.
"""

from __future__ import annotations

import contextlib
import json
import re
from json.decoder import scanstring  # type: ignore[attr-defined]
from typing import Any

#: A field's path as the reader names it: ``blocks[12].vertices[3]`` -> ``blocks``, 12, ``vertices``, 3.
_PART = re.compile(r"\.?([A-Za-z_][A-Za-z_0-9]*)|\[(\d+)\]")
_SPACE = re.compile(r"[ \t\n\r]*")
_SCALAR = re.compile(r"-?(?:0|[1-9]\d*)(?:\.\d+)?(?:[eE][-+]?\d+)?|true|false|null|NaN|-?Infinity")


class JsonError(ValueError):
    """Text that is not strict JSON, or an object with a key twice.

    Attributes:
        line: the line (from 1) of the problem, or 0 when not known.
    """

    def __init__(self, message: str, line: int = 0) -> None:
        super().__init__(message)
        self.line = line


class _Repeated(Exception):
    def __init__(self, key: str) -> None:
        self.key = key


def _unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise _Repeated(key)
        out[key] = value
    return out


def _constant(name: str) -> Any:
    raise JsonError(f"not strict JSON ({name} is not a JSON number)")


def loads(text: str) -> Any:
    """The JSON document of ``text``.

    Raises:
        JsonError: not JSON (its line), ``NaN`` or ``Infinity``, an integer of more digits than Python
            reads, JSON nested too deeply, or a key twice in one object (the key and the line of its
            second copy).
    """
    try:
        return json.loads(text, parse_constant=_constant, object_pairs_hook=_unique)
    except json.JSONDecodeError as exc:
        raise JsonError(f"(line {exc.lineno}, column {exc.colno}): not JSON ({exc.msg})", exc.lineno) from None
    except RecursionError:
        raise JsonError("not a state file (JSON nested too deeply)") from None
    except _Repeated as exc:
        line = _repeated_line(text, exc.key)
        where = f"(line {line}): " if line else ""
        raise JsonError(f"{where}the key {json.dumps(exc.key)} is given twice in one object (readers differ on "
                        "which copy they keep)", line) from None
    except JsonError:
        raise
    except ValueError as exc:  # an integer of more digits than Python reads
        raise JsonError(f"not strict JSON ({exc})") from None


def _walk(text: str, pos: int, path: tuple[str | int, ...], seen: Any) -> int:
    """Walk the JSON value at ``pos`` (its path ``path``); call ``seen(path, pos)`` at every value and
    ``seen(path + (key,), key_pos, repeated)`` at every key of an object; return the value's end."""
    pos = _SPACE.match(text, pos).end()  # type: ignore[union-attr]
    seen(path, pos)
    c = text[pos]
    if c in "{[":
        close, k, keys = ("}" if c == "{" else "]"), 0, set()
        pos = _SPACE.match(text, pos + 1).end()  # type: ignore[union-attr]
        while text[pos] != close:
            if c == "{":
                key, end = scanstring(text, pos + 1)
                seen(path + (key,), pos, key in keys)
                keys.add(key)
                pos = _walk(text, _SPACE.match(text, end).end() + 1, path + (key,), seen)  # type: ignore[union-attr]
            else:
                pos = _walk(text, pos, path + (k,), seen)
                k += 1
            pos = _SPACE.match(text, pos).end()  # type: ignore[union-attr]
            if text[pos] == ",":
                pos = _SPACE.match(text, pos + 1).end()  # type: ignore[union-attr]
        return pos + 1
    if c == '"':
        return scanstring(text, pos + 1)[1]
    m = _SCALAR.match(text, pos)
    return m.end() if m else pos + 1


def _first_line(text: str, wanted: Any) -> int:
    """The line of the first place of the walk where ``wanted(path, repeated)`` holds (0: none, or text the
    walk cannot read)."""
    found: list[int] = []

    def seen(path: tuple[str | int, ...], pos: int, repeated: bool | None = None) -> None:
        if not found and wanted(path, repeated):
            found.append(text.count("\n", 0, pos) + 1)

    with contextlib.suppress(IndexError, ValueError, RecursionError):  # text the walk cannot read: no line
        _walk(text, 0, (), seen)
    return found[0] if found else 0


def _repeated_line(text: str, key: str) -> int:
    """The line of the second copy of ``key`` in one object of ``text`` (0 if not found)."""
    return _first_line(text, lambda path, repeated: bool(repeated) and path[-1] == key)


def line_of(text: str, where: str) -> int:
    """The line (from 1) where the field ``where`` (``blocks[12].weight``; ``""``: the document) starts in
    ``text``, a JSON document; 0 when it is not found."""
    path = tuple(m.group(1) if m.group(1) else int(m.group(2)) for m in _PART.finditer(where))
    return _first_line(text, lambda p, repeated: p == path)
