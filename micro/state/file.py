"""The collapse state file: JSON, written whole or not at all, read from any file without trusting it.

FORMAT (version 2; JSON Schema ``docs/schemas/state.schema.json``; dimensional, any consistent units)::

    {"format": "xcheck-masonry collapse state", "version": 2,
     "friction": "nonassociative",            # or "associative": the flow rule checked
     "load_factor": 0.6911, "direction": "+x",
     "unit_weight": 1.0,                      # the blocks' specific weight
     "source": {...},                         # optional, free: who wrote it and how
     "wall": {"length": ..., "block_length": ..., "block_height": ..., "rows": [...], "thickness": [...],
              "overload": [...], "unit_weight": ..., "friction": ..., "first_course": "full",
              "head_joints": "frictional", "ends": "closers", "held": [...]},   # optional: the wall solved
     "fixed": [{"members": [k], "vertices": [[x, y], ...]}, ...],               # optional: held to the ground
     "blocks": [{"members": [k, ...], "vertices": [[x, y], ...], "centroid": [x, y], "thickness": t,
                 "weight": w, "floor": [[x, y, Q], ...], "dead": [Fx, Fy, M], "live": [Fx, Fy, M]}, ...],
     "points": [{"blocks": [a, b], "position": [x, y], "normal": [nx, ny], "tangent": [tx, ty],
                 "mu": 0.75}, ...],
     "normal_forces": [...], "shear_forces": [...],          # one per point
     "velocities": [[u, v, omega], ...],                      # one per block
     "opening_rates": [...], "slip_rates": [...],             # one per point
     "contact_states": ["closed" | "opening" | "sliding", ...]}

Each entry of ``blocks`` is a rigid body: a block of the wall, or a block with the blocks held to it
(``members``: their numbers in the wall as built, the host first; ``vertices``: the outline of their
union; ``parts``, ``[{"vertices", "thickness"}, ...]``, instead of ``thickness`` where they differ in
thickness). ``floor`` lists the floor loads on it (vertical forces ``Q`` at ``(x, y)``; optional). What
each entry means: :class:`~micro.state.data.CollapseStateData` (block ``-1`` is the ground; the normal
points from the first block into the second; ``live`` is the load per unit load factor as applied, in
``direction``). ``wall`` is :func:`micro.build_wall`'s arguments and the held blocks
(:class:`~micro.state.structure.WallParameters`): ``xcheck verify`` builds that wall again and compares
it with the file block by block. The writer puts one block or point per line, so that a reader's error
names a line that means something.

VERSION 1 (read, no longer written) has no ``unit_weight``, ``wall``, ``fixed``, nor a block's
``members``, ``thickness``, ``parts`` or ``floor``: a held block was not named, and the weights could not
be checked against the blocks' areas.

READING ANY FILE. :func:`read_state` reads only a regular file (a named pipe, a directory or a device is
refused at once: :func:`micro.files.read_input_file`) of at most :data:`MAX_STATE_BYTES`, as UTF-8 (a
byte-order mark allowed), as strict JSON (no ``NaN`` or ``Infinity``, no key twice in one object:
:mod:`micro.state.jsontext`), and checks every entry (:mod:`micro.state.document`). Whatever is wrong
raises :class:`StateFileError`: one line naming the file, the field (``points[12].normal``) and its line.
"""

from __future__ import annotations

import codecs
import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from micro.files import read_input_file, write_whole
from micro.geometry import BlockWall
from micro.hold import HeldWall
from micro.state.data import VERSION, CollapseStateData, collapse_state
from micro.state.document import FORMAT, StateFileError, state_from_document
from micro.state.jsontext import JsonError, loads

#: Largest state file read (a 7,575-block wall's state is about 11 MB).
MAX_STATE_BYTES = 64 << 20

__all__ = ["FORMAT", "MAX_STATE_BYTES", "VERSION", "StateFileError", "dumps_state", "parse_state", "read_state",
           "state_document", "write_state"]


