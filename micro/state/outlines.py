"""The geometry and the loads of a collapse state, checked against its own outlines.

CONTACT POINTS ON BOTH OUTLINES. A contact point between bodies ``a`` and ``b`` lies on an edge of each
whose outward normal is the point's: ``b``'s edge faces ``-normal`` (the normal points into ``b``) and
``a``'s faces ``normal``. For a point on the ground (``a = -1``) the ground's outline is the base line (the
horizontal line through the ground's other points, when they lie on one) or the outline of a block fixed
to the ground. :func:`contact_geometry` gives the largest distance of a point from such an edge, over the
size of the body (``inf`` where no edge of that body faces the right way).

TOUCHING EDGES. Two bodies touch where edges of their outlines lie on one line, face each other and
overlap over a segment; a body touches the ground where one of its edges lies on the base line facing
down, or faces a fixed block's edge. The contact forces of that interface act somewhere on that
segment: the file's points must span it, a point at each of its ends (:func:`touching_edges`). A point
moved inward from a rocking block's toe, or a head joint whose points were deleted, is found here.

LOADS. A body's weight is the unit weight times the area of its outline times its thickness (or the sum
over its parts); its dead load is that weight at the area's centroid plus its floor loads, all vertical;
its live load is the same masses pushed horizontally in the state's direction, per unit load factor
(:func:`loads`). Version 1 gives neither unit weight nor thickness nor floor positions: there the live
load must still follow the weight pattern (its horizontal force the dead load's vertical one, nothing
else) and the dead load be at least the weight, and, on a body without a floor load, act at its area's
centroid.

Each returns ``(value, where)``: the worst relative deviation and the body or point it is at.
"""

from __future__ import annotations

import math
from collections import defaultdict

import numpy as np
from numpy.typing import NDArray

from micro.state.data import CollapseStateData
from micro.state.structure import polygons

FloatArray = NDArray[np.float64]

#: Lengths within this share of the bodies' sizes are equal (the suite's coordinates are exact copies).
LENGTH_TOL = 1e-9
#: Two unit normals are the same direction within this.
ANGLE_TOL = 1e-9


def _edges(vertices: tuple[FloatArray, ...], owner: list[int]) -> dict[str, FloatArray]:
    """Every edge of every outline, run counter-clockwise: start, end, outward unit normal, owner."""
    if not vertices:
        return {"p0": np.zeros((0, 2)), "p1": np.zeros((0, 2)), "normal": np.zeros((0, 2)),
                "owner": np.zeros(0, dtype=np.int64)}
    counts = np.array([len(v) for v in vertices], dtype=np.int64)
    start = np.repeat(np.concatenate([[0], np.cumsum(counts)[:-1]]), counts)
    v = np.concatenate(vertices)
    local = np.arange(v.shape[0]) - start
    nxt = start + (local + 1) % np.repeat(counts, counts)
    clockwise = np.repeat(polygons(vertices)[0] < 0, counts)
    p0 = np.where(clockwise[:, None], v[nxt], v)
    p1 = np.where(clockwise[:, None], v, v[nxt])
    d = p1 - p0
    length = np.hypot(d[:, 0], d[:, 1])
    keep = length > 0
    n = np.column_stack([d[:, 1], -d[:, 0]])[keep] / length[keep, None]
    return {"p0": p0[keep], "p1": p1[keep], "normal": n,
            "owner": np.repeat(np.asarray(owner, dtype=np.int64), counts)[keep]}


def sizes(state: CollapseStateData) -> FloatArray:
    """Each body's size: the diagonal of its outline's bounding box."""
    return np.array([float(np.hypot(*(v.max(axis=0) - v.min(axis=0)))) for v in state.vertices])


