"""Local mechanisms: a collapse that a sliver allows, the block model's and not the wall's.

A piece ``w`` wide and ``b`` high that carries nothing tips over about its outer bottom corner on its own,
at

* ``lambda = w / b`` with non-associative friction (its head joint opens, no other block moves), and
* ``lambda = (w/b) (1 + mu^2) / (1 - mu^2 + 2 mu w/b)`` with associative friction (the head joint must
  dilate: its neighbour holds the piece down by friction),

which go to 0 with its width; a block resting on such a piece rocks out over it at a load that goes to a
small value with it as well (the corner wedge over a sliver). At ``w = mu b`` both closed forms are ``mu``,
the load at which the whole wall slides on its base: a piece at least that wide never collapses alone
below the wall. The default builder (``ends="closers"``, :mod:`micro.geometry`) lays no piece narrower
than :func:`micro.courses.closer_width` (``min(mu b, l/4)``); a narrower one, a **sliver**, comes only
from ``ends="cut"``.

The rule (:func:`find_local`): the governing mechanism is **local** when

1. nothing that stays at rest rests on its moving blocks (they are the top of the wall where they are:
   no block above them is held in place by the rest of the wall);
2. its moving blocks lie at one corner: all within one block length of the same end of the wall; and
3. it moves a sliver, or a moving block rests on one.

A block moves when some corner of it moves faster than :data:`MOVING_TOL` of the fastest corner of the
wall. Condition 3 is what makes it the block model's: the same corner of a wall built without slivers
(closers, or a whole number of half blocks) collapses as the wall does, and such a mechanism, a wedge of
whole end blocks at the top corner, is the wall's own. Conditions 1 and 2 keep a mechanism of the wall
that happens to carry a sliver along (the whole end of the wall rocking, say) from counting as local.

The held wall (:func:`micro.hold_blocks`) has the slivers the mechanism moves or rests on held to the
block that carries them: it is a different structure, reported beside the wall as built
(``comparison.domain.wall_mechanism.solve_wall_mechanism``), never in its place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.columns import json_number
from micro.courses import closer_width
from micro.geometry import BED, BlockWall
from micro.mechanism import Mechanism

FloatArray = NDArray[np.float64]

#: A block moves when a corner of it moves faster than this fraction of the fastest corner (the accuracy
#: of an interior point's duals, as :data:`micro.mechanism.CONTACT_STATE_TOL`).
MOVING_TOL = 1e-3
#: A block's length within this relative distance of ``l`` or ``l/2`` is a whole or half block, not cut;
#: a piece narrower than the closer width by more than this (relative to ``l``) is a sliver.
CUT_TOL = 1e-9


@dataclass(frozen=True)
class LocalMechanism:
    """A local collapse mechanism (module docstring).

    Attributes:
        blocks: the moving blocks (indices in the wall analysed), sorted.
        slivers: the slivers it moves or rests on (indices in the wall analysed), sorted: the pieces
            :func:`micro.hold_blocks` holds for the held wall.
        weight_share: the moving blocks' share of the wall's dead load.
        load_factor: its ``lambda`` (the block model's governing value).
        direction: the live-load direction, ``"+x"`` or ``"-x"``.
        description: one line saying what moves, e.g. ``"the cut end piece of course 16 (right end, 0.5 x 1)
            tips over alone"``.
    """

    blocks: tuple[int, ...]
    slivers: tuple[int, ...]
    weight_share: float
    load_factor: float
    direction: str
    description: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (NaN -> ``None``)."""
        return {"blocks": list(self.blocks), "slivers": list(self.slivers),
                "weight_share": json_number(self.weight_share),
                "load_factor": json_number(self.load_factor), "direction": self.direction,
                "description": self.description}


def moving_blocks(wall: BlockWall, mechanism: Mechanism, *, tol: float = MOVING_TOL) -> tuple[int, ...]:
    """The blocks of ``mechanism`` whose fastest corner moves faster than ``tol`` of the wall's fastest."""
    v = np.asarray(mechanism.velocities, dtype=float)
    ls = wall.block_height  # velocities are in the LP's units: lengths in block heights
    speed = np.zeros(wall.n_blocks)
    for x in (wall.x0, wall.x1):
        for y in (wall.y0, wall.y1):
            dx, dy = (x - wall.xc) / ls, (y - wall.yc) / ls
            speed = np.maximum(speed, np.hypot(v[:, 0] - v[:, 2] * dy, v[:, 1] + v[:, 2] * dx))
    top = float(speed.max(initial=0.0))
    if not math.isfinite(top) or top <= 0.0:
        return ()
    return tuple(int(i) for i in np.flatnonzero(speed > tol * top))


def weight_share(wall: BlockWall, blocks: tuple[int, ...]) -> float:
    """The share of the wall's dead load (self weight and floor loads) that ``blocks`` carry."""
    w = -wall.dead[:, 1]
    return float(w[list(blocks)].sum() / w.sum()) if blocks else 0.0


def slivers(wall: BlockWall) -> NDArray[np.bool_]:
    """Which blocks are slivers: narrower than :func:`micro.courses.closer_width` (module docstring)."""
    limit = closer_width(wall.block_length, wall.block_height, wall.friction) - CUT_TOL * wall.block_length
    return wall.block_lengths < limit


def find_local(wall: BlockWall, mechanism: Mechanism | None, load_factor: float,
               direction: str) -> LocalMechanism | None:
    """The local mechanism (module docstring) that ``mechanism`` is, or ``None``.

    Args:
        wall: the wall the mechanism belongs to.
        mechanism: the governing mechanism (``None``: no mechanism, nothing local).
        load_factor: its ``lambda``.
        direction: its live-load direction.

    Returns:
        The :class:`LocalMechanism`, or ``None`` when nothing moves, the load factor is not a number, or one
        of the rule's three conditions fails.
    """
    if mechanism is None or not math.isfinite(load_factor):
        return None
    blocks = moving_blocks(wall, mechanism)
    if not blocks:
        return None
    moving = np.zeros(wall.n_blocks, dtype=bool)
    moving[list(blocks)] = True
    a, b = wall.contact_a, wall.contact_b
    bed = (wall.contact_kind == BED) & (a >= 0)
    if np.any(moving[a[bed]] & ~moving[b[bed]]):  # a block at rest rests on a moving one
        return None
    reach = wall.block_length * (1.0 + CUT_TOL)
    if not (np.all(wall.x1[moving] >= wall.length - reach) or np.all(wall.x0[moving] <= reach)):
        return None  # not one corner
    under = np.zeros(wall.n_blocks, dtype=bool)
    under[a[bed & moving[np.maximum(b, 0)]]] = True
    thin = slivers(wall) & (moving | under)
    if not np.any(thin):
        return None
    held = tuple(int(i) for i in np.flatnonzero(thin))
    return LocalMechanism(blocks, held, weight_share(wall, blocks), float(load_factor), direction,
                          describe(wall, mechanism, blocks, held))


def local_mechanism(wall: BlockWall, result: Any) -> LocalMechanism | None:
    """The local mechanism that governs ``result``, or ``None``.

    Args:
        wall: the wall analysed.
        result: a :class:`micro.LimitResult` (its governing mechanism) or a
            :class:`micro.NonAssociativeResult` (the state of the value to quote:
            the lowest certified state where the descent found one, else the
            iterated LP's governing state).

    Returns:
        The :class:`LocalMechanism`, or ``None`` (also for a failed result).
    """
    if not result.ok:
        return None
    quoted = getattr(result, "lowest_state", None)
    if quoted is not None and quoted.state is not None:
        return find_local(wall, quoted.state.mechanism, quoted.load_factor, quoted.direction)
    state = result.governing if hasattr(result, "governing") else None
    mechanism = state.mechanism if state is not None else result.mechanism
    return find_local(wall, mechanism, result.load_factor, result.direction)


def describe(wall: BlockWall, mechanism: Mechanism, blocks: tuple[int, ...], slivers: tuple[int, ...] = ()) -> str:
    """One line saying what moves and how: it ``"tips over"`` when it turns (its rotation moves a corner
    faster than :data:`MOVING_TOL` of its translation), else it ``"slides"``; and the slivers it moves over
    (``slivers`` not among ``blocks``)."""
    v = np.asarray(mechanism.velocities, dtype=float)[list(blocks)]
    size = float(np.hypot(wall.block_length, wall.block_height)) / wall.block_height
    turns = np.abs(v[:, 2]) * size > MOVING_TOL * np.hypot(v[:, 0], v[:, 1])
    how = "tips over" if np.all(turns) else "slides" if not np.any(turns) else "moves"
    over = [_name(wall, b) for b in slivers if b not in blocks]
    along = [_name(wall, b) for b in slivers if b in blocks]
    tail = (" over " + " and ".join(over) if over else "") + (", with " + " and ".join(along) if along else "")
    if len(blocks) == 1:
        return f"{_name(wall, blocks[0])} {how}" + (" over " + " and ".join(over) if over else " alone")
    plural = {"tips over": "tip over", "slides": "slide", "moves": "move"}[how]
    courses = sorted({int(wall.course[b]) + 1 for b in blocks})
    span = f"course {courses[0]}" if len(courses) == 1 else f"courses {courses[0]}-{courses[-1]}"
    return f"{len(blocks)} blocks of {span} {plural}{tail}"


def _name(wall: BlockWall, b: int) -> str:
    """``"the cut end piece of course 16 (right end, 0.5 x 1)"`` and the like."""
    x0, x1 = float(wall.x0[b]), float(wall.x1[b])
    w, length = x1 - x0, wall.block_length
    tol = CUT_TOL * wall.length
    end = "left end" if abs(x0) <= tol else "right end" if abs(x1 - wall.length) <= tol else ""
    whole = abs(w - length) <= CUT_TOL * length or abs(w - 0.5 * length) <= CUT_TOL * length
    kind = ("end block" if whole else "cut end piece") if end else "block" if whole else "cut piece"
    size = f"{w:.4g} x {wall.block_height:.4g}"
    where = f"{end}, {size}" if end else f"x = {x0:.4g} to {x1:.4g}, {size}"
    return f"the {kind} of course {int(wall.course[b]) + 1} ({where})"
