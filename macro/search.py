"""Global minimum of Eq. (10) over the crack slope of Eq. (11), for every hinge storey.

For a hinge under storey ``k`` the admissible interval of Eq. (11),
``v/(n b) <= tan(alpha_c) <= v/b``, is cut at the kinks ``tan(alpha_pi) =
L/(T_i b)`` (where the crack passes a floor level) into at most ``k + 1``
smooth pieces (:mod:`macro.kernel`). Every piece is searched:

1. a proven lower bound (interval arithmetic, :func:`macro.kernel.lower_bound`)
   at or above the best value already found excludes the piece: it cannot
   hold the minimum;
2. otherwise Eq. (10) and its derivative are evaluated at ``cells + 1``
   equally spaced slopes (the piece's ends included); every cell over which
   the derivative goes from negative to positive brackets a local minimum,
   and each bracket whose own lower bound does not exclude it is refined by
   a safeguarded Newton iteration on the derivative (bisection whenever the
   Newton step leaves the bracket or the curvature is not positive) until
   the step falls below ``tolerance`` relative;
3. the minimum of the piece is the least of its samples and refined points;
   a minimum at a piece's end (a kink or an end of Eq. 11) is a sample.

Sampling the derivative, not only the value, finds every local minimum
that is at least one cell away from a local maximum: on random walls Eq. (10)
has at most one interior local minimum per piece, but sometimes behind a local
maximum near the piece's end, which the derivatives at the ends alone miss.
The tests compare against a dense brute force.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from macro.kernel import search_walls

Array = NDArray[np.float64]


#: The most cells per piece and Newton/bisection steps per bracket a search may take: the
#: defaults are 4 and 100 (bisection alone needs about 30), and a count past this only
#: makes a search that never ends (the kernel reads the counts as doubles).
MAX_SEARCH_COUNT = 10_000


@dataclass(frozen=True)
class SearchSettings:
    """How each smooth piece of Eq. (10) is searched.

    Attributes:
        cells: cells each piece is cut into for sampling Eq. (10) and its
            derivative (``cells + 1`` samples, the ends included).
        tolerance: the Newton iteration stops when its step is below
            ``tolerance * tan(alpha_c)``; the load factor is then exact to
            far below it (it is stationary there).
        max_iterations: cap on Newton/bisection steps per bracket (bisection
            alone reaches ``tolerance = 1e-9`` in about 30).

    Both counts are at most :data:`MAX_SEARCH_COUNT`.
    """

    cells: int = 4
    tolerance: float = 1e-9
    max_iterations: int = 100

    def __post_init__(self) -> None:
        for name in ("cells", "max_iterations"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_SEARCH_COUNT:
                raise ValueError(f"{name} must be an integer in 1..{MAX_SEARCH_COUNT:,}, got {value!r}")
        tol = self.tolerance
        if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not (0.0 < tol < 1.0):
            raise ValueError(f"tolerance must be in (0, 1), got {tol!r}")


DEFAULT_SEARCH = SearchSettings()


@dataclass(frozen=True)
class WallMinima:
    """What :func:`minimise_walls` returns.

    Attributes:
        rocking_load_factor: minimum of Eq. (10) for each wall and hinge,
            shape ``(W, N)``, column ``k - 1`` for the hinge under storey ``k``.
        tan_alpha_c: the crack slope there, shape ``(W, N)``.
        hinge_storey: the hinge storey of each wall's least minimum (1 = top), shape ``(W,)``.
        sliding_load_factor: Eq. (12) at that hinge and crack, shape ``(W,)``.
    """

    rocking_load_factor: Array
    tan_alpha_c: Array
    hinge_storey: NDArray[np.int_]
    sliding_load_factor: Array


def minimise_walls(
    length: ArrayLike,
    overlap: ArrayLike,
    block_height: ArrayLike,
    unit_weight: ArrayLike,
    friction: ArrayLike,
    rows: ArrayLike,
    thickness: ArrayLike,
    overload: ArrayLike,
    settings: SearchSettings = DEFAULT_SEARCH,
    *,
    wall_minimum_only: bool = False,
) -> WallMinima:
    """Minimum of Eq. (10) over Eq. (11) for every wall and every hinge storey.

    Args:
        length, overlap, block_height, unit_weight, friction: ``L``, ``v``,
            ``b``, ``gamma``, ``f``, shape ``(W,)``.
        rows, thickness, overload: ``n_i``, ``b_i``, ``q_i``, shape ``(W, N)``,
            storey 1 (the top) first.
        settings: the search.
        wall_minimum_only: exclude the pieces of every hinge whose bound lies
            above the least value found so far on the same wall (hinges are
            searched from the bottom up): only each wall's minimum over the
            hinges is then exact, a hinge that cannot hold it reports a
            larger value or ``inf``.

    Returns:
        The minima, see :class:`WallMinima`.
    """
    walls = tuple(
        np.ascontiguousarray(x, dtype=np.float64)
        for x in (length, overlap, block_height, unit_weight, friction, rows, thickness, overload)
    )
    n_walls, n_storeys = walls[5].shape
    shape = (n_walls, n_storeys)
    out = WallMinima(np.empty(shape), np.empty(shape), np.empty(n_walls, dtype=np.int64), np.empty(n_walls))
    opts = np.array([settings.cells, settings.tolerance, settings.max_iterations], dtype=np.float64)
    fields = (out.rocking_load_factor, out.tan_alpha_c, out.hinge_storey, out.sliding_load_factor)
    search_walls(walls, opts, wall_minimum_only, *fields)
    return out
