"""A collapse state against the wall it names, block by block.

The wall is built again (:meth:`~micro.state.structure.WallParameters.build`, from the file's ``wall``;
or given by the caller, e.g. from a version-1 file's paper parameters) and its bodies
(:func:`~micro.state.structure.structure_of`) compared with the file's: the same bodies (by their
members; a version-1 file's in the wall's order), each with the same outline, thickness, weight, floor
loads, dead and live loads (moments taken about the wall's reference point), the same fixed blocks, and
the same contact points (position, normal, the friction coefficient of the wall). Lengths are compared
within :data:`~micro.state.outlines.LENGTH_TOL` of the body's size, forces within that share of its weight.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall
from micro.hold import HeldWall
from micro.lp import point_geometry
from micro.state.data import CollapseStateData
from micro.state.outlines import sizes
from micro.state.structure import Structure, analysed_wall, structure_of

FloatArray = NDArray[np.float64]


def _vertex_sets(vertices: tuple[FloatArray, ...]) -> tuple[NDArray[np.int64], FloatArray]:
    """Each outline's vertex count, and all vertices sorted by outline, then ``x``, then ``y`` (two
    outlines of the same vertices in another order or from another corner compare equal)."""
    counts = np.array([len(v) for v in vertices], dtype=np.int64)
    v = np.concatenate(vertices)
    owner = np.repeat(np.arange(len(vertices)), counts)
    return counts, v[np.lexsort((v[:, 1], v[:, 0], owner))]


def compare_with_wall(state: CollapseStateData, wall: BlockWall | HeldWall) -> tuple[float, str]:
    """``(deviation, where)``: the largest relative difference between the state's structure and the wall's
    (module docstring; ``inf`` where they differ in kind: bodies, members, points), and what differs."""
    ref = structure_of(wall)
    n = len(ref.members)
    if state.n_blocks != n:
        return math.inf, f"the file has {state.n_blocks} bodies, the wall it names {n}"
    if state.members:
        by_members = {frozenset(m): i for i, m in enumerate(ref.members)}
        order = []
        for i, m in enumerate(state.members):
            j = by_members.get(frozenset(m))
            if j is None:
                return math.inf, f"blocks[{i}] is made of blocks {list(m)}; the wall has no such body"
            order.append(j)
        if {frozenset(m) for m in state.fixed_members} != {frozenset(m) for m in ref.fixed_members}:
            return math.inf, "the blocks fixed to the ground are not the wall's"
    else:
        order = list(range(n))
    dev, where = _bodies(state, ref, order)
    pdev, pwhere = _points(state, wall, order)
    return (dev, where) if dev >= pdev else (pdev, pwhere)


def _bodies(state: CollapseStateData, ref: Structure, order: list[int]) -> tuple[float, str]:
    """The bodies' outlines and loads against the wall's."""
    j = np.asarray(order, dtype=np.int64)
    size, w, c = sizes(state), ref.weight[j], ref.centroid[j]
    mine_n, mine = _vertex_sets(state.vertices)
    theirs_n, theirs = _vertex_sets(tuple(ref.vertices[k] for k in order))
    if not np.array_equal(mine_n, theirs_n):
        i = int(np.flatnonzero(mine_n != theirs_n)[0])
        return math.inf, f"blocks[{i}]'s outline has {mine_n[i]} vertices, the wall's {theirs_n[i]}"
    d = 1.0 if state.direction == "+x" else -1.0
    at = state.centroid - c  # the file's reference points, from the wall's

    def moment(load: FloatArray) -> FloatArray:  # about the wall's reference point
        return load[:, 2] + at[:, 0] * load[:, 1] - at[:, 1] * load[:, 0]

    outline = np.zeros(len(order))
    np.maximum.at(outline, np.repeat(np.arange(len(order)), mine_n), np.abs(mine - theirs).max(axis=1))
    devs = {
        "outline": outline / size,
        "weight": np.abs(state.weight - w) / w,
        "dead load": np.maximum(np.abs(state.dead[:, :2] - ref.dead[j, :2]).max(axis=1) / w,
                                np.abs(moment(state.dead) - ref.dead[j, 2]) / (w * size)),
        "live load": np.maximum(np.abs(state.live[:, :2] - d * ref.live[j, :2]).max(axis=1) / w,
                                np.abs(moment(state.live) - d * ref.live[j, 2]) / (w * size)),
    }
    if state.members:
        t, tr = state.thickness, ref.thickness[j]
        devs["thickness"] = np.where(np.isnan(t) & np.isnan(tr), 0.0, np.abs(t - tr) / np.where(tr == tr, tr, 1.0))
        devs["thickness"][np.isnan(devs["thickness"])] = np.inf
        mine_q = np.bincount(state.floor_block, weights=state.floor_load, minlength=len(order))
        theirs_q = np.bincount(ref.floor_block, weights=ref.floor_load, minlength=len(order))[j]
        devs["floor loads"] = np.abs(mine_q - theirs_q) / w
    worst, where = 0.0, ""
    for name, dev in devs.items():
        k = int(np.argmax(np.where(np.isnan(dev), np.inf, dev)))
        if not dev[k] <= worst:
            worst = float(dev[k])
            where = f"blocks[{k}]: its {name} is not the wall's (relative difference {dev[k]:.3g})"
    return worst, where


def _points(state: CollapseStateData, wall: BlockWall | HeldWall, order: list[int]) -> tuple[float, str]:
    """The contact points (position, normal, friction coefficient) against the wall's."""
    analysed = analysed_wall(wall)
    a, b, px, py, nrm, _ = point_geometry(analysed)
    if state.n_points != a.size:
        return math.inf, f"the file has {state.n_points} contact points, the wall {a.size}"
    mu = np.repeat(analysed.mu, 2)
    inverse = np.empty(len(order), dtype=np.int64)
    inverse[np.asarray(order, dtype=np.int64)] = np.arange(len(order))
    fa = np.where(state.point_a >= 0, np.asarray(order)[np.maximum(state.point_a, 0)], -1)
    fb = np.where(state.point_b >= 0, np.asarray(order)[np.maximum(state.point_b, 0)], -1)
    mine = _sorted(fa, fb, state.position, state.normal)
    theirs = _sorted(a, b, np.column_stack([px, py]), nrm)
    if not (np.array_equal(mine[0], theirs[0]) and np.array_equal(mine[1], theirs[1])):
        k = int(np.flatnonzero((mine[0] != theirs[0]) | (mine[1] != theirs[1]))[0])
        return math.inf, f"points[{int(mine[4][k])}] joins other bodies than the wall's contact points do"
    size = sizes(state)
    body = np.maximum(inverse[mine[1]], 0)
    pos = float(np.max(np.abs(mine[2] - theirs[2]).max(axis=1) / size[body], initial=0.0))
    nor = float(np.max(np.abs(mine[3] - theirs[3]), initial=0.0))
    fric = float(np.max(np.abs(state.mu[mine[4]] - mu[theirs[4]]), initial=0.0))
    worst = max(pos, nor, fric)
    if worst == 0.0:
        return 0.0, ""
    which = ("position", pos), ("normal", nor), ("friction coefficient", fric)
    name = max(which, key=lambda x: x[1])[0]
    if name == "friction coefficient":
        k = int(np.argmax(np.abs(state.mu[mine[4]] - mu[theirs[4]])))
        return fric, (f"points[{int(mine[4][k])}]: mu = {state.mu[mine[4][k]]:g}, the wall's {mu[theirs[4][k]]:g} "
                      f"({'frictionless head joints' if mu[theirs[4][k]] == 0 else 'the wall friction'})")
    return worst, f"a contact point's {name} is not the wall's (relative difference {worst:.3g})"


IntArray = NDArray[np.int64]


def _sorted(a: IntArray, b: IntArray, pos: FloatArray,
            normal: FloatArray) -> tuple[IntArray, IntArray, FloatArray, FloatArray, IntArray]:
    """Points with their bodies in one order (the lower number first, the normal turned with them), sorted
    by bodies, then position: ``(a, b, position, normal, original index)``."""
    swap = a > b
    lo, hi = np.where(swap, b, a), np.where(swap, a, b)
    n = np.where(swap[:, None], -normal, normal)
    order = np.lexsort((np.round(pos[:, 1], 9), np.round(pos[:, 0], 9), hi, lo))
    return lo[order], hi[order], pos[order], n[order], order
