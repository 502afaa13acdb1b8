"""The structure a collapse state is of: its rigid bodies, their outlines and loads, and the wall that builds it.

A body is a block of the wall, or a block with the blocks held to it (:func:`micro.hold_blocks`): its
``members`` are the numbers of those blocks in the wall as built, its outline the union of their
rectangles, its weight theirs, its dead load their weights plus the floor loads they carry, its live
load the same masses pushed horizontally. Blocks held to the ground are ``fixed``: part of the ground.

:class:`WallParameters` are the builder's arguments (:func:`micro.build_wall`) with the held blocks: the
wall a state file names, which :meth:`WallParameters.build` builds again for ``xcheck verify``.
:func:`structure_of` gives the bodies of a wall or a held wall: the writer writes them, and the check
compares a file's with those of the wall it names.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall, build_wall, check_block_wall
from micro.hold import GROUND, HeldWall, hold_blocks

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The builder's arguments a state file names its wall by (:func:`micro.build_wall`'s but its memory
#: budget and its end treatment, which a file may leave out: see :class:`WallParameters`), in its order.
WALL_KEYS = tuple(k for k in inspect.signature(build_wall).parameters if k not in ("max_bytes", "ends"))


@dataclass(frozen=True)
class WallParameters:
    """The wall a state is of, as :func:`micro.build_wall` builds it, and the blocks held to their hosts.

    Attributes:
        builder: the builder's keyword arguments (:data:`WALL_KEYS`, and ``ends``; a wall that does not name
            its ends has its courses cut, as every builder before the choice of ends laid them).
        held: the blocks held to their hosts (numbers in the wall as built; :func:`micro.hold_blocks`).
    """

    builder: Mapping[str, Any]
    held: tuple[int, ...] = field(default=())

    @classmethod
    def of(cls, wall: BlockWall | HeldWall) -> WallParameters:
        """The parameters of ``wall`` (a held wall: its original's, and its held blocks)."""
        held: tuple[int, ...] = ()
        if isinstance(wall, HeldWall):
            held, wall = wall.held, wall.original
        check_block_wall(wall)
        builder = {k: getattr(wall, k) for k in WALL_KEYS}
        builder["ends"] = wall.ends
        return cls(builder, tuple(int(b) for b in held))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, the keys of the file's ``wall``."""
        out = {k: (list(v) if isinstance(v, tuple) else v) for k, v in self.builder.items()}
        out["held"] = list(self.held)
        return out

    def build(self) -> BlockWall | HeldWall:
        """The wall these parameters describe (a :class:`~micro.hold.HeldWall` when blocks are held).

        Raises:
            ValueError: a parameter the builder refuses (its message), or a held block that is not one of the
                wall's.
        """
        kwargs = {"ends": "cut", **self.builder}
        try:
            wall = build_wall(**kwargs)
        except TypeError as exc:  # a value of the wrong kind the builder does not name
            raise ValueError(str(exc)) from None
        return hold_blocks(wall, self.held) if self.held else wall


# ------------------------------------------------------------------------------------------ geometry
def polygon_area_centroid(vertices: FloatArray) -> tuple[float, float, float]:
    """``(signed area, x, y)`` of a polygon's area and its centroid (the area is positive when the
    vertices run counter-clockwise; coordinates taken from the first vertex, for accuracy far from the
    origin)."""
    v = np.asarray(vertices, dtype=np.float64)
    o = v[0]
    x, y = v[:, 0] - o[0], v[:, 1] - o[1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * float(cross.sum())
    if area == 0.0:
        return 0.0, float(np.mean(v[:, 0])), float(np.mean(v[:, 1]))
    cx = float(((x + xn) * cross).sum()) / (6.0 * area)
    cy = float(((y + yn) * cross).sum()) / (6.0 * area)
    return area, cx + float(o[0]), cy + float(o[1])


def polygons(vertices: tuple[FloatArray, ...]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(signed area, x, y)`` of every polygon at once (:func:`polygon_area_centroid`'s, vectorised)."""
    if not vertices:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    counts = np.array([len(v) for v in vertices], dtype=np.int64)
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    v = np.concatenate(vertices)
    o = np.repeat(v[start], counts, axis=0)
    local = np.arange(v.shape[0]) - np.repeat(start, counts)
    nxt = np.repeat(start, counts) + (local + 1) % np.repeat(counts, counts)
    x, y = v[:, 0] - o[:, 0], v[:, 1] - o[:, 1]
    xn, yn = x[nxt], y[nxt]
    cross = x * yn - xn * y
    area = 0.5 * np.add.reduceat(cross, start)
    safe = np.where(area != 0.0, area, 1.0)
    cx = np.add.reduceat((x + xn) * cross, start) / (6.0 * safe) + v[start, 0]
    cy = np.add.reduceat((y + yn) * cross, start) / (6.0 * safe) + v[start, 1]
    mean_x = np.add.reduceat(v[:, 0], start) / counts
    mean_y = np.add.reduceat(v[:, 1], start) / counts
    return area, np.where(area != 0.0, cx, mean_x), np.where(area != 0.0, cy, mean_y)


def rectangle(x0: float, x1: float, y0: float, y1: float) -> FloatArray:
    """A rectangle's outline, counter-clockwise from its lower left corner."""
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=np.float64)


def union_outline(rects: list[tuple[float, float, float, float]]) -> FloatArray:
    """The outline of the union of axis-aligned rectangles ``(x0, x1, y0, y1)`` that touch along edges
    (a block and the blocks held to it), counter-clockwise, collinear vertices dropped.

    Every rectangle's edges are cut at every coordinate of the others; the pieces two rectangles share
    (an inner joint) cancel, and the rest, chained end to end, is the outline.

    Raises:
        ValueError: the union is not one simple outline (rectangles apart, or enclosing a hole).
    """
    if len(rects) == 1:
        return rectangle(*rects[0])
    xs = sorted({v for r in rects for v in r[:2]})
    ys = sorted({v for r in rects for v in r[2:]})
    pieces: dict[tuple[tuple[float, float], tuple[float, float]], int] = {}

    def add(p: tuple[float, float], q: tuple[float, float]) -> None:
        if (q, p) in pieces:  # the same piece run the other way: an inner joint
            pieces[(q, p)] -= 1
            if pieces[(q, p)] == 0:
                del pieces[(q, p)]
        else:
            pieces[(p, q)] = pieces.get((p, q), 0) + 1

    for x0, x1, y0, y1 in rects:
        cx = [x for x in xs if x0 <= x <= x1]
        cy = [y for y in ys if y0 <= y <= y1]
        for a, b in zip(cx, cx[1:], strict=False):
            add((a, y0), (b, y0))
            add((b, y1), (a, y1))
        for a, b in zip(cy, cy[1:], strict=False):
            add((x1, a), (x1, b))
            add((x0, b), (x0, a))
    nxt = {p: q for (p, q) in pieces}
    if len(nxt) != len(pieces):
        raise ValueError("the blocks' union is not one simple outline (two edges leave one corner)")
    start = min(nxt)
    loop, p = [start], nxt[start]
    while p != start:
        loop.append(p)
        p = nxt[p]
        if len(loop) > len(nxt):
            raise ValueError("the blocks' union is not one simple outline")
    if len(loop) != len(nxt):
        raise ValueError("the blocks' union is not one simple outline (apart, or around a hole)")
    pts = np.array(loop, dtype=np.float64)
    before, after = pts - np.roll(pts, 1, axis=0), np.roll(pts, -1, axis=0) - pts
    turn = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
    return pts[turn != 0.0]


# ------------------------------------------------------------------------------------------ bodies
@dataclass(frozen=True, eq=False)
class Structure:
    """The bodies of a wall (or a held wall) as a state file writes them (arrays read-only by convention).

    Attributes:
        members: per body, the wall's blocks it is made of (the wall as built; the first is the host).
        vertices: per body, its outline (counter-clockwise).
        centroid: ``(n, 2)`` the reference point of each body's loads and velocity (the host's centroid).
        thickness: per body, its blocks' thickness (NaN where they differ: see ``parts``).
        parts: the bodies whose blocks differ in thickness: body -> ``((outline, thickness), ...)``.
        weight: per body, the weight of its blocks.
        floor_block, floor_position, floor_load: the floor loads, each a vertical force on a body at a point.
        dead, live: ``(n, 3)`` as the analysis applied them (``live`` in ``+x``, per unit load factor).
        fixed_members, fixed_vertices: the blocks held to the ground (part of it), each with its outline.
        unit_weight: the blocks' specific weight.
    """

    members: tuple[tuple[int, ...], ...]
    vertices: tuple[FloatArray, ...]
    centroid: FloatArray
    thickness: FloatArray
    parts: Mapping[int, tuple[tuple[FloatArray, float], ...]]
    weight: FloatArray
    floor_block: IntArray
    floor_position: FloatArray
    floor_load: FloatArray
    dead: FloatArray
    live: FloatArray
    fixed_members: tuple[tuple[int, ...], ...]
    fixed_vertices: tuple[FloatArray, ...]
    unit_weight: float


def floor_loads(wall: BlockWall) -> FloatArray:
    """The floor load on each block of ``wall`` (``q`` times its length on the top course of a storey with
    a floor load, else 0), as :func:`micro.build_wall` applies it at the middle of the block's top face."""
    rows = wall.rows
    top = np.array([sum(rows[s:]) - 1 for s in range(len(rows))], dtype=np.int64)  # storey s+1's top course
    on_top = wall.course == top[wall.storey - 1]
    q = np.asarray(wall.overload, dtype=np.float64)[wall.storey - 1]
    return np.where(on_top, q * wall.block_lengths, 0.0)


def structure_of(wall: BlockWall | HeldWall) -> Structure:
    """The bodies of ``wall``: one per block of a :class:`~micro.geometry.BlockWall`; one per block of a
    held wall's analysed wall, each with the blocks held to it (module docstring)."""
    held = wall if isinstance(wall, HeldWall) else None
    base = held.original if held is not None else check_block_wall(wall)
    analysed = held.wall if held is not None else base
    index = held.index if held is not None else np.arange(base.n_blocks, dtype=np.int64)
    t_block = np.asarray(base.thickness, dtype=np.float64)[base.storey - 1]
    area = base.block_lengths * base.block_height
    w_block = base.unit_weight * area * t_block
    q_block = floor_loads(base)
    order = np.argsort(index, kind="stable")
    groups = np.split(order, np.flatnonzero(np.diff(index[order])) + 1)
    by_body = {int(index[g[0]]): g for g in groups}
    members, outlines, thick = [], [], np.empty(analysed.n_blocks)
    parts: dict[int, tuple[tuple[FloatArray, float], ...]] = {}
    weight = np.empty(analysed.n_blocks)
    for j in range(analysed.n_blocks):
        g = by_body[j]
        host = [k for k in g if base.x0[k] == analysed.x0[j] and base.y0[k] == analysed.y0[j]
                and base.x1[k] == analysed.x1[j]][:1]
        ordered = host + [int(k) for k in g if k not in host]
        members.append(tuple(int(k) for k in ordered))
        rects = [(float(base.x0[k]), float(base.x1[k]), float(base.y0[k]), float(base.y1[k])) for k in ordered]
        outlines.append(union_outline(rects))
        ts = {float(t_block[k]) for k in ordered}
        thick[j] = ts.pop() if len(ts) == 1 else math.nan
        if math.isnan(thick[j]):
            parts[j] = tuple((rectangle(*r), float(t_block[k])) for r, k in zip(rects, ordered, strict=True))
        weight[j] = float(np.sum(w_block[ordered]))
    loaded = np.flatnonzero((q_block > 0) & (index >= 0))
    fixed = np.flatnonzero(index == GROUND)
    return Structure(
        members=tuple(members), vertices=tuple(outlines),
        centroid=np.column_stack([analysed.xc, analysed.yc]), thickness=thick, parts=parts, weight=weight,
        floor_block=index[loaded], floor_position=np.column_stack([base.xc[loaded], base.y1[loaded]]),
        floor_load=q_block[loaded], dead=np.asarray(analysed.dead), live=np.asarray(analysed.live),
        fixed_members=tuple((int(k),) for k in fixed),
        fixed_vertices=tuple(rectangle(base.x0[k], base.x1[k], base.y0[k], base.y1[k]) for k in fixed),
        unit_weight=float(base.unit_weight),
    )


def analysed_wall(wall: BlockWall | HeldWall) -> BlockWall:
    """The wall an analysis runs on: the held wall's, or ``wall`` itself."""
    return wall.wall if isinstance(wall, HeldWall) else check_block_wall(wall)
