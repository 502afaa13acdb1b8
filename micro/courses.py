"""Where the head joints of a running-bond course fall: the course layout of :func:`micro.build_wall`.

A course's regular joints sit at whole half blocks from ``x = 0``; how the course ends when the wall's
length is not a whole number of half blocks is the builder's ``ends``: cut (whatever remains after the
last joint) or closed as a mason closes it (no piece narrower than :func:`closer_width`). The blocks, their
contacts and loads are laid from these edges in :mod:`micro.geometry`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: A length within this relative distance of a whole number of half blocks is
#: that whole number (the builder's tolerance before cut end blocks, kept so
#: that such walls come out exactly as before).
WHOLE_TOLERANCE = 1e-9


def half_block_count(length: float, half: float) -> tuple[float, bool]:
    """The wall length in half blocks, and whether it is a whole number of them.

    A ratio within :data:`WHOLE_TOLERANCE` (relative) of an integer counts as
    whole and is returned as that integer (a length read from a file as
    ``59.99999999999999`` lays the same blocks as ``60``).
    """
    ratio = length / half
    n = round(ratio)
    if n >= 1 and abs(ratio - n) <= WHOLE_TOLERANCE * max(1.0, ratio):
        return float(n), True
    return ratio, False


def blocks_in_course(last: int, starts_full: bool) -> int:
    """Blocks in one course whose joints run up to ``last`` (half blocks)."""
    if starts_full:  # joints 2, 4, ..., <= last
        return max(last, 0) // 2 + 1
    return max(last + 1, 0) // 2 + 1  # joints 1, 3, ..., <= last


def course_edges(last: int, end: float, half: float, starts_full: bool) -> FloatArray:
    """Block edges of one course: ``0``, the joints up to ``last`` (half
    blocks, times ``half``) and the course's end ``end``."""
    inner = np.arange(2 if starts_full else 1, last + 1, 2, dtype=np.int64)
    return np.concatenate([[0.0], inner * half, [end]])


def closer_width(block_length: float, block_height: float, friction: float) -> float:
    """The narrowest closer :func:`build_wall` lays with ``ends="closers"``: ``min(mu b, l/4)``.

    A piece ``w`` wide and ``b`` high that carries nothing tips over alone at ``lambda = w/b`` with
    non-associative friction, and at ``(w/b)(1 + mu^2)/(1 - mu^2 + 2 mu w/b)`` with associative friction;
    at ``w = mu b`` both are ``mu``, the load at which the whole wall slides on its base, which bounds the
    wall's own load factor from above. A closer at least ``mu b`` wide therefore never collapses alone
    below the wall. The cap ``l/4`` keeps the longest end unit (``l`` plus a remainder narrower than the
    closer) within a quarter block of a block, for walls of tall blocks (``mu b > l/4``).
    """
    return min(friction * block_height, 0.25 * block_length)


def closed_edges(edges: tuple[FloatArray, FloatArray], length: float,
                  closer: float) -> tuple[FloatArray, FloatArray]:
    """The two course types' edges with their ends closed as :func:`build_wall` does with ``ends="closers"``.

    The regular joints stay where they are (every lap half a block); a course whose last piece would be
    narrower than ``closer`` (:func:`closer_width`) does not lay it: its last unit runs to the end,
    ``l`` plus the remainder long. Every other course keeps its last piece, a closer at least ``closer``
    wide (``docs/micro/walls.md``: why, and what the load factor does); a piece as wide as the closer
    within :data:`WHOLE_TOLERANCE` of the length (``1.5 * 1.4`` leaves ``0.6 - 4e-16`` for a closer of
    ``0.6``) is one.
    """
    out = []
    for e in edges:
        if e.size > 2 and float(e[-1] - e[-2]) < closer - WHOLE_TOLERANCE * length:
            e = np.concatenate([e[:-2], [length]])
        out.append(e)
    return out[0], out[1]
