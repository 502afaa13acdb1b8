"""TOML scenes: a dimensional wall given storey by storey.

Format (see ``examples/three-storey.toml``)::

    name = "three-storey wall"     # optional label

    [wall]
    length = 6.0          # L
    unit_weight = 18.0    # gamma, force per volume (optional, default 1)
    friction = 0.6        # f

    [block]
    length = 0.30         # l (the overlap is l/2)
    height = 0.10         # b

    [[storey]]            # storey 1 is the top one, as in the paper
    rows = 20
    thickness = 0.10      # b_i (optional, default: the block height)
    overload = 2.0        # q_i, floor load per unit length on top of the storey (optional, default 0)

Any unit system works as long as it is consistent; the load factor does not
depend on it. Every error names the key and, where it can, its line.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from typing import Any

from comparison.wall import StoreySpec, WallSpec, positive

_ALLOWED: dict[str, set[str]] = {
    "": {"name", "wall", "block", "storey"},
    "wall": {"length", "unit_weight", "friction"},
    "block": {"length", "height"},
    "storey": {"rows", "thickness", "overload"},
}
_REQUIRED: dict[str, set[str]] = {
    "wall": {"length", "friction"},
    "block": {"length", "height"},
    "storey": {"rows"},
}


def _key_line(text: str, table: str, key: str, index: int = 0) -> int | None:
    """Line number (1-based) of ``key`` inside the ``index``-th ``[table]``."""
    current, seen = "", -1
    header = re.compile(r"^\s*\[\[?\s*([A-Za-z0-9_.\-\"]+)\s*\]\]?")
    assign = re.compile(r"^\s*([A-Za-z0-9_\-\"]+)\s*=")
    for number, line in enumerate(text.splitlines(), start=1):
        h = header.match(line)
        if h:
            current = h.group(1).strip('"')
            if current == table:
                seen += 1
            continue
        a = assign.match(line)
        if a and a.group(1).strip('"') == key and current == table and (table == "" or seen == index):
            return number
    return None


def _table_line(text: str, table: str, index: int = 0) -> int | None:
    seen = -1
    for number, line in enumerate(text.splitlines(), start=1):
        if re.match(rf"^\s*\[\[?\s*{re.escape(table)}\s*\]\]?", line):
            seen += 1
            if seen == index:
                return number
    return None


class SceneError(ValueError):
    """A malformed scene file; the message names the file, key and line."""


def load_scene(path: str | Path) -> WallSpec:
    """Read a TOML scene into a :class:`WallSpec`.

    Raises:
        SceneError: unreadable file, TOML syntax error, unknown or missing
            key, or an invalid value; the message gives the key and line.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(f"scene {path}: cannot read ({exc.strerror})") from None
    return parse_scene(text, source=str(path))


class _Source:
    """The text of a scene and its name, to word errors with the key's line."""

    def __init__(self, text: str, source: str) -> None:
        self.text, self.source = text, source

    def error(self, msg: str, table: str = "", key: str | None = None, index: int = 0) -> SceneError:
        line = _key_line(self.text, table, key, index) if key else _table_line(self.text, table, index)
        where = f" (line {line})" if line else ""
        return SceneError(f"scene {self.source}{where}: {msg}")


def parse_scene(text: str, source: str = "<scene>") -> WallSpec:
    """Parse the text of a TOML scene; see :func:`load_scene`."""
    try:
        data: dict[str, Any] = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene {source}: malformed TOML: {exc}") from None
    src = _Source(text, source)
    tables = _tables(data, src)
    name = data.get("name", Path(source).stem)
    if not isinstance(name, str):
        raise src.error(f"name must be a string, got {name!r}", "", "name")
    return _wall(tables, name, src)


def _tables(data: dict[str, Any], src: _Source) -> dict[str, list[dict[str, Any]]]:
    """The tables of the scene, every key known and every required key there."""
    for key in data:
        if key not in _ALLOWED[""]:
            raise (
                src.error(f"unknown key {key!r}", "", key)
                if _key_line(src.text, "", key)
                else src.error(f"unknown table [{key}]", key)
            )
    tables: dict[str, list[dict[str, Any]]] = {}
    for table in ("wall", "block"):
        if table not in data:
            raise SceneError(f"scene {src.source}: missing table [{table}]")
        if not isinstance(data[table], dict):
            raise src.error(f"[{table}] must be a table", table)
        tables[table] = [data[table]]
    storeys = data.get("storey")
    if not storeys:
        raise SceneError(f"scene {src.source}: no [[storey]] given; a wall needs at least one storey")
    if not isinstance(storeys, list):
        raise src.error("storey must be an array of tables, written [[storey]]", "storey")
    tables["storey"] = storeys
    for table, entries in tables.items():
        for index, entry in enumerate(entries):
            _check_keys(table, index, entry, src)
    return tables


def _check_keys(table: str, index: int, entry: dict[str, Any], src: _Source) -> None:
    """Every key of the ``index``-th ``[table]`` known, every required one there."""
    for key in entry:
        if key not in _ALLOWED[table]:
            raise src.error(f"unknown key {key!r} in [{table}]", table, key, index)
    for key in sorted(_REQUIRED[table] - set(entry)):
        raise src.error(f"missing key {key!r} in [{table}]", table, None, index)


def _wall(tables: dict[str, list[dict[str, Any]]], name: str, src: _Source) -> WallSpec:
    """The wall of checked tables; a bad value is worded with the wall vocabulary and its line."""
    scalars = {}
    for table, key, default in (
        ("wall", "length", None),
        ("block", "length", None),
        ("block", "height", None),
        ("wall", "unit_weight", 1.0),
        ("wall", "friction", None),
    ):
        try:
            scalars[(table, key)] = positive(f"{table}.{key}", tables[table][0].get(key, default))
        except ValueError as exc:
            raise src.error(str(exc), table, key) from None
    height = scalars[("block", "height")]
    built: list[StoreySpec] = []
    for i, entry in enumerate(tables["storey"]):
        try:
            built.append(StoreySpec(entry["rows"], entry.get("thickness", height), entry.get("overload", 0.0)))
        except ValueError as exc:
            key = str(exc).split(" must", 1)[0]
            raise src.error(f"storey {i + 1}: {exc}", "storey", key, i) from None
    return WallSpec(
        length=scalars[("wall", "length")],
        block_length=scalars[("block", "length")],
        block_height=height,
        storeys=tuple(built),
        unit_weight=scalars[("wall", "unit_weight")],
        friction=scalars[("wall", "friction")],
        name=name,
    )
