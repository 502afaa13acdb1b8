"""The rigid-body bounds of the load factor, and which mechanism governs.

Eq. (10) minimises over one family of mechanisms: a crack from the hinge O
through the wall, the part beyond it rocking about O. Two mechanisms outside
that family are open to every dry-joint wall, and each bounds the collapse load
factor from above (kinematic theorem):

* **sliding**: the wall above any bed joint slides on it, resisted by
  ``f`` times the weight and floor loads above it and driven by ``lambda`` times
  the same masses, so ``lambda = f`` (the paper calls ``f`` an upper bound);
* **overturning**: the storeys ``1..k`` above the base of storey ``k`` turn as
  one rigid body about the far corner of that base, with no crack in the
  wall: ``lambda = (sum of weights and floor loads) (L/2) / (their moment of
  height above that base)``, ``L/H`` for a wall without floor loads.

For a wall much longer than a block the crack of Eq. (10) always does better
than overturning. For a slender wall (length near one block) the crack of
Eq. (2) leaves the far side a row or two above O, the moving part is the wall
less a small wedge at its base, and with the stepped crack of Eq. (9) part D
reaches past the far end of the wall: Eq. (10) then exceeds the rigid
overturning bound (by 0.2 % for a wall one block long and 60 rows high). The
paper's model assumes the crack lies inside the wall; the suite keeps Eq. (10)'s
minimum as ``rocking_load_factor`` and reports as the load factor the least of
the three mechanisms, with the mechanism that governs.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: The governing mechanisms (indices of :func:`governing`).
MECHANISMS = ("rocking-sliding", "rocking", "sliding", "overturning")

#: Tolerance on ``alpha_c/alpha_b`` above which the mechanism reads as pure rocking.
ROCKING_TOL = 1e-9


def overturning_load_factor(
    length: ArrayLike,
    block_height: ArrayLike,
    unit_weight: ArrayLike,
    rows: ArrayLike,
    thickness: ArrayLike,
    overload: ArrayLike,
) -> FloatArray:
    """The least load factor of the storeys ``1..k`` overturning as one rigid body, over ``k``.

    Args:
        length, block_height, unit_weight: shape ``(P,)``.
        rows, thickness, overload: shape ``(P, N)``, storey 1 (top) first.

    Returns:
        Shape ``(P,)``.
    """
    L = np.asarray(length, dtype=float)[:, None]
    b = np.asarray(block_height, dtype=float)[:, None]
    n = np.asarray(rows, dtype=float)
    weight = np.asarray(unit_weight, dtype=float)[:, None] * b * np.asarray(thickness, dtype=float) * n * L
    floor = np.asarray(overload, dtype=float) * L
    below = np.cumsum(n[:, ::-1], axis=1)[:, ::-1] - n  # rows of the wall below each storey
    top = below + n
    mass = np.cumsum(weight + floor, axis=1)  # storeys 1..k
    moment = np.cumsum(weight * (below + 0.5 * n) * b + floor * top * b, axis=1)  # about the wall's base
    over = moment - below * b * mass  # about the base of storey k
    return np.asarray(np.min(0.5 * L * mass / over, axis=1), dtype=float)


def governing(
    rocking: ArrayLike, friction: ArrayLike, overturning: ArrayLike, alpha_ratio: ArrayLike
) -> tuple[FloatArray, NDArray[np.int_]]:
    """The load factor (the least of the three mechanisms) and the index in :data:`MECHANISMS` of the one that governs.

    Eq. (10) keeps the load factor on a tie; ``"rocking"`` when ``alpha_c = alpha_b``.
    """
    lam_r, f, lam_o = (np.asarray(x, dtype=float) for x in (rocking, friction, overturning))
    crack = np.where(np.asarray(alpha_ratio) >= 1.0 - ROCKING_TOL, 1, 0)
    mech = np.where(lam_o < np.minimum(lam_r, f), 3, np.where(f < lam_r, 2, crack))
    return np.minimum(np.minimum(lam_r, f), lam_o), mech
