"""A state file's JSON document, every entry checked, as a :class:`~micro.state.data.CollapseStateData`.

Versions 1 and 2 (:mod:`micro.state.file` describes both). Every entry's type, length and range is
checked, the geometry's consistency (unit normals, tangents orthogonal to them, bodies that exist,
outlines that enclose an area), and every scale of the state (weights, thicknesses, sizes, velocities)
lies within :data:`SMALLEST` and :data:`LARGEST`, where products of two numbers stay ordinary doubles.
Whatever is wrong raises :class:`StateFileError`, one line naming the file, the field and its line.
"""

from __future__ import annotations

import json
import math
from typing import Any, NoReturn

import numpy as np

from micro.mechanism import CONTACT_STATE_NAMES
from micro.state.data import DIRECTIONS, FRICTIONS, VERSION, CollapseStateData
from micro.state.jsontext import line_of
from micro.state.structure import WALL_KEYS, WallParameters, polygon_area_centroid

#: The ``format`` of a state file.
FORMAT = "xcheck-masonry collapse state"
#: The versions read.
VERSIONS = (1, 2)
#: A normal or tangent is a unit vector, and the two orthogonal, to this tolerance (six digits pass).
UNIT_TOL = 1e-6
#: The scales of a state (a body's weight and size, a thickness, the unit weight, the largest velocity)
#: lie within [SMALLEST, LARGEST], and every number within LARGEST: a product of two stays an ordinary
#: double (no overflow, no subnormal number whose digits are lost), so that no residual vanishes in the
#: arithmetic. A state scaled by 1e-308 is refused, not checked.
SMALLEST, LARGEST = 1e-100, 1e100

_TOP: dict[int, tuple[str, ...]] = {1: (
    "format", "version", "friction", "load_factor", "direction", "blocks", "points", "normal_forces", "shear_forces",
    "velocities", "opening_rates", "slip_rates", "contact_states")}
_TOP[2] = _TOP[1][:5] + ("unit_weight",) + _TOP[1][5:]
_TOP_OPTIONAL = {1: ("source",), 2: ("source", "wall", "fixed")}
_BLOCK = {1: ("vertices", "centroid", "weight", "dead", "live"), 2: ("members", "vertices", "centroid", "weight",
                                                                  "dead", "live")}
_BLOCK_OPTIONAL = {1: (), 2: ("thickness", "parts", "floor")}
_POINT = ("blocks", "position", "normal", "tangent", "mu")


class StateFileError(ValueError):
    """A state file that cannot be read or is malformed; the message (one line) names the file and the
    JSON line or the field."""


def state_from_document(doc: Any, source: str = "<document>", text: str | None = None) -> CollapseStateData:
    """A state from a parsed JSON document, every entry checked (module docstring).

    Args:
        doc: the document.
        source: names it in errors.
        text: its text, to name a field's line in errors.

    Raises:
        StateFileError: naming ``source``, the field and (with ``text``) its line.
    """
    r = _Reader(source, text)
    if not isinstance(doc, dict):
        r.fail("", f"must be an object, got {_short(doc)}")
    version = doc.get("version")
    if "version" in doc and (type(version) is not int or version not in VERSIONS):
        r.fail("version", f"this reader reads versions {', '.join(map(str, VERSIONS))}, the file is version "
               f"{_short(version)}")
    v = version if version in VERSIONS else VERSION
    top = r.obj(doc, "", required=_TOP[v], optional=_TOP_OPTIONAL[v])
    if top["format"] != FORMAT:
        r.fail("format", f"must be {FORMAT!r}, got {_short(top['format'])}")
    friction = r.choice(top["friction"], "friction", FRICTIONS)
    direction = r.choice(top["direction"], "direction", DIRECTIONS)
    lam = r.number(top["load_factor"], "load_factor")
    src = top.get("source", {})
    if not isinstance(src, dict):
        r.fail("source", f"must be an object, got {_short(src)}")
    blocks = r.array(top["blocks"], "blocks", minimum=1)
    points = r.array(top["points"], "points")
    nb, npt = len(blocks), len(points)
    extra: dict[str, Any] = {}
    if v == 2:
        extra["unit_weight"] = r.number(top["unit_weight"], "unit_weight", scale=True)
    b = _blocks(r, blocks, v)
    pa, pb, position, normal, tangent, mu = _points(r, points, nb)
    forces = [r.vector(top[k], k, npt) for k in ("normal_forces", "shear_forces", "opening_rates", "slip_rates")]
    vel = r.array(top["velocities"], "velocities")
    if len(vel) != nb:
        r.fail("velocities", f"must hold one [u, v, omega] per block ({nb}), holds {len(vel)}")
    velocities = np.array([r.vector(x, f"velocities[{i}]", 3) for i, x in enumerate(vel)]).reshape(-1, 3)
    fastest = float(np.max(np.abs(velocities), initial=0.0))
    if 0.0 < fastest < SMALLEST:
        r.fail("velocities", f"are all below {SMALLEST:g}: outside the range the check computes in")
    states = r.array(top["contact_states"], "contact_states")
    if len(states) != npt:
        r.fail("contact_states", f"must hold one state per point ({npt}), holds {len(states)}")
    for i, x in enumerate(states):
        r.choice(x, f"contact_states[{i}]", CONTACT_STATE_NAMES)
    live_x = float(sum(x[0] for x in b["live"]))
    if live_x != 0.0 and (live_x > 0) != (direction == "+x"):
        r.fail("direction", f"is {direction!r} but the live loads push towards {'+x' if live_x > 0 else '-x'} "
               "(live holds the load as applied)")
    if v == 2:
        extra.update(_version_2(r, top, b, nb))
    return CollapseStateData(
        friction=friction, load_factor=lam, direction=direction, vertices=tuple(b["vertices"]),
        centroid=np.array(b["centroid"]), weight=np.array(b["weight"]), dead=np.array(b["dead"]),
        live=np.array(b["live"]), point_a=np.array(pa, dtype=np.int64).reshape(-1),
        point_b=np.array(pb, dtype=np.int64).reshape(-1), position=np.array(position).reshape(-1, 2),
        normal=np.array(normal).reshape(-1, 2), tangent=np.array(tangent).reshape(-1, 2), mu=np.array(mu),
        normal_force=forces[0], shear_force=forces[1], velocities=velocities, opening_rate=forces[2],
        slip_rate=forces[3], contact_state=tuple(states), source=src, version=v, **extra,
    )


