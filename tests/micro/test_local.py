"""Local mechanisms (a cut end piece of the top course that tips over alone) and held walls.

Closed forms (``micro.local_mechanisms``): the piece, ``w`` wide and ``b`` high, loaded by
``lambda W`` at its centroid, tips over about its outer bottom corner. With
non-associative friction its head joint opens and nothing holds it:
``lambda = w/b``. With associative friction the head joint must dilate as it
slips, so its neighbour may push it (``n``) and hold it down by friction
(``mu n``): equilibrium of the piece with the bed joint at its friction limit,
``lambda W + n = mu (W + mu n)``, and the moment about the toe,
``lambda W b/2 = W w/2 + mu n w``, give
``lambda = (w/b)(1 + mu^2)/(1 - mu^2 + 2 mu w/b)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import micro
from micro.hold import GROUND, hold_blocks, host_block
from micro.local_mechanisms import LOCAL_WEIGHT_SHARE, find_local, local_mechanism, moving_blocks, weight_share

MU = 0.65


def grid_wall(length: float, block_length: float, rows: int) -> micro.BlockWall:
    """A wall of the grid that showed the local mechanisms (block height 1, f = 0.65)."""
    return micro.build_wall(length=length, block_length=block_length, block_height=1.0, rows=(rows,),
                            thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=MU)


#: (length, block length, rows, width of the top course's cut end piece): the grid's walls
#: t = 1, m = 1/3, 8 rows; t = 3/2, m = 1/2, 8 rows; t = 3/2, m = 1/3, 16 rows.
LOCAL_WALLS = [(8.0, 3.0, 8, 0.5), (16.0 / 3.0, 2.0, 8, 1.0 / 3.0), (32.0 / 3.0, 3.0, 16, 1.0 / 6.0)]


def associative_piece(w: float, b: float = 1.0, mu: float = MU) -> float:
    """The associative collapse load of the piece alone (module docstring)."""
    r = w / b
    return r * (1 + mu * mu) / (1 - mu * mu + 2 * mu * r)


def _piece(wall: micro.BlockWall) -> int:
    """The top course's last block."""
    return int(np.flatnonzero(wall.course == wall.n_courses - 1)[-1])


@pytest.mark.parametrize("length, block_length, rows, width", LOCAL_WALLS)
def test_nonassociative_piece_tips_over_alone(length: float, block_length: float, rows: int, width: float) -> None:
    """The iterated LP (and its descent) governs by the piece alone at ``lambda = w/b``: detected as local,
    one block, the top course's cut end piece, named in the description."""
    wall = grid_wall(length, block_length, rows)
    piece = _piece(wall)
    assert wall.block_lengths[piece] == pytest.approx(width)
    r = micro.solve_nonassociative(wall)
    assert r.load_factor == pytest.approx(width, rel=1e-7)
    loc = local_mechanism(wall, r)
    assert loc is not None
    assert loc.blocks == (piece,)
    assert loc.load_factor == pytest.approx(width, rel=1e-7)
    assert loc.direction == "+x"
    assert loc.weight_share == pytest.approx(width / (length * rows))
    assert loc.description == (f"the cut end piece of course {rows} (right end, {width:.4g} x 1) tips over alone")


@pytest.mark.parametrize("length, block_length, rows, width", LOCAL_WALLS)
def test_associative_piece_tips_over_alone(length: float, block_length: float, rows: int, width: float) -> None:
    """The associative LP governs by the piece alone at its closed form (module docstring)."""
    wall = grid_wall(length, block_length, rows)
    r = micro.solve_associative(wall)
    assert r.load_factor == pytest.approx(associative_piece(width), rel=1e-6)
    loc = local_mechanism(wall, r)
    assert loc is not None and loc.blocks == (_piece(wall),)
    assert loc.description.endswith("tips over alone")


@pytest.mark.parametrize("solve", [micro.solve_associative, micro.solve_nonassociative])
@pytest.mark.parametrize("length, block_length, rows, width", LOCAL_WALLS[:2])
def test_held_piece_gives_the_walls_own_mechanism(solve, length: float, block_length: float, rows: int,
                                                   width: float) -> None:
    """Held to the block below, the piece no longer tips: the held wall's load factor is higher and its
    mechanism is not local (both friction models)."""
    wall = grid_wall(length, block_length, rows)
    first = solve(wall)
    loc = local_mechanism(wall, first)
    assert loc is not None
    held = hold_blocks(wall, loc.blocks)
    r = solve(held.wall)
    assert r.ok
    lam = r.load_factor
    assert lam > loc.load_factor + 0.01
    assert local_mechanism(held.wall, r) is None


