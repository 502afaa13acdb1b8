"""Global minimum of Eq. (10) over the crack slope of Eq. (11), for every hinge storey.

For a hinge under storey ``k`` the admissible interval of Eq. (11),
``v/(n b) <= tan(alpha_c) <= v/b``, is cut at the kinks ``tan(alpha_pi) =
L/(T_i b)`` (where the crack passes a floor level) into at most ``k + 1``
smooth pieces (:mod:`macro.pieces`). Every piece is searched:

1. a proven lower bound (interval arithmetic, :func:`macro.pieces.lower_bound`)
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

import math
from dataclasses import dataclass

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from macro.pieces import N_COEF, lambda_derivatives, lower_bound, piece_coefficients, sliding_factor, storey_constants

Array = NDArray[np.float64]


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
    """

    cells: int = 4
    tolerance: float = 1e-9
    max_iterations: int = 100

    def __post_init__(self) -> None:
        for name in ("cells", "max_iterations"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"{name} must be a positive integer, got {value!r}")
        if not (math.isfinite(self.tolerance) and 0.0 < self.tolerance < 1.0):
            raise ValueError(f"tolerance must be in (0, 1), got {self.tolerance!r}")


DEFAULT_SEARCH = SearchSettings()


@njit(cache=True)
def _refine(
    lo: float, hi: float, g_lo: float, g_hi: float, cf: Array, tau_low: float, alpha_b: float, tol: float, max_it: int
) -> tuple[float, float]:
    """Safeguarded Newton on ``dlambda/dtau`` in ``[lo, hi]``, where it goes from ``g_lo < 0`` to ``g_hi > 0``.

    Starts where the chord of the derivative crosses zero; a Newton step that
    leaves the bracket (or meets a non-positive curvature) is replaced by
    bisection. Stops when the next step would be below ``tol * tau``.

    Returns:
        ``(lambda, tau)`` at the least point evaluated.
    """
    t = lo - g_lo * (hi - lo) / (g_hi - g_lo)
    best_l, best_t = math.inf, t
    for _ in range(max_it):
        lam, g, h = lambda_derivatives(t, cf, tau_low, alpha_b, True)
        if lam < best_l:
            best_l, best_t = lam, t
        if g < 0.0:
            lo = t
        elif g > 0.0:
            hi = t
        else:
            break
        new = t - g / h if h > 0.0 else lo - 1.0
        if not lo < new < hi:
            new = 0.5 * (lo + hi)
        if abs(new - t) <= tol * t:
            break
        t = new
    return best_l, best_t


@njit(cache=True)
def _search_piece(
    a: float, b: float, cf: Array, tau_low: float, alpha_b: float, cells: int, tol: float, max_it: int, bound: float
) -> tuple[float, float]:
    """Minimum of Eq. (10) over ``a <= tau <= b`` on the piece ``cf`` (see the module docstring).

    Brackets whose lower bound is at or above ``bound`` are not refined.

    Returns:
        ``(lambda, tau)``.
    """
    t0 = a
    l0, g0, _ = lambda_derivatives(a, cf, tau_low, alpha_b, False)
    best_l, best_t = l0, a
    for i in range(1, cells + 1):
        t1 = b if i == cells else a + (b - a) * i / cells
        l1, g1, _ = lambda_derivatives(t1, cf, tau_low, alpha_b, False)
        if l1 < best_l:
            best_l, best_t = l1, t1
        if g0 < 0.0 < g1 and lower_bound(t0, t1, cf, tau_low, alpha_b) < min(bound, best_l):
            lr, tr = _refine(t0, t1, g0, g1, cf, tau_low, alpha_b, tol, max_it)
            if lr < best_l:
                best_l, best_t = lr, tr
        t0, g0 = t1, g1
    return best_l, best_t


@njit(cache=True)
def _minimise_hinge(
    k: int, w: int, walls: tuple[Array, ...], st: Array, cf: Array, opts: Array, bound: float
) -> tuple[float, float]:
    """Minimum of Eq. (10) of wall ``w`` with the hinge under storey ``k - 1``.

    ``walls`` holds the arrays of :func:`minimise_walls`; pieces whose lower
    bound reaches ``bound`` are skipped.
    """
    length, overlap, height, weight, friction, rows, thickness, overload = walls
    L, v, b = length[w], overlap[w], height[w]
    moment_a, overturn_a, n = storey_constants(
        k, L, v, b, weight[w], friction[w], rows[w], thickness[w], overload[w], st
    )
    tau_low, tau_high, alpha_b = v / (n * b), v / b, math.atan(v / b)
    cells, tol, max_it = int(opts[0]), opts[1], int(opts[2])
    best_l, best_t = math.inf, math.nan
    start = 0.0
    for p in range(k + 1):
        kink = L / ((st[p, 1] + st[p, 0]) * b) if p < k else math.inf
        lo, hi, start = max(tau_low, start), min(tau_high, kink), kink
        if hi < lo or (hi == lo and tau_high > tau_low):
            continue  # the kink lies outside Eq. (11): an empty piece
        piece_coefficients(p, k, st, moment_a, overturn_a, L, v, b, friction[w], cf)
        if hi == lo:  # a one-row mechanism: Eq. (11) is a point
            return lambda_derivatives(lo, cf, tau_low, alpha_b, False)[0], lo
        if lower_bound(lo, hi, cf, tau_low, alpha_b) >= min(bound, best_l):
            continue
        lam, tau = _search_piece(lo, hi, cf, tau_low, alpha_b, cells, tol, max_it, min(bound, best_l))
        if lam < best_l:
            best_l, best_t = lam, tau
    return best_l, best_t


@njit(cache=True)
def _minimise_walls(
    walls: tuple[Array, ...], opts: Array, shared: bool, lam: Array, tau: Array, hinge: NDArray[np.int64], lam_s: Array
) -> None:
    length, overlap, height, weight, friction, rows, thickness, overload = walls
    n_walls, n_storeys = rows.shape
    st = np.empty((n_storeys, 12))
    cf = np.empty(N_COEF)
    for w in range(n_walls):
        best, best_k = math.inf, n_storeys
        for k in range(n_storeys, 0, -1):
            lam[w, k - 1], tau[w, k - 1] = _minimise_hinge(k, w, walls, st, cf, opts, best if shared else math.inf)
            if lam[w, k - 1] <= best:  # ties go to the upper hinge
                best, best_k = lam[w, k - 1], k
        hinge[w] = best_k
        L, v, b, f, q = length[w], overlap[w], height[w], friction[w], overload[w]
        storey_constants(best_k, L, v, b, weight[w], f, rows[w], thickness[w], q, st)
        lam_s[w] = sliding_factor(tau[w, best_k - 1], best_k, st, L, v, b, f, q)


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
    out = WallMinima(
        np.empty((n_walls, n_storeys)),
        np.empty((n_walls, n_storeys)),
        np.empty(n_walls, dtype=np.int64),
        np.empty(n_walls),
    )
    opts = np.array([settings.cells, settings.tolerance, settings.max_iterations], dtype=np.float64)
    _minimise_walls(
        walls,
        opts,
        wall_minimum_only,
        out.rocking_load_factor,
        out.tan_alpha_c,
        out.hinge_storey,
        out.sliding_load_factor,
    )
    return out