def _blocks(r: _Reader, blocks: list, version: int) -> dict[str, list]:
    """The ``blocks`` entries, each checked: lists of vertices, centroid, weight, dead, live (and, in
    version 2, members, thickness, parts, floor loads)."""
    out: dict[str, list] = {k: [] for k in ("vertices", "centroid", "weight", "dead", "live", "members",
                                            "thickness", "parts", "floor")}
    for i, rec in enumerate(blocks):
        where = f"blocks[{i}]"
        b = r.obj(rec, where, required=_BLOCK[version], optional=_BLOCK_OPTIONAL[version])
        out["vertices"].append(r.outline(b["vertices"], f"{where}.vertices"))
        out["centroid"].append(r.vector(b["centroid"], f"{where}.centroid", 2))
        out["weight"].append(r.number(b["weight"], f"{where}.weight", scale=True))
        out["dead"].append(r.vector(b["dead"], f"{where}.dead", 3))
        out["live"].append(r.vector(b["live"], f"{where}.live", 3))
        if version == 2:
            out["members"].append(r.block_numbers(b["members"], f"{where}.members", minimum=1))
            if ("thickness" in b) == ("parts" in b):
                r.fail(where, "must give either thickness or parts (the thickness of each of its parts)")
            if "thickness" in b:
                out["thickness"].append(r.number(b["thickness"], f"{where}.thickness", scale=True))
                out["parts"].append(None)
            else:
                parts = r.array(b["parts"], f"{where}.parts", minimum=1)
                out["thickness"].append(math.nan)
                out["parts"].append(tuple(
                    (r.outline(r.obj(p, f"{where}.parts[{k}]", required=("vertices", "thickness"))["vertices"],
                               f"{where}.parts[{k}].vertices"),
                     r.number(p["thickness"], f"{where}.parts[{k}].thickness", scale=True))
                    for k, p in enumerate(parts)))
            floor = r.array(b.get("floor", []), f"{where}.floor")
            out["floor"].append([r.vector(f, f"{where}.floor[{k}]", 3) for k, f in enumerate(floor)])
    return out


def _version_2(r: _Reader, top: dict, b: dict[str, list], nb: int) -> dict[str, Any]:
    """The fields only version 2 has: members, thickness, parts, floor loads, fixed blocks, the wall."""
    members = tuple(b["members"])
    seen: dict[int, str] = {}
    for i, m in enumerate(members):
        for k in m:
            if k in seen:
                r.fail(f"blocks[{i}].members", f"names block {k}, which {seen[k]} names too")
            seen[k] = f"blocks[{i}]"
    fixed = r.array(top.get("fixed", []), "fixed")
    fixed_members, fixed_vertices = [], []
    for i, rec in enumerate(fixed):
        f = r.obj(rec, f"fixed[{i}]", required=("members", "vertices"))
        fixed_members.append(r.block_numbers(f["members"], f"fixed[{i}].members", minimum=1))
        for k in fixed_members[-1]:
            if k in seen:
                r.fail(f"fixed[{i}].members", f"names block {k}, which {seen[k]} names too")
            seen[k] = f"fixed[{i}]"
        fixed_vertices.append(r.outline(f["vertices"], f"fixed[{i}].vertices"))
    floor = [(i, f) for i, fl in enumerate(b["floor"]) for f in fl]
    wall = _wall(r, top["wall"]) if "wall" in top else None
    return {
        "members": members, "thickness": np.array(b["thickness"]),
        "parts": {i: p for i, p in enumerate(b["parts"]) if p is not None},
        "floor_block": np.array([i for i, _ in floor], dtype=np.int64),
        "floor_position": np.array([f[:2] for _, f in floor]).reshape(-1, 2),
        "floor_load": np.array([f[2] for _, f in floor]), "fixed_members": tuple(fixed_members),
        "fixed_vertices": tuple(fixed_vertices), "wall": wall,
    }


