"""Local mechanisms: a collapse of a few blocks that is the block model's, not the wall's.

When a wall's length is not a whole number of half blocks every course ends
with a cut block (:mod:`micro.geometry`). A cut end piece of the TOP course
carries nothing: loaded horizontally it tips over about its outer bottom
corner on its own, at

* ``lambda = w / b`` with non-associative friction (``w`` its width, ``b`` its
  height; its head joint opens, no other block moves), and
* ``lambda = (w/b) (1 + mu^2) / (1 - mu^2 + 2 mu w/b)`` with associative
  friction (the head joint must dilate: its neighbour holds the piece down by
  friction; the associative collapse of the piece alone),

which go to 0 with the piece's width. That is a true mechanism of the block
model, but not the wall's: no macro model of the wall (nor the wall, once the
piece is mortared or left out) collapses that way.

The rule (:func:`find_local`): the governing mechanism is **local** when its
moving blocks (1) all lie in the wall's top course, so that no block rests on
them and the wall does not hold them in, and (2) carry at most
:data:`LOCAL_WEIGHT_SHARE` of the wall's dead load (self weight and floor
loads). A block moves when some corner of it moves faster than
:data:`MOVING_TOL` of the fastest corner of the wall. On the 12-wall grid that
showed it (t = 1/2, 1, 3/2; m = 1/3, 1/2; rows 8, 16; f = 0.65) the four local
mechanisms (both friction models) move one block each, the top course's cut end
piece, 0.10-0.78 % of the wall's weight. The other walls' mechanisms move
22-100 % of it but one: at ``lambda = f`` the non-associative state of the
16-long, 8-row wall slides the end blocks of courses 7 and 8 together, 2.7 %
of its weight, a mechanism of the wall (the top course is carried by course 7)
that condition (1) tells apart however small its share. Condition (1) also
keeps the rule from depending on the wall's size: with the piece held, the next
mechanism of the 32-long, 16-row wall of that grid (non-associative) is the
wedge of the three end blocks of courses 14-16, 1.2 % of its weight, the same
wedge and the same ``lambda`` (0.5234) as in the 8-long, 8-row wall where it is
4.7 %: a mechanism of the wall's corner in both. Condition (2) keeps a whole top
course that slides (a mechanism of the wall) from counting as local on a short
wall.

The wall's own mechanism is the same analysis with the local blocks held to
the block that carries them (:func:`micro.hold_blocks`); the comparison with
the macro model uses it (``comparison.domain.wall_mechanism.solve_wall_mechanism``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall
from micro.mechanism import Mechanism
from micro.records import json_number

FloatArray = NDArray[np.float64]

#: A mechanism is local when its moving blocks carry at most this share of the wall's dead load
#: (module docstring: the grid's local mechanisms move at most 0.8 %, its wall mechanisms 2.7 % or more).
LOCAL_WEIGHT_SHARE = 0.02
#: A block moves when a corner of it moves faster than this fraction of the fastest corner (the accuracy
#: of an interior point's duals, as :data:`micro.mechanism.CONTACT_STATE_TOL`).
MOVING_TOL = 1e-3
#: A block's length within this relative distance of ``l`` or ``l/2`` is a whole or half block, not cut.
CUT_TOL = 1e-9


@dataclass(frozen=True)
class LocalMechanism:
    """A local collapse mechanism (module docstring).

    Attributes:
        blocks: the moving blocks (indices in the wall analysed), sorted.
        weight_share: their share of the wall's dead load.
        load_factor: its ``lambda`` (the block model's governing value).
        direction: the live-load direction, ``"+x"`` or ``"-x"``.
        description: one line saying what moves, e.g. ``"the cut end piece of course 16 (right end, 0.5 x 1)
            tips over alone"``.
    """

    blocks: tuple[int, ...]
    weight_share: float
    load_factor: float
    direction: str
    description: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (NaN -> ``None``)."""
        return {"blocks": list(self.blocks), "weight_share": json_number(self.weight_share),
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


def find_local(wall: BlockWall, mechanism: Mechanism | None, load_factor: float, direction: str, *,
               share: float = LOCAL_WEIGHT_SHARE) -> LocalMechanism | None:
    """The local mechanism (module docstring) that ``mechanism`` is, or ``None``.

    Args:
        wall: the wall the mechanism belongs to.
        mechanism: the governing mechanism (``None``: no mechanism, nothing local).
        load_factor: its ``lambda``.
        direction: its live-load direction.
        share: the largest share of the dead load that a local mechanism moves.

    Returns:
        The :class:`LocalMechanism`, or ``None`` when nothing moves, the load factor is not a number, or the
        moving blocks carry more than ``share`` of the dead load.

    Raises:
        ValueError: ``share`` not in ``[0, 1)``.

    Note: the moving blocks must also all lie in the top course (module docstring).
    """
    if not (isinstance(share, (int, float)) and 0.0 <= share < 1.0):
        raise ValueError(f"share must be a number in [0, 1), got {share!r}")
    if mechanism is None or not math.isfinite(load_factor):
        return None
    blocks = moving_blocks(wall, mechanism)
    part = weight_share(wall, blocks)
    if not blocks or part > share or np.any(wall.course[list(blocks)] != wall.n_courses - 1):
        return None
    return LocalMechanism(blocks, part, float(load_factor), direction, describe(wall, mechanism, blocks))


def local_mechanism(wall: BlockWall, result: Any, *, share: float = LOCAL_WEIGHT_SHARE) -> LocalMechanism | None:
    """The local mechanism that governs ``result``, or ``None``.

    Args:
        wall: the wall analysed.
        result: a :class:`micro.LimitResult` (its governing mechanism) or a
            :class:`micro.NonAssociativeResult` (the state of the value to quote:
            the lowest certified state where the descent found one, else the
            iterated LP's governing state).
        share: as :func:`find_local`.

    Returns:
        The :class:`LocalMechanism`, or ``None`` (also for a failed result).
    """
    if not result.ok:
        return None
    quoted = getattr(result, "lowest_state", None)
    if quoted is not None and quoted.state is not None:
        return find_local(wall, quoted.state.mechanism, quoted.load_factor, quoted.direction, share=share)
    state = result.governing if hasattr(result, "governing") else None
    mechanism = state.mechanism if state is not None else result.mechanism
    return find_local(wall, mechanism, result.load_factor, result.direction, share=share)


def describe(wall: BlockWall, mechanism: Mechanism, blocks: tuple[int, ...]) -> str:
    """One line saying what moves and how: it ``"tips over"`` when it turns (its rotation moves a corner
    faster than :data:`MOVING_TOL` of its translation), else it ``"slides"``."""
    v = np.asarray(mechanism.velocities, dtype=float)[list(blocks)]
    size = float(np.hypot(wall.block_length, wall.block_height)) / wall.block_height
    turns = np.abs(v[:, 2]) * size > MOVING_TOL * np.hypot(v[:, 0], v[:, 1])
    how = "tips over" if np.all(turns) else "slides" if not np.any(turns) else "moves"
    if len(blocks) == 1:
        return f"{_name(wall, blocks[0])} {how} alone"
    plural = {"tips over": "tip over", "slides": "slide", "moves": "move"}[how]
    return f"{len(blocks)} blocks of course {int(wall.course[blocks[0]]) + 1} {plural}"


def _name(wall: BlockWall, b: int) -> str:
    """``"the cut end piece of course 16 (right end, 0.5 x 1)"`` and the like."""
    x0, x1 = float(wall.x0[b]), float(wall.x1[b])
    w, length = x1 - x0, wall.block_length
    tol = CUT_TOL * wall.length
    end = "left end" if abs(x0) <= tol else "right end" if abs(x1 - wall.length) <= tol else ""
    whole = abs(w - length) <= CUT_TOL * length or abs(w - 0.5 * length) <= CUT_TOL * length
    kind = ("end block" if whole else "cut end piece") if end else "block"
    size = f"{w:.4g} x {wall.block_height:.4g}"
    where = f"{end}, {size}" if end else f"x = {x0:.4g} to {x1:.4g}, {size}"
    return f"the {kind} of course {int(wall.course[b]) + 1} ({where})"
