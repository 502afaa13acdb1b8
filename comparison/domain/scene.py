"""TOML scenes: a dimensional wall given storey by storey.

Format (see ``examples/three-storey.toml``)::

    name = "three-storey wall"     # optional label

    [wall]
    length = 6.0          # L
    unit_weight = 18.0    # gamma, force per volume (optional, default 1)
    friction = 0.6        # f
    ends = "closers"      # how the block wall's courses end (optional: "closers", the default, or "cut")

    [block]
    length = 0.30         # l (the overlap is l/2)
    height = 0.10         # b

    [[storey]]            # storey 1 is the top one, as in the paper
    rows = 20
    thickness = 0.10      # b_i (optional, default: the block height)
    overload = 2.0        # q_i, floor load per unit length on top of the storey (optional, default 0)

Any unit system works as long as it is consistent; the load factor does not
depend on it. Every error names the file, the key and, where it can, its line;
values are held to the physical bounds of :func:`macro.checks.wall_bounds`. A
scene is UTF-8 text (a byte-order mark is allowed) of at most
:data:`MAX_SCENE_BYTES`.
"""

from __future__ import annotations

import codecs
import re
from pathlib import Path
from typing import Any

from comparison.domain.wall import ENDS, StoreySpec, WallSpec
from comparison.utilities.inputs import parse_toml, read_input_file
from comparison.utilities.toml_source import TomlSource, key_line
from macro.checks import friction, magnitude

#: Largest scene file read (a scene is a few hundred bytes; this refuses a wrong file before reading it whole).
MAX_SCENE_BYTES = 1 << 20

#: The scene key of each parameter of the wall (table, key) for the line of an error.
_SCENE_KEYS = {
    "length": ("wall", "length"),
    "block_length": ("block", "length"),
    "block_height": ("block", "height"),
    "unit_weight": ("wall", "unit_weight"),
    "friction": ("wall", "friction"),
    "rows": ("storey", "rows"),
}

#: How a storey is written, for the messages of a scene whose storeys are missing or misspelt.
STOREY_HOWTO = (
    "write each storey as a table of its own: a line [[storey]], then rows = N on the next "
    "(optionally thickness, overload); storey 1 is the top one"
)

_ALLOWED: dict[str, set[str]] = {
    "": {"name", "wall", "block", "storey"},
    "wall": {"length", "unit_weight", "friction", "ends"},
    "block": {"length", "height"},
    "storey": {"rows", "thickness", "overload"},
}
_REQUIRED: dict[str, set[str]] = {
    "wall": {"length", "friction"},
    "block": {"length", "height"},
    "storey": {"rows"},
}


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
        data = read_input_file(path, MAX_SCENE_BYTES)
    except OSError as exc:
        raise SceneError(f"scene {path}: cannot read ({exc.strerror or exc})") from None
    if len(data) > MAX_SCENE_BYTES:
        raise SceneError(f"scene {path}: larger than {MAX_SCENE_BYTES:,} bytes; a scene is a short TOML text")
    return parse_scene(decode_scene(data, str(path)), source=str(path))