# ------------------------------------------------------------------------------------------ writing
def state_document(state: CollapseStateData) -> dict[str, Any]:
    """``state`` as the JSON document of the format, version 2 (plain lists and numbers; ``-0.0`` written as
    ``0.0``).

    Raises:
        ValueError: a state read from a version-1 file (it lacks what version 2 holds).
    """
    def num(a: Any) -> Any:
        return (np.asarray(a, dtype=np.float64) + 0.0).tolist()

    if state.version != VERSION or len(state.members) != state.n_blocks:
        raise ValueError(f"a state of version {state.version} cannot be written as version {VERSION} (it does "
                         "not name its blocks' members, thickness and unit weight)")
    floor: list[list[Any]] = [[] for _ in range(state.n_blocks)]
    for i, p, q in zip(state.floor_block, state.floor_position, state.floor_load, strict=True):
        floor[int(i)].append(num([p[0], p[1], q]))
    blocks = []
    for i, (v, c, w, d, li) in enumerate(zip(state.vertices, state.centroid, state.weight, state.dead, state.live,
                                             strict=True)):
        b: dict[str, Any] = {"members": list(state.members[i]), "vertices": num(v), "centroid": num(c)}
        if i in state.parts:
            b["parts"] = [{"vertices": num(pv), "thickness": num(pt)} for pv, pt in state.parts[i]]
        else:
            b["thickness"] = num(state.thickness[i])
        b["weight"] = num(w)
        if floor[i]:
            b["floor"] = floor[i]
        b.update(dead=num(d), live=num(li))
        blocks.append(b)
    points = [{"blocks": [int(a), int(b)], "position": num(p), "normal": num(n), "tangent": num(t), "mu": num(m)}
              for a, b, p, n, t, m in zip(state.point_a, state.point_b, state.position, state.normal,
                                          state.tangent, state.mu, strict=True)]
    doc: dict[str, Any] = {
        "format": FORMAT, "version": VERSION, "friction": state.friction, "load_factor": float(state.load_factor),
        "direction": state.direction, "unit_weight": float(state.unit_weight), "source": dict(state.source)}
    if state.wall is not None:
        doc["wall"] = state.wall.to_dict()
    if state.fixed_members:
        doc["fixed"] = [{"members": list(m), "vertices": num(v)}
                        for m, v in zip(state.fixed_members, state.fixed_vertices, strict=True)]
    doc.update({
        "blocks": blocks, "points": points,
        "normal_forces": num(state.normal_force), "shear_forces": num(state.shear_force),
        "velocities": num(state.velocities), "opening_rates": num(state.opening_rate),
        "slip_rates": num(state.slip_rate), "contact_states": list(state.contact_state),
    })
    return doc


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
        if key in ("blocks", "points", "fixed"):
            body = ",\n".join(one(x) for x in value)
            lines.append(f"{one(key)}: [\n{body}\n]")
        else:
            lines.append(f"{one(key)}: {one(value)}")
    return "{\n" + ",\n".join(lines) + "\n}\n"


def write_state(state: Any, path: str | os.PathLike[str], *, wall: BlockWall | HeldWall | None = None,
                source: Mapping[str, Any] | None = None) -> Path:
    """Write a collapse state file, whole or not at all (:func:`micro.files.write_whole`).

    Args:
        state: a :class:`~micro.state.data.CollapseStateData`, or a result of this library
            (:class:`micro.LimitResult`, :class:`micro.NonAssociativeResult`) with its ``wall``: its
            governing state (:func:`~micro.state.data.collapse_state`).
        path: the file.
        wall: the wall of a result (not with a state): a :class:`micro.BlockWall`, or the
            :class:`micro.HeldWall` whose analysed wall the result is of.
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
        StateFileError: not strict JSON, a key twice in one object, or not a state of this format.
    """
    try:
        doc = loads(text)
    except JsonError as exc:
        raise StateFileError(f"state {source} {exc}" if str(exc).startswith("(") else f"state {source}: {exc}") \
            from None
    return state_from_document(doc, source, text)