def _wall(r: _Reader, value: Any) -> WallParameters:
    """The ``wall`` object: the builder's arguments and the held blocks (their kinds checked here; the
    builder checks the values when the wall is built again)."""
    w = r.obj(value, "wall", required=WALL_KEYS + ("held",), optional=("ends",))
    kw: dict[str, Any] = {}
    for k in ("length", "block_length", "block_height", "unit_weight", "friction"):
        kw[k] = r.number(w[k], f"wall.{k}")
    rows = r.array(w["rows"], "wall.rows", minimum=1)
    if any(type(x) is not int or x < 1 for x in rows):
        r.fail("wall.rows", f"must be positive integers, one per storey, got {_short(rows)}")
    kw["rows"] = tuple(rows)
    for k in ("thickness", "overload"):
        kw[k] = tuple(float(x) for x in r.vector(w[k], f"wall.{k}", len(rows)))
    for k in ("first_course", "head_joints", "ends"):
        if k in w and (not isinstance(w[k], str) or not w[k]):
            r.fail(f"wall.{k}", f"must be the name of the builder's choice, got {_short(w[k])}")
        if k in w:
            kw[k] = w[k]
    return WallParameters(kw, r.block_numbers(w["held"], "wall.held"))


def _points(r: _Reader, points: list, n_blocks: int) -> tuple[list, list, list, list, list, list]:
    """``(a, b, position, normal, tangent, mu)`` of the ``points`` entries, each checked (unit normals,
    tangents orthogonal to them, blocks that exist)."""
    pa, pb, position, normal, tangent, mu = [], [], [], [], [], []
    for i, rec in enumerate(points):
        where = f"points[{i}]"
        p = r.obj(rec, where, required=_POINT)
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
    """Typed access to a parsed document; every failure is a :class:`StateFileError` naming the field and,
    with the text, its line."""

    def __init__(self, source: str, text: str | None) -> None:
        self.source = source
        self.text = text

    def fail(self, where: str, problem: str) -> NoReturn:
        line = line_of(self.text, where) if self.text is not None else 0
        at = f" (line {line})" if line else ""
        raise StateFileError(f"state {self.source}{at}: {where or 'the document'} {problem}")

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

    def number(self, value: Any, where: str, *, minimum: float | None = None, scale: bool = False) -> float:
        if type(value) not in (int, float):
            self.fail(where, f"must be a number, got {_short(value)}")
        try:
            x = float(value)
        except OverflowError:
            x = math.inf
        if not math.isfinite(x) or abs(x) > LARGEST:
            self.fail(where, f"must be a finite number of at most {LARGEST:g} in size, got {_short(value)}")
        if minimum is not None and x < minimum:
            self.fail(where, f"must be at least {minimum:g}, got {x:g}")
        if scale and x < SMALLEST:
            self.fail(where, f"must be at least {SMALLEST:g} (a scale of the state), got {x:g}")
        return x

    def vector(self, value: Any, where: str, size: int) -> np.ndarray:
        items = self.array(value, where)
        if len(items) != size:
            self.fail(where, f"must hold {size} numbers, holds {len(items)}")
        return np.array([self.number(x, f"{where}[{k}]") for k, x in enumerate(items)], dtype=np.float64)

    def outline(self, value: Any, where: str) -> np.ndarray:
        """A polygon of at least three vertices enclosing an area, its size within the state's scales."""
        verts = self.array(value, where, minimum=3)
        v = np.array([self.vector(x, f"{where}[{k}]", 2) for k, x in enumerate(verts)])
        size = float(np.hypot(*(v.max(axis=0) - v.min(axis=0))))
        if not SMALLEST <= size <= LARGEST:
            self.fail(where, f"span {size:g}: outside [{SMALLEST:g}, {LARGEST:g}], the range the check computes in")
        area = polygon_area_centroid(v)[0]
        if abs(area) <= 1e-12 * size * size:
            self.fail(where, "enclose no area (an outline is a polygon around its block)")
        return v

    def block_numbers(self, value: Any, where: str, *, minimum: int = 0) -> tuple[int, ...]:
        items = self.array(value, where, minimum=minimum)
        if any(type(x) is not int or x < 0 for x in items) or len(set(items)) != len(items):
            self.fail(where, f"must be distinct numbers of blocks (0 or more), got {_short(value)}")
        return tuple(items)

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
