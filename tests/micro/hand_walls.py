"""Block assemblages built by hand (the builder only makes running bond).

:func:`micro.build_wall` lays every other course with half blocks at the
ends, so a wall one block long (``L = l``) is a full block under two half
blocks, not a column: a column of aligned blocks is built here directly as a
:class:`micro.BlockWall` (unit weight, unit thickness, no overload).
"""

from __future__ import annotations

import numpy as np

import micro
from micro.geometry import BASE, BED


def column_wall(k: int, width: float, height: float, friction: float) -> micro.BlockWall:
    """``k`` aligned blocks of ``width x height`` stacked on a fixed base.

    Block ``i`` (from the base) spans ``[0, width] x [i h, (i + 1) h]``;
    interface ``i`` joins block ``i - 1`` (``-1``: the ground) to block ``i``.
    """
    i = np.arange(k)
    weight = width * height
    dead = np.zeros((k, 3))
    dead[:, 1] = -weight
    live = np.zeros((k, 3))
    live[:, 0] = weight
    return micro.BlockWall(
        length=width, block_length=width, block_height=height, rows=(k,), thickness=(1.0,), overload=(0.0,),
        unit_weight=1.0, friction=friction, first_course="full", head_joints="frictional", ends="closers",
        x0=np.zeros(k), x1=np.full(k, width), y0=i * height, y1=(i + 1) * height, course=i.astype(np.int64),
        storey=np.ones(k, dtype=np.int64), dead=dead, live=live, contact_a=(i - 1).astype(np.int64),
        contact_b=i.astype(np.int64), contact_kind=np.where(i == 0, BASE, BED).astype(np.int64),
        normal=np.tile([0.0, 1.0], (k, 1)), px=np.tile([0.0, width], (k, 1)),
        py=np.column_stack([i * height, i * height]).astype(float), mu=np.full(k, friction),
    )


def small_wall(length: float, block_length: float, block_height: float, rows: int, friction: float) -> micro.BlockWall:
    """A single-storey running-bond wall of the builder (unit weight and thickness)."""
    return micro.build_wall(length=length, block_length=block_length, block_height=block_height, rows=(rows,),
                            thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=friction)