def decode_scene(data: bytes, source: str) -> str:
    """The text of a scene file: UTF-8, with or without a byte-order mark.

    Raises:
        SceneError: UTF-16/32 text or bytes that are not UTF-8, naming the file and the line.
    """
    if data.startswith((codecs.BOM_UTF32_LE, codecs.BOM_UTF32_BE, codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        raise SceneError(f"scene {source}: UTF-16 or UTF-32 text; save the scene as UTF-8")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise SceneError(
            f"scene {source} (line {line}): not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); "
            "a scene is a TOML text file"
        ) from None


def parse_scene(text: str, source: str = "<scene>") -> WallSpec:
    """Parse the text of a TOML scene; see :func:`load_scene`."""
    try:
        data = parse_toml(text)
    except ValueError as exc:
        raise SceneError(f"scene {source}: {exc}") from None
    src = TomlSource(text, source, "scene", SceneError)
    tables = _tables(data, src)
    name = data.get("name", Path(source).stem)
    if not isinstance(name, str):
        raise src.error(f"name must be a string, got {name!r}", "", "name")
    return _wall(tables, name, src)


def _tables(data: dict[str, Any], src: TomlSource[SceneError]) -> dict[str, list[dict[str, Any]]]:
    """The tables of the scene, every key known and every required key there."""
    for key in data:
        if key not in _ALLOWED[""]:
            hint = f"; {STOREY_HOWTO}" if key == "storeys" else ""
            raise (
                src.error(f"unknown key {key!r}{hint}", "", key)
                if key_line(src.text, "", key)
                else src.error(f"unknown table [{key}]", key)
            )
    tables: dict[str, list[dict[str, Any]]] = {}
    for table in ("wall", "block"):
        if table not in data:
            raise SceneError(f"scene {src.source}: missing table [{table}]")
        if not isinstance(data[table], dict):
            raise src.error(f"[{table}] must be a table", table)
        tables[table] = [data[table]]
        _check_keys(table, 0, data[table], src)  # a storey written as a key of [wall] is named as such
    storeys = data.get("storey")
    if "storey" not in data:
        raise SceneError(f"scene {src.source}: no [[storey]] given: {STOREY_HOWTO}")
    if isinstance(storeys, dict):
        raise src.error(f"[storey] is a single table, not one per storey: {STOREY_HOWTO}", "storey")
    if not isinstance(storeys, list) or not storeys:
        raise src.error(f"storey = {storeys!r} gives no storey: {STOREY_HOWTO}", "", "storey")
    tables["storey"] = storeys
    for index, entry in enumerate(storeys):
        if not isinstance(entry, dict):
            raise src.error(f"[[storey]] entry {index + 1} must be a table, got {entry!r}", "storey", None, index)
        _check_keys("storey", index, entry, src)
    return tables


def _check_keys(table: str, index: int, entry: dict[str, Any], src: TomlSource[SceneError]) -> None:
    """Every key of the ``index``-th ``[table]`` known, every required one there."""
    for key in entry:
        if key not in _ALLOWED[table]:
            hint = f"; {STOREY_HOWTO}" if key in ("storey", "storeys") else ""
            raise src.error(f"unknown key {key!r} in [{table}]{hint}", table, key, index)
    for key in sorted(_REQUIRED[table] - set(entry)):
        raise src.error(f"missing key {key!r} in [{table}]", table, None, index)


def _wall(tables: dict[str, list[dict[str, Any]]], name: str, src: TomlSource[SceneError]) -> WallSpec:
    """The wall of checked tables; a bad value is worded with the wall vocabulary and its line."""
    scalars = {}
    for param, (table, key) in _SCENE_KEYS.items():
        if table == "storey":
            continue
        check = friction if key == "friction" else magnitude
        try:
            scalars[param] = check(f"{table}.{key}", tables[table][0].get(key, 1.0 if key == "unit_weight" else None))
        except ValueError as exc:
            raise src.error(str(exc), table, key) from None
    ends = tables["wall"][0].get("ends", ENDS[0])
    if ends not in ENDS:
        raise src.error(f"wall.ends must be one of {', '.join(ENDS)}, got {ends!r}", "wall", "ends")
    height = scalars["block_height"]
    built: list[StoreySpec] = []
    for i, entry in enumerate(tables["storey"]):
        try:
            built.append(StoreySpec(entry["rows"], entry.get("thickness", height), entry.get("overload", 0.0)))
        except ValueError as exc:
            key = str(exc).split(" must", 1)[0]
            raise src.error(f"storey {i + 1}: {exc}", "storey", key, i) from None
    try:
        return WallSpec(storeys=tuple(built), name=name, ends=ends, **scalars)
    except ValueError as exc:
        raise _bound_error(str(exc), src) from None


def _bound_error(message: str, src: TomlSource[SceneError]) -> SceneError:
    """A physical bound of the wall (``macro.checks.wall_bounds``) in the scene's terms, with the key's line."""
    param, _, rest = message.partition(" must")
    entry = re.fullmatch(r"(\w+)\[(\d+)\]", param)
    if entry:
        key, index = entry.group(1), int(entry.group(2))
        return src.error(f"storey {index + 1}: {key} must{rest}", "storey", key, index)
    table, key = _SCENE_KEYS.get(param, ("", param))
    return src.error(f"{table}.{key} must{rest}" if table != "storey" else message, table, key)