@pytest.mark.parametrize("length, block_length, rows", [(16.0, 3.0, 8), (8.0, 2.0, 8), (16.0, 3.0, 16)])
def test_wall_mechanisms_are_not_local(length: float, block_length: float, rows: int) -> None:
    """The grid's walls whose top course ends with a half or a long block collapse as walls: their moving
    blocks reach below the top course and carry more than the local share of the weight."""
    wall = grid_wall(length, block_length, rows)
    for r in (micro.solve_associative(wall), micro.solve_nonassociative(wall)):
        assert local_mechanism(wall, r) is None
        low = getattr(r, "lowest_state", None)
        mech = low.state.mechanism if low is not None else r.mechanism
        moving = moving_blocks(wall, mech)
        assert weight_share(wall, moving) > LOCAL_WEIGHT_SHARE
        assert np.any(wall.course[list(moving)] < wall.n_courses - 1)


def test_threshold_edges() -> None:
    """Local exactly up to the share (inclusive); a share of 0 or one just below the piece's finds nothing;
    no mechanism or no number finds nothing; a bad share is refused."""
    wall = grid_wall(8.0, 3.0, 8)
    r = micro.solve_associative(wall)
    mech, lam = r.mechanism, r.load_factor
    part = 0.5 / 64.0
    assert part < LOCAL_WEIGHT_SHARE
    assert find_local(wall, mech, lam, "+x", share=part) is not None
    assert find_local(wall, mech, lam, "+x", share=part * (1 - 1e-9)) is None
    assert find_local(wall, mech, lam, "+x", share=0.0) is None
    assert find_local(wall, None, lam, "+x") is None
    assert find_local(wall, mech, math.nan, "+x") is None
    for bad in (-0.1, 1.0, "0.02"):
        with pytest.raises(ValueError, match="share must be a number in"):
            find_local(wall, mech, lam, "+x", share=bad)  # type: ignore[arg-type]


def test_local_needs_the_top_course() -> None:
    """The same small share below the top course is not local: a block that carries others is held in by
    the wall (a mechanism of the wall's corner, whatever its share)."""
    wall = grid_wall(32.0 / 3.0, 3.0, 16)
    r = micro.solve_associative(wall)
    mech = r.mechanism
    v = np.zeros_like(mech.velocities)
    below = int(np.flatnonzero(wall.course == wall.n_courses - 2)[-1])
    v[below] = (1.0, 0.0, 0.0)
    moved = micro.Mechanism(v, mech.opening_rate, mech.slip_rate, mech.contact_state, 1.0, -0.5)
    assert moving_blocks(wall, moved) == (below,)
    assert weight_share(wall, (below,)) < LOCAL_WEIGHT_SHARE
    assert find_local(wall, moved, 0.5, "+x") is None


def test_hold_blocks_moves_the_loads_and_the_interfaces() -> None:
    """Holding keeps every force and moment of the loads (about the origin), drops the held block and its
    bed joint with the host, and gives the host its other interfaces; nothing held is the same wall."""
    wall = grid_wall(8.0, 3.0, 8)
    piece = _piece(wall)
    host = host_block(wall, piece)
    assert wall.course[host] == wall.n_courses - 2 and wall.x1[host] == pytest.approx(8.0)
    hw = hold_blocks(wall, [piece, piece])
    w2 = hw.wall
    assert w2.n_blocks == wall.n_blocks - 1 and hw.held == (piece,) and hw.host == (host,)
    assert hw.index[piece] == hw.index[host]
    for name in ("dead", "live"):
        a, b = getattr(wall, name), getattr(w2, name)
        assert b[:, :2].sum(axis=0) == pytest.approx(a[:, :2].sum(axis=0))
        m_a = np.sum(a[:, 2] + wall.xc * a[:, 1] - wall.yc * a[:, 0])
        m_b = np.sum(b[:, 2] + w2.xc * b[:, 1] - w2.yc * b[:, 0])
        assert m_b == pytest.approx(m_a)
    # the piece had a head joint and a bed joint: the bed joint with the host is gone
    assert w2.n_contacts == wall.n_contacts - 1
    assert np.all(w2.contact_b < w2.n_blocks) and np.all(w2.contact_a < w2.n_blocks)
    assert hw.original_blocks([hw.index[host]]) == (host, piece)
    assert hold_blocks(wall, []).wall is wall


def test_hold_to_the_ground_and_chains() -> None:
    """A bottom-course block is held to the ground (its interfaces become the ground's, on side a); a
    block whose host is held goes with its host's host."""
    wall = grid_wall(8.0, 3.0, 3)
    bottom = int(np.flatnonzero(wall.course == 0)[-1])
    hw = hold_blocks(wall, [bottom])
    assert hw.host == (GROUND,) and hw.index[bottom] == GROUND
    assert np.all(hw.wall.contact_b >= 0)
    assert micro.solve_associative(hw.wall).ok
    piece = _piece(wall)
    mid = host_block(wall, piece)
    chained = hold_blocks(wall, [piece, mid])
    assert chained.host == tuple(sorted((host_block(wall, mid),) * 2))
    with pytest.raises(ValueError, match="hold: block 999 is not a block of the wall"):
        hold_blocks(wall, [999])
