"""A wall with some blocks held to the block that carries them: :func:`hold_blocks`.

Holding a block bonds it rigidly to its host, the block below with which it
shares the longest bed joint (the ground for a block of the bottom course):
the two move as one rigid body. The held wall is the same wall with the held
block taken out, its dead and live loads carried by the host (forces summed,
moments transferred to the host's centroid) and its interfaces with the other
blocks made interfaces of the host (its bed joint with the host is gone). For
the LP this is exactly a bonded interface (contact forces of any sign and size,
no yield condition), and every analysis (:func:`micro.solve_associative`,
:func:`micro.solve_nonassociative`) runs on the held wall unchanged.

Its use: a cut end piece of the top course carries nothing above it and tips
over alone at ``lambda = width / height`` (:mod:`micro.local_mechanisms`); held to its
neighbour below, the analysis gives the wall's own mechanism.

The host keeps its own rectangle (``x0, x1, y0, y1``): a plot of the held wall
draws the hosts without the pieces they carry.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall, check_block_wall

IntArray = NDArray[np.int64]

#: Host index of a block held to the ground.
GROUND = -1


@dataclass(frozen=True, eq=False)
class HeldWall:
    """A wall with blocks held to their hosts.

    Attributes:
        wall: the held wall (the held blocks taken out).
        original: the wall it was made from.
        held: the held blocks (indices in ``original``), sorted.
        host: the host of each held block after chains are followed (index in
            ``original``; :data:`GROUND` for the ground).
        index: ``(original.n_blocks,)`` the index in ``wall`` of every block of
            ``original``: its host's for a held block (:data:`GROUND` when held
            to the ground).
    """

    wall: BlockWall
    original: BlockWall = field(repr=False)
    held: tuple[int, ...]
    host: tuple[int, ...]
    index: IntArray = field(repr=False)

    def original_blocks(self, blocks: Iterable[int]) -> tuple[int, ...]:
        """The blocks of ``original`` that make up ``blocks`` of the held wall (each with the blocks held to
        it), sorted."""
        wanted = {int(b) for b in blocks}
        return tuple(int(i) for i in np.flatnonzero(np.isin(self.index, list(wanted))))


def host_block(wall: BlockWall, block: int) -> int:
    """The block that carries ``block``: the one below with the longest bed joint under it
    (:data:`GROUND` for a block of the bottom course)."""
    below = np.flatnonzero((wall.contact_b == block) & (wall.normal[:, 1] > 0.5))
    if below.size == 0:
        raise ValueError(f"block {block} has no bed joint under it")
    widths = np.abs(wall.px[below, 1] - wall.px[below, 0])
    return int(wall.contact_a[below[int(np.argmax(widths))]])


def hold_blocks(wall: BlockWall, blocks: Iterable[int]) -> HeldWall:
    """``wall`` with ``blocks`` held to their hosts (module docstring).

    A block whose host is itself held goes with that host's host (chains are
    followed down to a block that is not held, or the ground).

    Args:
        wall: the block assemblage.
        blocks: indices of the blocks to hold (any order, repeats ignored).

    Returns:
        The :class:`HeldWall` (with no block held: the same wall).

    Raises:
        TypeError: ``wall`` is not a :class:`~micro.geometry.BlockWall`.
        ValueError: a block index out of range, or every block held.
    """
    check_block_wall(wall)
    held = sorted({int(b) for b in blocks})
    nb = wall.n_blocks
    bad = [b for b in held if not 0 <= b < nb]
    if bad:
        raise ValueError(f"hold: block {bad[0]} is not a block of the wall (0 to {nb - 1})")
    if len(held) == nb:
        raise ValueError("hold: every block is held, nothing is left to move")
    direct = {b: host_block(wall, b) for b in held}
    final: dict[int, int] = {}
    for b in held:
        h = direct[b]
        while h in direct:  # hosts lie in lower courses: the chain ends
            h = direct[h]
        final[b] = h
    keep = np.ones(nb, dtype=bool)
    keep[held] = False
    new_of_kept = np.full(nb, GROUND, dtype=np.int64)
    new_of_kept[keep] = np.arange(int(keep.sum()), dtype=np.int64)
    index = new_of_kept.copy()
    for b, h in final.items():
        index[b] = GROUND if h == GROUND else new_of_kept[h]
    return HeldWall(_held_wall(wall, final, keep, index), wall, tuple(held),
                    tuple(final[b] for b in held), index)


def _held_wall(wall: BlockWall, final: dict[int, int], keep: NDArray[np.bool_], index: IntArray) -> BlockWall:
    """The held wall's arrays: loads moved to the hosts, interfaces renumbered."""
    if not final:
        return wall
    dead, live = wall.dead.copy(), wall.live.copy()
    xc, yc = wall.xc, wall.yc
    for b, h in final.items():
        if h == GROUND:
            continue
        dx, dy = xc[b] - xc[h], yc[b] - yc[h]
        for loads in (dead, live):
            fx, fy, m = loads[b]
            loads[h] += (fx, fy, m + dx * fy - dy * fx)
    a = np.where(wall.contact_a < 0, GROUND, index[np.maximum(wall.contact_a, 0)])
    b_ = np.where(wall.contact_b < 0, GROUND, index[np.maximum(wall.contact_b, 0)])
    normal = wall.normal.copy()
    # the ground on the b side (a block held to the ground above an interface): swap the sides, so that the
    # ground is always side a; the normal turns over with them (the LP's n >= 0, |s| <= mu n are the same)
    flip = (b_ == GROUND) & (a != GROUND)
    a[flip], b_[flip] = b_[flip], a[flip]
    normal[flip] *= -1.0
    live_c = a != b_
    arrays = {name: getattr(wall, name)[keep] for name in ("x0", "x1", "y0", "y1", "course", "storey")}
    contacts = {name: getattr(wall, name)[live_c] for name in ("contact_kind", "px", "py", "mu")}
    return BlockWall(
        length=wall.length, block_length=wall.block_length, block_height=wall.block_height, rows=wall.rows,
        thickness=wall.thickness, overload=wall.overload, unit_weight=wall.unit_weight, friction=wall.friction,
        first_course=wall.first_course, head_joints=wall.head_joints, ends=wall.ends,
        dead=dead[keep], live=live[keep],
        contact_a=a[live_c], contact_b=b_[live_c], normal=normal[live_c], **arrays, **contacts,
    )
