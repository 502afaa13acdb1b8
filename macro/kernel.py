"""The compiled kernel of the search: Eq. (10) piece by piece, its derivatives and bounds, the search.

Between two kinks ``alpha_pi`` the set of crossed storeys is fixed: the
storeys below the crack exit are crossed whole (``n_c = n_i``), the one the
crack leaves through is crossed over ``x = L/(b tau) - B_j`` rows, the ones
above not at all. Every sum of Eq. (10) is then a polynomial in ``x`` and
``y = tau - v/(n b)`` (``tan(alpha_c*)`` of Eq. 9), cubic in ``x`` and at most
quadratic in ``y``, plus the floor terms ``tau^2`` and ``tau`` of the storeys
crossed whole (their floors move over ``T_i b tau``)::

    S = s00 + s01 y + s02 y^2 + FT tau^2 + x (s10 + s11 y + s12 y^2) + x^2 y (s21 + s22 y) + s32 x^3 y^2
    O = o00 + o01 y + 2 FT tau + x (o10 + o11 y) + x^2 (o20 + o21 y) + o31 x^3 y
    F = f00 + f10 x + f20 x^2 + f30 x^3
    lambda = (S + (1 - atan(tau)/alpha_b) F) / O

(stabilising, overturning and unreduced friction moments, Eqs. 5-8 and 10).
:func:`piece_coefficients` builds the coefficients once per piece from the
storeys; :func:`lambda_derivatives` then costs a few multiply-adds and one
``atan``; :func:`lower_bound` bounds ``lambda`` from below over an interval
by interval arithmetic (every monomial is monotone in ``x, y >= 0``).

The search of :mod:`macro.search` (:func:`search_walls`) calls them millions
of times on scalars, where numpy's per-call overhead dominates: they are
compiled by numba (``nopython``, cached on disk). Every compiled function
lives in this one file on purpose: numba's cache is invalidated when the
file of the function changes, not when a file it calls into does. Tests pin
them to the term-by-term :func:`macro.equations.evaluate`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

# indices into a piece's coefficient vector
S00, S01, S02, S10, S11, S12, S21, S22, S32, FT = range(10)
O00, O01, O10, O11, O20, O21, O31 = range(10, 17)
F00, F10, F20, F30 = range(17, 21)
#: ``c = L/b`` and ``B_j``: ``x = c/tau - B_j`` (both 0 on the piece where every storey is crossed whole).
XC, XB = 21, 22
N_COEF = 23

Array = NDArray[np.float64]


@njit(cache=True)
def storey_constants(
    k: int,
    w: int,
    length: float,
    overlap: float,
    height: float,
    weight: float,
    friction: float,
    rows: Array,
    thickness: Array,
    overload: Array,
    out: Array,
) -> tuple[float, float, float]:
    """Per-storey constants of wall ``w`` (row of ``rows``, ``thickness``, ``overload``), hinge under storey ``k - 1``.

    Storey 0 is the top. Fills ``out[i]`` (``i < k``) with ``n, B, K, LA, cB, cBy, cC, cD, cg, fx, fy, ft``
    (rows, rows below, row weight ``b b_i gamma``, load above, and the
    coefficients named in :class:`macro.equations.HingeProblems`).

    Returns:
        ``(M_A, O_A, n)``: the stabilising and overturning moments of the
        half-block columns A, and the rows of the mechanism.
    """
    below = 0.0
    for i in range(k - 1, -1, -1):
        out[i, 1] = below
        below += rows[w, i]
    load = 0.0
    moment_a = overturn_a = 0.0
    b, v, L = height, overlap, length
    for i in range(k):
        n, B, q = rows[w, i], out[i, 1], overload[w, i]
        K = b * thickness[w, i] * weight
        top = (B + n) * b
        load += q
        out[i, 0], out[i, 2], out[i, 3] = n, K, load
        out[i, 4] = 0.5 * K * (L * L - v * v)
        out[i, 5] = K * (L - v) * b
        out[i, 6] = K * b * B
        out[i, 7] = 0.5 * K * b
        out[i, 8] = 0.5 * v * K * friction * b
        out[i, 9] = 0.5 * q * L * L
        out[i, 10] = q * L * top
        out[i, 11] = 0.5 * q * top * top
        load += n * K
        moment_a += 0.5 * v * n * K * v
        overturn_a += n * K * v * (0.5 * n + B) * b
    return moment_a, overturn_a, below


@njit(cache=True)
def piece_coefficients(
    p: int,
    k: int,
    st: Array,
    moment_a: float,
    overturn_a: float,
    length: float,
    overlap: float,
    height: float,
    friction: float,
    out: Array,
) -> None:
    """Coefficients of piece ``p`` (``0..k``) of a mechanism of ``k`` storeys into ``out``.

    Piece 0 has every storey crossed whole; piece ``p >= 1`` is crossed
    partly at storey ``j = p - 1`` (0 = top), whole below it, not above.
    ``st`` holds the storey constants of :func:`storey_constants`.
    """
    out[:] = 0.0
    out[S00], out[O00] = moment_a, overturn_a
    v, b = overlap, height
    cq = v * friction * b
    for i in range(k):
        n, B, K, LA = st[i, 0], st[i, 1], st[i, 2], st[i, 3]
        cB, cBy, cC, cD, cg = st[i, 4], st[i, 5], st[i, 6], st[i, 7], st[i, 8]
        fx, fy, ft = st[i, 9], st[i, 10], st[i, 11]
        if i > p - 1:  # crossed whole
            out[S01] += v * n * (cC + cD * n)
            out[S02] += n * b * (0.5 * B * cC + cD * n * (B + n / 3.0))
            out[FT] += ft
            out[O01] += n * b * (cC * (0.5 * n + B) + n * cD * (2.0 * n / 3.0 + B))
            out[F00] += n * (cg * (n + 1.0) * (n / 3.0 + B) + LA * (0.5 * n + B) * cq)
        elif i < p - 1:  # not crossed, floor moves whole
            out[S00] += n * cB + fx
            out[O00] += n * cBy * (0.5 * n + B) + fy
        else:  # crossed over x rows, floor moves whole
            out[S00] += n * cB + fx
            out[S10] -= cB
            out[S11] += v * cC
            out[S12] += 0.5 * b * B * cC
            out[S21] += v * cD
            out[S22] += b * B * cD
            out[S32] += b * cD / 3.0
            out[O00] += cBy * (0.5 * n * n + n * B) + fy
            out[O10] -= cBy * B
            out[O20] -= 0.5 * cBy
            out[O11] += b * cC * B
            out[O21] += 0.5 * b * cC + b * B * cD
            out[O31] += 2.0 * b * cD / 3.0
            w = n * K + LA
            out[F10] += cg * B + cq * w * B
            out[F20] += cg * (B + 1.0 / 3.0) + cq * (0.5 * w - K * B)
            out[F30] += cg / 3.0 - 0.5 * cq * K
            out[XC], out[XB] = length / b, B


@njit(cache=True)
def lambda_derivatives(
    tau: float, cf: Array, tau_low: float, alpha_b: float, second: bool
) -> tuple[float, float, float]:
    """Eq. (10) and its first two derivatives in ``tau`` on the piece of coefficients ``cf``.

    Returns:
        ``(lambda, dlambda/dtau, d2lambda/dtau2)``; the second derivative is
        0 unless ``second``.
    """
    u = 1.0 / tau
    x = cf[XC] * u - cf[XB]
    x1 = -cf[XC] * u * u  # dx/dtau
    x2 = -2.0 * x1 * u
    y = tau - tau_low
    # S = a0 + x a1 + x^2 a2 + x^3 a3, a_i polynomials in y (a0 with FT tau^2)
    a0 = cf[S00] + y * (cf[S01] + y * cf[S02]) + cf[FT] * tau * tau
    a0y, a0yy = cf[S01] + 2.0 * y * cf[S02] + 2.0 * cf[FT] * tau, 2.0 * (cf[S02] + cf[FT])
    a1, a1y, a1yy = cf[S10] + y * (cf[S11] + y * cf[S12]), cf[S11] + 2.0 * y * cf[S12], 2.0 * cf[S12]
    a2, a2y, a2yy = y * (cf[S21] + y * cf[S22]), cf[S21] + 2.0 * y * cf[S22], 2.0 * cf[S22]
    a3, a3y, a3yy = cf[S32] * y * y, 2.0 * cf[S32] * y, 2.0 * cf[S32]
    s, sx = a0 + x * (a1 + x * (a2 + x * a3)), a1 + x * (2.0 * a2 + 3.0 * x * a3)
    sy = a0y + x * (a1y + x * (a2y + x * a3y))
    # O = c0 + x c1 + x^2 c2 + x^3 c3, each linear in y (c0 with 2 FT tau)
    c0, c0y = cf[O00] + y * cf[O01] + 2.0 * cf[FT] * tau, cf[O01] + 2.0 * cf[FT]
    c1, c2, c3 = cf[O10] + y * cf[O11], cf[O20] + y * cf[O21], y * cf[O31]
    o = c0 + x * (c1 + x * (c2 + x * c3))
    ox = c1 + x * (2.0 * c2 + 3.0 * x * c3)
    oy = c0y + x * (cf[O11] + x * (cf[O21] + x * cf[O31]))
    # F = f0 + f1 x + f2 x^2 + f3 x^3
    f = cf[F00] + x * (cf[F10] + x * (cf[F20] + x * cf[F30]))
    fx = cf[F10] + x * (2.0 * cf[F20] + 3.0 * x * cf[F30])
    # reduction of Eq. (8), r = 1 - atan(tau)/alpha_b
    d = 1.0 / (1.0 + tau * tau)
    r, r1 = 1.0 - math.atan(tau) / alpha_b, -d / alpha_b
    inv = 1.0 / o
    lam = (s + r * f) * inv
    o1 = oy + x1 * ox
    lam1 = (sy + x1 * sx + r1 * f + r * x1 * fx - lam * o1) * inv
    if not second:
        return lam, lam1, 0.0
    sxx, sxy = 2.0 * a2 + 6.0 * x * a3, a1y + x * (2.0 * a2y + 3.0 * x * a3y)
    syy = a0yy + x * (a1yy + x * (a2yy + x * a3yy))
    s2 = syy + 2.0 * x1 * sxy + x1 * x1 * sxx + x2 * sx
    oxx, oxy = 2.0 * c2 + 6.0 * x * c3, cf[O11] + x * (2.0 * cf[O21] + 3.0 * x * cf[O31])
    o2 = 2.0 * x1 * oxy + x1 * x1 * oxx + x2 * ox
    f1, f2 = x1 * fx, x1 * x1 * (2.0 * cf[F20] + 6.0 * x * cf[F30]) + x2 * fx
    r2 = -2.0 * tau * d * r1
    num2 = s2 + r2 * f + 2.0 * r1 * f1 + r * f2
    return lam, lam1, (num2 - 2.0 * lam1 * o1 - lam * o2) * inv


@njit(cache=True)
def _low(c: float, lo: float, hi: float) -> float:
    """Least value of ``c m`` for a monomial ``m`` ranging over ``[lo, hi]``."""
    return c * (lo if c >= 0.0 else hi)


@njit(cache=True)
def lower_bound(a: float, b: float, cf: Array, tau_low: float, alpha_b: float) -> float:
    """A proven lower bound of Eq. (10) over ``a <= tau <= b`` on the piece ``cf``.

    Interval arithmetic: each monomial of ``S``, ``O`` and ``F`` is monotone in
    ``x`` (which decreases with ``tau``) and ``y`` (which increases), so its
    range over the interval is spanned by its values at the corners; the
    reduction ``1 - atan(tau)/alpha_b`` is bounded by its value at ``b`` and
    ``F >= 0``. Rounding aside, ``lambda >= lower_bound`` everywhere on the interval.
    """
    x_lo = max(cf[XC] / b - cf[XB], 0.0)
    x_hi = max(cf[XC] / a - cf[XB], 0.0)
    y_lo, y_hi = max(a - tau_low, 0.0), max(b - tau_low, 0.0)
    x2_lo, x2_hi, y2_lo, y2_hi = x_lo * x_lo, x_hi * x_hi, y_lo * y_lo, y_hi * y_hi
    s_lo = cf[S00] + cf[FT] * a * a + _low(cf[S01], y_lo, y_hi) + _low(cf[S02], y2_lo, y2_hi)
    s_lo += _low(cf[S10], x_lo, x_hi) + _low(cf[S11], x_lo * y_lo, x_hi * y_hi)
    s_lo += _low(cf[S12], x_lo * y2_lo, x_hi * y2_hi)
    s_lo += _low(cf[S21], x2_lo * y_lo, x2_hi * y_hi) + _low(cf[S22], x2_lo * y2_lo, x2_hi * y2_hi)
    s_lo += _low(cf[S32], x2_lo * x_lo * y2_lo, x2_hi * x_hi * y2_hi)
    # the least value of -O bounds O from above
    o_hi = cf[O00] + 2.0 * cf[FT] * b - _low(-cf[O01], y_lo, y_hi) - _low(-cf[O10], x_lo, x_hi)
    o_hi -= _low(-cf[O11], x_lo * y_lo, x_hi * y_hi) + _low(-cf[O20], x2_lo, x2_hi)
    o_hi -= _low(-cf[O21], x2_lo * y_lo, x2_hi * y_hi) + _low(-cf[O31], x2_lo * x_lo * y_lo, x2_hi * x_hi * y_hi)
    f_lo = cf[F00] + _low(cf[F10], x_lo, x_hi) + _low(cf[F20], x2_lo, x2_hi) + _low(cf[F30], x2_lo * x_lo, x2_hi * x_hi)
    num = s_lo + (1.0 - math.atan(b) / alpha_b) * max(f_lo, 0.0)
    if num <= 0.0 or o_hi <= 0.0:
        return -math.inf
    return num / o_hi


@njit(cache=True)
def sliding_factor(
    tau: float,
    k: int,
    st: Array,
    length: float,
    overlap: float,
    height: float,
    friction: float,
    overload: Array,
    w: int,
) -> float:
    """Eq. (12) at the crack slope ``tau``: frictional resistance over weight of the moving part.

    The terms of Table 2 and Eqs. (5)-(6) summed storey by storey, as
    :func:`macro.equations.evaluate` does (a test pins the two together);
    ``st`` holds the storey constants of :func:`storey_constants` for the
    hinge under storey ``k - 1`` of wall ``w``.
    """
    e = length / (height * tau)
    y = tau - overlap / (st[0, 1] + st[0, 0]) / height
    weight = resist = 0.0
    for i in range(k):
        n, B, K, LA = st[i, 0], st[i, 1], st[i, 2], st[i, 3]
        nc = min(max(e - B, 0.0), n)
        floor = length if e <= B + n else (B + n) * height * tau
        weight += K * (n * overlap + (n - nc) * (length - overlap) + y * nc * height * (B + 0.5 * nc))
        weight += overload[w, i] * floor
        resist += overlap * friction * nc * (0.5 * K * (nc + 1.0) + (n - nc) * K + LA)
    return resist / weight


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

    ``walls`` holds the arrays of :func:`macro.search.minimise_walls`; pieces
    whose lower bound reaches ``bound`` are skipped.
    """
    length, overlap, height, weight, friction, rows, thickness, overload = walls
    L, v, b, f = length[w], overlap[w], height[w], friction[w]
    moment_a, overturn_a, n = storey_constants(k, w, L, v, b, weight[w], f, rows, thickness, overload, st)
    tau_low, tau_high, alpha_b = v / (n * b), v / b, math.atan(v / b)
    cells, tol, max_it = int(opts[0]), opts[1], int(opts[2])
    best_l, best_t = math.inf, math.nan
    start = 0.0
    for p in range(k + 1):
        kink = L / ((st[p, 1] + st[p, 0]) * b) if p < k else math.inf
        lo, hi, start = max(tau_low, start), min(tau_high, kink), kink
        if hi < lo or (hi == lo and tau_high > tau_low):
            continue  # the kink lies outside Eq. (11): an empty piece
        piece_coefficients(p, k, st, moment_a, overturn_a, L, v, b, f, cf)
        if hi == lo:  # a one-row mechanism: Eq. (11) is a point
            return lambda_derivatives(lo, cf, tau_low, alpha_b, False)[0], lo
        if lower_bound(lo, hi, cf, tau_low, alpha_b) >= min(bound, best_l):
            continue
        lam, tau = _search_piece(lo, hi, cf, tau_low, alpha_b, cells, tol, max_it, min(bound, best_l))
        if lam < best_l:
            best_l, best_t = lam, tau
    return best_l, best_t


