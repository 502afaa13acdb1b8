"""The collapse state file: JSON, written whole or not at all, read from any file without trusting it.

FORMAT (version 1; JSON Schema ``docs/schemas/state.schema.json``; dimensional, any consistent units)::

    {"format": "xcheck-masonry collapse state", "version": 1,
     "friction": "nonassociative",            # or "associative": the flow rule checked
     "load_factor": 0.6911, "direction": "+x",
     "source": {...},                         # optional, free: who wrote it and how
     "blocks": [{"vertices": [[x, y], ...], "centroid": [x, y], "weight": w,
                 "dead": [Fx, Fy, M], "live": [Fx, Fy, M]}, ...],
     "points": [{"blocks": [a, b], "position": [x, y], "normal": [nx, ny], "tangent": [tx, ty],
                 "mu": 0.75}, ...],
     "normal_forces": [...], "shear_forces": [...],          # one per point
     "velocities": [[u, v, omega], ...],                      # one per block
     "opening_rates": [...], "slip_rates": [...],             # one per point
     "contact_states": ["closed" | "opening" | "sliding", ...]}

What each entry means: :class:`~micro.state.data.CollapseStateData` (block ``-1`` is the ground; the
normal points from the first block into the second; ``live`` is the load per unit load factor as
applied, in ``direction``). The writer puts one block or point per line, so that a reader's error
names a line that means something.

READING ANY FILE. :func:`read_state` reads only a regular file (a named pipe, a directory or a device is
refused at once: :func:`micro.files.read_input_file`) of at most :data:`MAX_STATE_BYTES`, as UTF-8 (a
byte-order mark allowed), as strict JSON (no ``NaN`` or ``Infinity``), and checks every entry's type,
length, range and the geometry's consistency (unit normals, tangents orthogonal to them, blocks that
exist). Whatever is wrong raises :class:`StateFileError`: one line naming the file and the JSON line or
the field (``points[12].normal``).
"""

from __future__ import annotations

import codecs
import json
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from micro.files import read_input_file, write_whole
from micro.geometry import BlockWall
from micro.mechanism import CONTACT_STATE_NAMES
from micro.state.data import DIRECTIONS, FRICTIONS, CollapseStateData, collapse_state

#: The ``format`` of a state file.
FORMAT = "xcheck-masonry collapse state"
#: The version this module writes and reads.
VERSION = 1
#: Largest state file read (a 7,575-block wall's state is about 10 MB).
MAX_STATE_BYTES = 64 << 20
#: A normal or tangent is a unit vector, and the two orthogonal, to this tolerance (six digits pass).
UNIT_TOL = 1e-6

_TOP_KEYS = ("format", "version", "friction", "load_factor", "direction", "source", "blocks", "points",
             "normal_forces", "shear_forces", "velocities", "opening_rates", "slip_rates", "contact_states")
_BLOCK_KEYS = ("vertices", "centroid", "weight", "dead", "live")
_POINT_KEYS = ("blocks", "position", "normal", "tangent", "mu")


class StateFileError(ValueError):
    """A state file that cannot be read or is malformed; the message (one line) names the file and the
    JSON line or the field."""


# ------------------------------------------------------------------------------------------ writing
def state_document(state: CollapseStateData) -> dict[str, Any]:
    """``state`` as the JSON document of the format (plain lists and numbers; ``-0.0`` written as ``0.0``)."""
    def num(a: Any) -> Any:
        return (np.asarray(a, dtype=np.float64) + 0.0).tolist()

    blocks = [{"vertices": num(v), "centroid": num(c), "weight": num(w), "dead": num(d), "live": num(li)}
              for v, c, w, d, li in zip(state.vertices, state.centroid, state.weight, state.dead, state.live,
                                        strict=True)]
    points = [{"blocks": [int(a), int(b)], "position": num(p), "normal": num(n), "tangent": num(t), "mu": num(m)}
              for a, b, p, n, t, m in zip(state.point_a, state.point_b, state.position, state.normal,
                                          state.tangent, state.mu, strict=True)]
    return {
        "format": FORMAT, "version": VERSION, "friction": state.friction, "load_factor": float(state.load_factor),
        "direction": state.direction, "source": dict(state.source), "blocks": blocks, "points": points,
        "normal_forces": num(state.normal_force), "shear_forces": num(state.shear_force),
        "velocities": num(state.velocities), "opening_rates": num(state.opening_rate),
        "slip_rates": num(state.slip_rate), "contact_states": list(state.contact_state),
    }


