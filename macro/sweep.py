"""Vectorised path: arrays of the paper's parameters in, arrays of results out.

Walls are described by the paper's Table 4 parameters and normalised by
:func:`macro.paper.paper_walls` (block height 1, thickness 1, unit weight 1,
rows split equally over the storeys, the same overload ratio ``p`` on every
floor), as one wall of ``macro.solve`` built by ``WallSpec.from_paper`` is; a
test pins that both give the same numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from macro import checks
from macro.bounds import MECHANISMS, governing, overturning_load_factor
from macro.paper import BLOCK_HEIGHT, broadcast_shape, paper_walls
from macro.search import DEFAULT_SEARCH, SearchSettings, minimise_walls
from macro.solve import search_bytes

__all__ = ["MECHANISMS", "SweepResult", "sweep"]

#: Peak memory of a sweep besides its search batches, per wall and per wall and storey: the
#: parameters broadcast and checked, the walls, the results and the rigid bounds over every
#: storey. Measured (peak resident set over the input array): 10^6 walls of 1 and 5 storeys
#: 258 and 611 bytes per wall, 3 x 10^5 walls of 20 storeys 2,094 (about 160 + 97 N); the
#: estimate keeps a margin above each.
SWEEP_BYTES_PER_WALL = 200
SWEEP_BYTES_PER_WALL_AND_STOREY = 110


def sweep_bytes(walls: int, storeys: int) -> int:
    """Estimated peak memory of a sweep of ``walls`` walls of ``storeys`` storeys (its search batches apart)."""
    return walls * (SWEEP_BYTES_PER_WALL + SWEEP_BYTES_PER_WALL_AND_STOREY * storeys)


@dataclass(frozen=True)
class SweepResult:
    """Results of :func:`sweep`, one entry per wall (broadcast shape).

    ``mechanism`` holds indices into :data:`MECHANISMS`; ``load_factor`` is
    the least of Eq. (10), ``f`` and the rigid overturning bound
    (:mod:`macro.bounds`), NaN where it is not a finite positive number.
    """

    load_factor: NDArray[np.float64]
    rocking_load_factor: NDArray[np.float64]
    sliding_load_factor: NDArray[np.float64]
    overturning_load_factor: NDArray[np.float64]
    tan_alpha_c: NDArray[np.float64]
    alpha_c_deg: NDArray[np.float64]
    alpha_ratio: NDArray[np.float64]
    hinge_storey: NDArray[np.int_]
    mechanism: NDArray[np.int_]


def sweep(
    t: ArrayLike,
    m: ArrayLike,
    rows: ArrayLike,
    f: ArrayLike,
    p: ArrayLike = 0.0,
    storeys: int = 1,
    *,
    p_height: str = "wall",
    settings: SearchSettings = DEFAULT_SEARCH,
    chunk: int = 4096,
) -> SweepResult:
    """Macro-block load factors of many walls at once.

    Args:
        t: the wall shape ratio H/L (the paper's parameters ``t, m, rows, f, p``
            are broadcast together).
        m: the unit shape ratio b/l.
        rows: the number of rows o.
        f: the friction coefficient.
        p: the overloading ratio.
        storeys: number of storeys ``N`` of every wall.
        p_height: ``"wall"`` or ``"storey"``, the reading of ``p``
            (see :mod:`macro.paper`).
        settings: search resolution.
        chunk: walls per vectorised batch (memory vs. speed), a positive integer.

    Raises:
        ValueError: naming the first invalid parameter; parameters whose shapes do not broadcast together;
            a sweep whose estimated memory (:data:`SWEEP_BYTES_PER_WALL`, :data:`SWEEP_BYTES_PER_WALL_AND_STOREY`)
            exceeds the memory available (:class:`macro.checks.TooLarge`, checked before any array is built).
        TypeError: ``settings`` that is not a :class:`SearchSettings`.
    """
    if not isinstance(settings, SearchSettings):
        raise TypeError(f"settings must be a macro.SearchSettings, got {settings!r} ({type(settings).__name__})")
    if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1:
        raise ValueError(checks.POSITIVE_INT.format(name="chunk", value=chunk))
    chunk = int(chunk)
    n = checks.positive_int("storeys", storeys)
    size = math.prod(broadcast_shape(t=t, m=m, rows=rows, f=f, p=p))
    batch = min(size, chunk)
    checks.fits_in_memory("storeys", f"a batch of {batch} walls of {n} storeys", search_bytes(n, batch))
    what = f"a sweep of {size:,} walls of {n} storey{'s' if n > 1 else ''}"
    checks.fits_in_memory("t, m, rows, f, p", what, sweep_bytes(size, n))
    walls = paper_walls(t, m, rows, f, p, storeys, p_height)
    shape, N = walls.shape, walls.storeys
    W = walls.size
    out = {k: np.empty(W) for k in ("lam", "lam_s", "tau", "hinge")}
    for s in range(0, W, chunk):
        sl = slice(s, min(s + chunk, W))
        n_w = sl.stop - sl.start
        ones = np.ones(n_w)
        per = np.repeat(walls.rows_per_storey[sl, None], N, axis=1)
        q = np.repeat(walls.overload[sl, None], N, axis=1)
        found = minimise_walls(
            walls.length[sl], walls.overlap[sl], ones * BLOCK_HEIGHT, ones, walls.friction[sl],
            per, np.ones((n_w, N)), q, settings, wall_minimum_only=True,
        )  # fmt: skip
        r = np.arange(n_w)
        out["hinge"][sl] = found.hinge_storey
        out["lam"][sl] = found.rocking_load_factor[r, found.hinge_storey - 1]
        out["tau"][sl] = found.tan_alpha_c[r, found.hinge_storey - 1]
        out["lam_s"][sl] = found.sliding_load_factor

    lam, tau = out["lam"], out["tau"]
    ratio = np.arctan(tau) / np.arctan(walls.overlap / BLOCK_HEIGHT)
    per_storey = np.repeat(walls.rows_per_storey[:, None], N, axis=1)
    ones = np.ones(W)
    lam_o = overturning_load_factor(
        walls.length, ones, ones, per_storey, np.ones((W, N)), np.repeat(walls.overload[:, None], N, axis=1)
    )
    lam_g, mech = governing(lam, walls.friction, lam_o, ratio)
    rs = lambda a: a.reshape(shape)  # noqa: E731
    return SweepResult(
        load_factor=rs(np.where(np.isfinite(lam_g) & (lam_g > 0), lam_g, np.nan)),
        rocking_load_factor=rs(lam),
        sliding_load_factor=rs(out["lam_s"]),
        overturning_load_factor=rs(lam_o),
        tan_alpha_c=rs(tau),
        alpha_c_deg=rs(np.degrees(np.arctan(tau))),
        alpha_ratio=rs(ratio),
        hinge_storey=rs(out["hinge"].astype(int)),
        mechanism=rs(mech.astype(int)),
    )