@njit(cache=True)
def search_walls(
    walls: tuple[Array, ...], opts: Array, shared: bool, lam: Array, tau: Array, hinge: NDArray[np.int64], lam_s: Array
) -> None:
    """The search of :mod:`macro.search` over walls ``walls`` (the arrays of :func:`macro.search.minimise_walls`).

    Fills, per wall and hinge, the minimum ``lam`` and its slope ``tau``; per
    wall, the hinge of the least minimum and Eq. (12) there. With ``shared``,
    the least value found on a wall bounds the search of its other hinges.
    ``opts`` holds ``cells, tolerance, max_iterations``.
    """
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
        L, v, b, f = length[w], overlap[w], height[w], friction[w]
        storey_constants(best_k, w, L, v, b, weight[w], f, rows, thickness, overload, st)
        lam_s[w] = sliding_factor(tau[w, best_k - 1], best_k, st, L, v, b, f, overload, w)


#: The compiled functions of this module (what :func:`compilations` counts).
COMPILED = (storey_constants, piece_coefficients, lambda_derivatives, _low, lower_bound, sliding_factor, _refine,
            _search_piece, _minimise_hinge, search_walls)


def compilations() -> int:
    """How many compilations of this module's functions this process made rather than read from numba's cache
    on disk: the first use after an install (or an edit of this file) compiles them, seconds that a time
    printed then includes; 0 once the cache is warm."""
    return sum(sum(f.stats.cache_misses.values()) for f in COMPILED)