def _distances(pos: FloatArray, facing: FloatArray, who: NDArray[np.int64], edges: dict[str, FloatArray],
               n_owners: int) -> FloatArray:
    """For each point ``pos[k]``, its distance from the nearest edge of owner ``who[k]`` whose outward
    normal is ``facing[k]`` (``inf`` where there is none)."""
    order = np.argsort(edges["owner"], kind="stable")
    bounds = np.searchsorted(edges["owner"][order], np.arange(n_owners + 1))
    first, count = bounds[who], bounds[who + 1] - bounds[who]
    row = np.repeat(np.arange(who.size), count)
    e = order[np.repeat(first, count) + (np.arange(row.size) - np.repeat(np.cumsum(count) - count, count))]
    a, b = edges["p0"][e], edges["p1"][e]
    d = b - a
    p = pos[row]
    t = np.clip(((p - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
    dist = np.hypot(*(a + t[:, None] * d - p).T)
    dist[np.abs((edges["normal"][e] * facing[row]).sum(axis=1) - 1.0) > ANGLE_TOL] = np.inf
    out = np.full(who.size, np.inf)
    np.minimum.at(out, row, dist)
    return out


def base_line(state: CollapseStateData, size: FloatArray | None = None) -> float | None:
    """The base line's height: the one height of the ground's points that face up and lie on no fixed
    block (``None`` when they lie on several heights, or there are none: the ground's outline is then not
    known, and its points are checked on their blocks' outlines only)."""
    size = sizes(state) if size is None else size
    up = (state.point_a < 0) & (np.abs(state.normal[:, 1] - 1.0) <= ANGLE_TOL)
    up &= ~_on_fixed(state, size)
    ys = state.position[up, 1]
    if ys.size == 0:
        return None
    lo, hi = float(ys.min()), float(ys.max())
    return lo if hi - lo <= LENGTH_TOL * float(np.max(size[state.point_b[up]])) else None


def _on_fixed(state: CollapseStateData, size: FloatArray) -> NDArray[np.bool_]:
    """The ground's points that lie on a block fixed to the ground, on an edge facing the way their
    normal says."""
    on = np.zeros(state.n_points, dtype=bool)
    ground = np.flatnonzero(state.point_a < 0)
    if not state.fixed_vertices or ground.size == 0:
        return on
    fixed = _edges(state.fixed_vertices, [0] * len(state.fixed_vertices))
    dist = _distances(state.position[ground], state.normal[ground], np.zeros(ground.size, dtype=np.int64), fixed, 1)
    on[ground] = dist <= LENGTH_TOL * size[state.point_b[ground]]
    return on


def contact_geometry(state: CollapseStateData) -> tuple[float, str]:
    """The largest distance of a contact point from an edge of its bodies' outlines that faces the way
    its normal says, over the body's size (module docstring); ``inf`` where no edge faces that way."""
    size = sizes(state)
    edges = _edges(state.vertices, list(range(state.n_blocks)))
    a, b = state.point_a, state.point_b
    dist = _distances(state.position, -state.normal, b, edges, state.n_blocks) / size[b]
    body = np.flatnonzero(a >= 0)
    dist[body] = np.maximum(dist[body], _distances(state.position[body], state.normal[body], a[body], edges,
                                                   state.n_blocks) / size[a[body]])
    ground = np.flatnonzero(a < 0)
    base = base_line(state, size)
    if ground.size and (base is not None or state.fixed_vertices):
        on_base = np.zeros(ground.size, dtype=bool) if base is None else (
            (np.abs(state.position[ground, 1] - base) <= LENGTH_TOL * size[b[ground]])
            & (np.abs(state.normal[ground, 1] - 1.0) <= ANGLE_TOL))
        off = ~(on_base | _on_fixed(state, size)[ground])
        dist[ground[off]] = np.inf
    if dist.size == 0:
        return 0.0, ""
    k = int(np.argmax(np.where(np.isnan(dist), np.inf, dist)))
    return float(dist[k]), (f"points[{k}]" if dist[k] > 0 else "")


def touching_edges(state: CollapseStateData) -> tuple[float, str]:
    """The number of touching segments (module docstring) whose ends do not both carry a contact point of
    the two bodies, and the first of them."""
    size = sizes(state)
    owner = list(range(state.n_blocks)) + [-1] * len(state.fixed_vertices)
    e = _edges(state.vertices + state.fixed_vertices, owner)
    segments = _shared(e, size)
    base = base_line(state, size)
    if base is not None:  # body edges on the base line, facing down
        down = (np.abs(e["normal"][:, 1] + 1.0) <= ANGLE_TOL) & (e["owner"] >= 0)
        for k in np.flatnonzero(down):
            o = int(e["owner"][k])
            if abs(e["p0"][k, 1] - base) <= LENGTH_TOL * size[o]:
                segments.append((-1, o, e["p0"][k], e["p1"][k]))
    points: dict[tuple[int, int], list[FloatArray]] = defaultdict(list)
    for a, b, pos in zip(state.point_a, state.point_b, state.position, strict=True):
        points[(min(int(a), int(b)), max(int(a), int(b)))].append(pos)
    missing, first = 0, ""
    for a, b, p0, p1 in segments:
        key = (min(a, b), max(a, b))
        tol = LENGTH_TOL * float(min(size[o] for o in key if o >= 0))
        have = points.get(key, [])
        ends = [any(math.hypot(*(q - end)) <= tol for q in have) for end in (p0, p1)]
        if not all(ends):
            missing += 1
            if not first:
                end = p0 if not ends[0] else p1
                who = "the ground" if a < 0 else f"block {a}"
                first = f"blocks {b} and {who} touch from ({p0[0]:.6g}, {p0[1]:.6g}) to ({p1[0]:.6g}, {p1[1]:.6g}); " \
                        f"no contact point at ({end[0]:.6g}, {end[1]:.6g})"
    return float(missing), first


def _shared(e: dict[str, FloatArray], size: FloatArray) -> list[tuple[int, int, FloatArray, FloatArray]]:
    """The segments where two owners' edges lie on one line facing each other: ``(a, b, start, end)``."""
    n = e["normal"]
    flip = (n[:, 0] < -ANGLE_TOL) | ((np.abs(n[:, 0]) <= ANGLE_TOL) & (n[:, 1] < 0))
    nc = np.where(flip[:, None], -n, n)
    side = np.where(flip, -1, 1)
    angle = np.round(np.arctan2(nc[:, 1], nc[:, 0]) / ANGLE_TOL).astype(np.int64)
    offset = (nc * e["p0"]).sum(axis=1)
    tan = np.column_stack([-nc[:, 1], nc[:, 0]])
    s0, s1 = (tan * e["p0"]).sum(axis=1), (tan * e["p1"]).sum(axis=1)
    lo, hi = np.minimum(s0, s1), np.maximum(s0, s1)
    own_size = size[np.where(e["owner"] >= 0, e["owner"], 0)]
    own_size = np.where(e["owner"] >= 0, own_size, np.inf)
    order = np.lexsort((offset, angle))
    out: list[tuple[int, int, FloatArray, FloatArray]] = []
    i, m = 0, order.size
    while i < m:  # one line: one angle, offsets within the tolerance of the smallest body on it
        j = i + 1
        while j < m and angle[order[j]] == angle[order[i]] and \
                offset[order[j]] - offset[order[j - 1]] <= LENGTH_TOL * min(own_size[order[j]], own_size[order[j - 1]]):
            j += 1
        line = order[i:j]
        i = j
        plus, minus = line[side[line] > 0], line[side[line] < 0]
        if plus.size == 0 or minus.size == 0:
            continue
        plus = plus[np.argsort(lo[plus])]
        first = np.searchsorted(hi[plus], lo[minus], side="right")
        last = np.searchsorted(lo[plus], hi[minus], side="left")
        for k, f, la in zip(minus, first, last, strict=True):
            for q in plus[f:la]:
                if e["owner"][k] < 0 and e["owner"][q] < 0:  # two blocks of the ground
                    continue
                a0, a1 = max(lo[k], lo[q]), min(hi[k], hi[q])
                tol = LENGTH_TOL * min(own_size[k], own_size[q])
                if a1 - a0 > tol:
                    c = 0.5 * (offset[k] + offset[q]) * nc[k]
                    out.append((int(e["owner"][q]), int(e["owner"][k]), c + a0 * tan[k], c + a1 * tan[k]))
    return out


def loads(state: CollapseStateData) -> tuple[float, str]:
    """The largest deviation of a body's weight, dead load or live load from what its outline, unit weight,
    thickness and floor loads give (module docstring), over its weight (moments over its weight times its
    size)."""
    size, w, c = sizes(state), state.weight, state.centroid
    d = 1.0 if state.direction == "+x" else -1.0
    version_2 = state.version >= 2 and len(state.members) == state.n_blocks
    area, ax, ay = polygons(state.vertices)
    if version_2:  # the weight of the outline (or of its parts), at its centroid; the floor loads where they act
        weight = np.abs(area) * state.thickness * state.unit_weight
        mx, my = weight * (ax - c[:, 0]), weight * (ay - c[:, 1])
        for i, parts in state.parts.items():
            pa, px, py = polygons(tuple(v for v, _ in parts))
            pw = np.abs(pa) * np.array([t for _, t in parts]) * state.unit_weight
            weight[i], mx[i], my[i] = pw.sum(), (pw * (px - c[i, 0])).sum(), (pw * (py - c[i, 1])).sum()
        q, qx, qy = (np.zeros(state.n_blocks) for _ in range(3))
        rel = state.floor_position - c[state.floor_block]
        np.add.at(q, state.floor_block, state.floor_load)
        np.add.at(qx, state.floor_block, state.floor_load * rel[:, 0])
        np.add.at(qy, state.floor_block, state.floor_load * rel[:, 1])
        moments = np.ones(state.n_blocks, dtype=bool)
    else:  # version 1: the weight as given, at the outline's centroid; a floor load's place is not known
        weight = w.copy()
        mx, my = w * (ax - c[:, 0]), w * (ay - c[:, 1])
        q = -state.dead[:, 1] - w
        qx = qy = np.zeros(state.n_blocks)
        moments = np.abs(q) <= LENGTH_TOL * w
    dead = np.column_stack([np.zeros(state.n_blocks), -(weight + q), -(mx + qx)])
    live = d * np.column_stack([weight + q, np.zeros(state.n_blocks), -(my + qy)])
    dev = np.column_stack([
        np.abs(w - weight) / w,
        np.abs(state.dead[:, :2] - dead[:, :2]).max(axis=1) / w,
        np.abs(state.live[:, :2] - live[:, :2]).max(axis=1) / w,
        np.where(moments, np.abs(state.dead[:, 2] - dead[:, 2]) / (w * size), 0.0),
        np.where(moments, np.abs(state.live[:, 2] - live[:, 2]) / (w * size), 0.0),
        np.maximum(-q / w, 0.0),  # a dead load below the weight
    ]).max(axis=1)
    if dev.size == 0:
        return 0.0, ""
    k = int(np.argmax(np.where(np.isnan(dev), np.inf, dev)))
    return float(dev[k]), (f"blocks[{k}]" if dev[k] > 0 else "")