def dumps_state(state: CollapseStateData) -> str:
    """The file's text: one key per line, one block or point per line; numbers as Python writes them
    (they read back bit for bit).

    Raises:
        ValueError: a number that is not finite (JSON has none).
    """
    doc = state_document(state)

    def one(value: Any) -> str:
        return json.dumps(value, allow_nan=False, ensure_ascii=False)

    lines = []
    for key, value in doc.items():
        if key in ("blocks", "points"):
            body = ",\n".join(one(x) for x in value)
            lines.append(f"{one(key)}: [\n{body}\n]")
        else:
            lines.append(f"{one(key)}: {one(value)}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


def write_state(state: Any, path: str | os.PathLike[str], *, wall: BlockWall | None = None,
                source: Mapping[str, Any] | None = None) -> Path:
    """Write a collapse state file, whole or not at all (:func:`micro.files.write_whole`).

    Args:
        state: a :class:`~micro.state.data.CollapseStateData`, or a result of this library
            (:class:`micro.LimitResult`, :class:`micro.NonAssociativeResult`) with its ``wall``: its
            governing state (:func:`~micro.state.data.collapse_state`).
        path: the file.
        wall: the wall of a result (not with a state).
        source: with a result, more to record under ``source``.

    Returns:
        The path written.

    Raises:
        TypeError: a result without its wall, or a state with one.
        ValueError: a failed result (no state), or a state with a number that is not finite.
        OSError: the file could not be written (it is then as it was).
    """
    if isinstance(state, CollapseStateData):
        if wall is not None or source is not None:
            raise TypeError("write_state: wall and source go with a result, not with a CollapseStateData")
    elif wall is None:
        raise TypeError("write_state: a result needs its wall (write_state(result, path, wall=wall))")
    else:
        state = collapse_state(state, wall, source=source)
    return write_whole(path, dumps_state(state).encode("utf-8"))


# ------------------------------------------------------------------------------------------ reading
def read_state(path: str | os.PathLike[str]) -> CollapseStateData:
    """Read a collapse state file (module docstring: any file, refused in one line when it is not one).

    Raises:
        StateFileError: the file cannot be read or is malformed.
    """
    name = str(path)
    try:
        data = read_input_file(path, MAX_STATE_BYTES)
    except OSError as exc:
        raise StateFileError(f"state {name}: cannot read ({exc.strerror or exc})") from None
    if len(data) > MAX_STATE_BYTES:
        raise StateFileError(f"state {name}: larger than {MAX_STATE_BYTES:,} bytes")
    if data.startswith((codecs.BOM_UTF32_LE, codecs.BOM_UTF32_BE, codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        raise StateFileError(f"state {name}: UTF-16 or UTF-32 text; a state file is UTF-8 JSON")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise StateFileError(f"state {name} (line {line}): not UTF-8 text (byte 0x{data[exc.start]:02x} at "
                             f"offset {exc.start}); a state file is UTF-8 JSON") from None
    return parse_state(text, name)


def parse_state(text: str, source: str = "<text>") -> CollapseStateData:
    """A state from the text of a state file (``source`` names it in errors).

    Raises:
        StateFileError: not JSON, or not a state of this format.
    """
    def constant(name: str) -> Any:
        raise _NotJson(f"{name} is not a JSON number")

    try:
        doc = json.loads(text, parse_constant=constant)
    except json.JSONDecodeError as exc:
        raise StateFileError(f"state {source} (line {exc.lineno}, column {exc.colno}): not JSON ({exc.msg})") from None
    except RecursionError:
        raise StateFileError(f"state {source}: not a state file (JSON nested too deeply)") from None
    except (_NotJson, ValueError) as exc:  # NaN/Infinity; an integer of more digits than Python reads
        raise StateFileError(f"state {source}: not strict JSON ({exc})") from None
    return state_from_document(doc, source)


class _NotJson(Exception):
    """``NaN``, ``Infinity`` or ``-Infinity`` in the text."""


def state_from_document(doc: Any, source: str = "<document>") -> CollapseStateData:
    """A state from a parsed JSON document, every entry checked (module docstring).

    Raises:
        StateFileError: naming ``source`` and the field.
    """
    r = _Reader(source)
    top = r.obj(doc, "", required=tuple(k for k in _TOP_KEYS if k != "source"), optional=("source",))
    if top["format"] != FORMAT:
        r.fail("format", f"must be {FORMAT!r}, got {_short(top['format'])}")
    version = top["version"]
    if type(version) is not int:
        r.fail("version", f"must be an integer, got {_short(version)}")
    if version != VERSION:
        r.fail("version", f"this reader reads version {VERSION}, the file is version {version}")
    friction = r.choice(top["friction"], "friction", FRICTIONS)
    direction = r.choice(top["direction"], "direction", DIRECTIONS)
    lam = r.number(top["load_factor"], "load_factor")
    src = top.get("source", {})
    if not isinstance(src, dict):
        r.fail("source", f"must be an object, got {_short(src)}")
    blocks = r.array(top["blocks"], "blocks", minimum=1)
    points = r.array(top["points"], "points")
    nb, npt = len(blocks), len(points)
    vertices, centroid, weight, dead, live = _blocks(r, blocks)
    pa, pb, position, normal, tangent, mu = _points(r, points, nb)
    forces = [r.vector(top[k], k, npt) for k in ("normal_forces", "shear_forces", "opening_rates", "slip_rates")]
    vel = r.array(top["velocities"], "velocities")
    if len(vel) != nb:
        r.fail("velocities", f"must hold one [u, v, omega] per block ({nb}), holds {len(vel)}")
    velocities = [r.vector(v, f"velocities[{i}]", 3) for i, v in enumerate(vel)]
    states = r.array(top["contact_states"], "contact_states")
    if len(states) != npt:
        r.fail("contact_states", f"must hold one state per point ({npt}), holds {len(states)}")
    for i, x in enumerate(states):
        r.choice(x, f"contact_states[{i}]", CONTACT_STATE_NAMES)
    live_x = sum(v[0] for v in live)
    if live_x != 0.0 and (live_x > 0) != (direction == "+x"):
        r.fail("direction", f"is {direction!r} but the live loads push towards {'+x' if live_x > 0 else '-x'} "
               "(live holds the load as applied)")
    return CollapseStateData(
        friction=friction, load_factor=lam, direction=direction, vertices=tuple(vertices),
        centroid=np.array(centroid), weight=np.array(weight), dead=np.array(dead), live=np.array(live),
        point_a=np.array(pa, dtype=np.int64).reshape(-1), point_b=np.array(pb, dtype=np.int64).reshape(-1),
        position=np.array(position).reshape(-1, 2), normal=np.array(normal).reshape(-1, 2),
        tangent=np.array(tangent).reshape(-1, 2), mu=np.array(mu), normal_force=forces[0], shear_force=forces[1],
        velocities=np.array(velocities).reshape(-1, 3), opening_rate=forces[2], slip_rate=forces[3],
        contact_state=tuple(states), source=src,
    )


def _blocks(r: _Reader, blocks: list) -> tuple[list, list, list, list, list]:
    """``(vertices, centroid, weight, dead, live)`` of the ``blocks`` entries, each checked."""
    vertices, centroid, weight, dead, live = [], [], [], [], []
    for i, rec in enumerate(blocks):
        where = f"blocks[{i}]"
        b = r.obj(rec, where, required=_BLOCK_KEYS)
        verts = r.array(b["vertices"], f"{where}.vertices", minimum=3)
        vertices.append(np.array([r.vector(v, f"{where}.vertices[{k}]", 2) for k, v in enumerate(verts)]))
        centroid.append(r.vector(b["centroid"], f"{where}.centroid", 2))
        weight.append(r.number(b["weight"], f"{where}.weight", minimum=0.0))
        dead.append(r.vector(b["dead"], f"{where}.dead", 3))
        live.append(r.vector(b["live"], f"{where}.live", 3))
    return vertices, centroid, weight, dead, live


def _points(r: _Reader, points: list, n_blocks: int) -> tuple[list, list, list, list, list, list]:
    """``(a, b, position, normal, tangent, mu)`` of the ``points`` entries, each checked (unit normals,
    tangents orthogonal to them, blocks that exist)."""
    pa, pb, position, normal, tangent, mu = [], [], [], [], [], []
    for i, rec in enumerate(points):
        where = f"points[{i}]"
        p = r.obj(rec, where, required=_POINT_KEYS)
        a, b = r.pair(p["blocks"], f"{where}.blocks", n_blocks)
        pa.append(a)
        pb.append(b)
        position.append(r.vector(p["position"], f"{where}.position", 2))
        nv, tv = r.vector(p["normal"], f"{where}.normal", 2), r.vector(p["tangent"], f"{where}.tangent", 2)
        if abs(math.hypot(*nv) - 1.0) > UNIT_TOL:
            r.fail(f"{where}.normal", f"must be a unit vector, its length is {math.hypot(*nv):.9g}")
        if abs(math.hypot(*tv) - 1.0) > UNIT_TOL or abs(nv[0] * tv[0] + nv[1] * tv[1]) > UNIT_TOL:
            r.fail(f"{where}.tangent", "must be a unit vector orthogonal to the normal")
        normal.append(nv)
        tangent.append(tv)
        mu.append(r.number(p["mu"], f"{where}.mu", minimum=0.0))
    return pa, pb, position, normal, tangent, mu


def _short(value: Any) -> str:
    """A value for a message, cut to 40 characters."""
    text = repr(value) if not isinstance(value, (dict, list)) else type(value).__name__.replace("dict", "an object") \
        .replace("list", "an array")
    return text if len(text) <= 40 else text[:37] + "..."


class _Reader:
    """Typed access to a parsed document; every failure is a :class:`StateFileError` naming the field."""

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, where: str, problem: str) -> NoReturn:
        raise StateFileError(f"state {self.source}: {where or 'the document'} {problem}")

    def obj(self, value: Any, where: str, *, required: tuple[str, ...], optional: tuple[str, ...] = ()) -> dict:
        if not isinstance(value, dict):
            self.fail(where, f"must be an object, got {_short(value)}")
        for key in value:
            if key not in required and key not in optional:
                name = key if key.isidentifier() else json.dumps(key)  # a newline in a key stays on one line
                self.fail(f"{where}.{name}" if where else name, f"is not a key of the format (keys: "
                          f"{', '.join(required + optional)})")
        for key in required:
            if key not in value:
                self.fail(f"{where}.{key}" if where else key, "is missing")
        return value

    def array(self, value: Any, where: str, *, minimum: int = 0) -> list:
        if not isinstance(value, list):
            self.fail(where, f"must be an array, got {_short(value)}")
        if len(value) < minimum:
            self.fail(where, f"must hold at least {minimum} entr{'y' if minimum == 1 else 'ies'}, holds {len(value)}")
        return value

    def number(self, value: Any, where: str, *, minimum: float | None = None) -> float:
        if type(value) not in (int, float):
            self.fail(where, f"must be a number, got {_short(value)}")
        try:
            x = float(value)
        except OverflowError:
            x = math.inf
        if not math.isfinite(x):
            self.fail(where, f"must be a finite number, got {_short(value)}")
        if minimum is not None and x < minimum:
            self.fail(where, f"must be at least {minimum:g}, got {x:g}")
        return x

    def vector(self, value: Any, where: str, size: int) -> np.ndarray:
        items = self.array(value, where)
        if len(items) != size:
            self.fail(where, f"must hold {size} numbers, holds {len(items)}")
        return np.array([self.number(x, f"{where}[{k}]") for k, x in enumerate(items)], dtype=np.float64)

    def pair(self, value: Any, where: str, n_blocks: int) -> tuple[int, int]:
        items = self.array(value, where)
        if len(items) != 2 or any(type(x) is not int or not -1 <= x < n_blocks for x in items):
            self.fail(where, f"must be two block numbers in [-1, {n_blocks - 1}] (-1: the ground), got "
                      f"{_short(value)}")
        if items[0] == items[1]:
            self.fail(where, f"joins block {items[0]} to itself")
        return int(items[0]), int(items[1])

    def choice(self, value: Any, where: str, allowed: tuple[str, ...]) -> str:
        if not isinstance(value, str) or value not in allowed:
            self.fail(where, f"must be one of {', '.join(allowed)}, got {_short(value)}")
        return value
