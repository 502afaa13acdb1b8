"""A dense brute force of Eq. (10), and random walls to run it on (shared by the macro tests)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from macro.equations import HingeProblems, hinge_problems, load_factor

Array = NDArray[np.float64]

#: Crack angles of the brute force per hinge, evenly spaced over Eq. (11) (the kinks and ends are added).
GRID_POINTS = 100_001
#: Crack angles evaluated at once (the temporaries stay in cache).
CHUNK = 4096


@dataclass(frozen=True)
class Walls:
    """Walls with unequal storeys, in the arguments of :func:`macro.search.minimise_walls`."""

    length: Array
    overlap: Array
    block_height: Array
    unit_weight: Array
    friction: Array
    rows: Array
    thickness: Array
    overload: Array

    def problems(self, w: int) -> HingeProblems:
        """Every hinge of wall ``w``, for :func:`macro.equations.load_factor`."""
        n = self.rows.shape[1]
        rep = lambda a: np.full(n, a[w])  # noqa: E731
        tile = lambda a: np.tile(a[w], (n, 1))  # noqa: E731
        return hinge_problems(
            rep(self.length), rep(self.overlap), rep(self.block_height), rep(self.unit_weight), rep(self.friction),
            tile(self.rows), tile(self.thickness), tile(self.overload), np.arange(1, n + 1),
        )  # fmt: skip


def random_walls(rng: np.random.Generator, count: int, storeys: int) -> Walls:
    """Random walls: 1-30 rows per storey, thickness and floor load per storey, any units."""
    rows = rng.integers(1, 31, (count, storeys)).astype(float)
    b = rng.uniform(0.5, 2.0, count)
    loaded = rng.random(count) < 0.7
    return Walls(
        length=rng.uniform(0.2, 4.0, count) * rows.sum(axis=1) * b,
        overlap=rng.uniform(0.15, 1.0, count) * b,
        block_height=b,
        unit_weight=rng.uniform(0.5, 2.0, count),
        friction=rng.uniform(0.2, 1.2, count),
        rows=rows,
        thickness=rng.uniform(0.5, 2.0, (count, storeys)) * b[:, None],
        overload=rng.uniform(0.0, 8.0, (count, storeys)) * (rows.sum(axis=1) * b * loaded)[:, None],
    )


def brute_force(pb: HingeProblems, points: int = GRID_POINTS) -> Array:
    """Least Eq. (10) of every problem over ``points`` even crack angles of Eq. (11), its ends and its kinks."""
    out = np.empty(pb.size)
    for i in range(pb.size):
        one = pb.select(slice(i, i + 1))
        lo, hi = one.tau_low[0, 0], one.tau_high[0, 0]
        kinks = one.breakpoints[0][(one.breakpoints[0] >= lo) & (one.breakpoints[0] <= hi)]
        tau = np.concatenate([np.tan(np.linspace(np.arctan(lo), np.arctan(hi), points)), kinks, [lo, hi]])
        out[i] = min(load_factor(tau[None, j : j + CHUNK], one).min() for j in range(0, tau.size, CHUNK))
    return out
