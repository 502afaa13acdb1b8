"""Vectorised path: arrays of the paper's parameters in, arrays of results out.

Walls are described by the paper's Table 4 parameters and normalised by
:func:`macro.paper.paper_walls` (block height 1, thickness 1, unit weight 1,
rows split equally over the storeys, the same overload ratio ``p`` on every
floor), as one wall of ``macro.solve`` built by ``WallSpec.from_paper`` is; a
test pins that both give the same numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from macro import checks
from macro.bounds import MECHANISMS, governing, overturning_load_factor
from macro.model import SearchSettings, evaluate, hinge_problems, minimise, sample_pieces
from macro.paper import BLOCK_HEIGHT, paper_walls
from macro.solve import SEARCH_BYTES_PER_STOREY_CUBED

#: Search used by :func:`sweep`: five samples per smooth piece, ten golden-section
#: steps and one parabolic step; within 2e-12 of a 100,001-point brute force on
#: 300 random walls of 1, 3 and 5 storeys.
SWEEP_SEARCH = SearchSettings(initial_points=5, method="golden", rounds=10)

__all__ = ["MECHANISMS", "SWEEP_SEARCH", "SweepResult", "sweep"]


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
    settings: SearchSettings = SWEEP_SEARCH,
    chunk: int = 4096,
) -> SweepResult:
    """Macro-block load factors of many walls at once.

    Args:
        t, m, rows, f, p: the paper's parameters, broadcast together.
        storeys: number of storeys ``N`` of every wall.
        p_height: ``"wall"`` or ``"storey"``, the reading of ``p``
            (see :mod:`macro.paper`).
        settings: search resolution.
        chunk: walls per vectorised batch (memory vs. speed).

    Raises:
        ValueError: naming the first invalid parameter.
    """
    walls = paper_walls(t, m, rows, f, p, storeys, p_height)
    shape, N = walls.shape, walls.storeys
    W = walls.size
    need = SEARCH_BYTES_PER_STOREY_CUBED * N**3 * min(W, chunk)
    checks.fits_in_memory("storeys", f"a batch of {min(W, chunk)} walls of {N} storeys", need)
    out = {k: np.empty(W) for k in ("lam", "lam_s", "tau", "hinge")}
    for s in range(0, W, chunk):
        sl = slice(s, min(s + chunk, W))
        n_w = sl.stop - sl.start
        per = walls.rows_per_storey[sl]
        q = walls.overload[sl]
        lam = np.empty((N, n_w))
        tau = np.empty((N, n_w))
        lam_s = np.empty((N, n_w))
        problems, samples = [], []
        for k in range(1, N + 1):  # the hinge storey; storeys below it drop out
            pb = hinge_problems(
                length=walls.length[sl],
                overlap=walls.overlap[sl],
                block_height=np.ones(n_w),
                unit_weight=np.ones(n_w),
                friction=walls.friction[sl],
                rows=np.repeat(per[:, None], k, axis=1),
                thickness=np.ones((n_w, k)),
                overload=np.repeat(q[:, None], k, axis=1),
                hinge=np.full(n_w, k),
            )
            problems.append(pb)
            samples.append(sample_pieces(pb, settings))
        # the best sample of any hinge bounds the wall's minimum from above:
        # pieces (and whole hinges) that cannot go below it are not refined
        best = np.full(n_w, np.inf)
        for sm in samples:
            np.minimum.at(best, sm.owner, sm.best_l)
        for k, (pb, sm) in enumerate(zip(problems, samples, strict=True)):
            lam[k], tau[k] = minimise(pb, settings, samples=sm, upper_bound=best)
            lam_s[k] = evaluate(tau[k][:, None], pb)["lambda_s"][:, 0]
        best = np.argmin(lam, axis=0)
        r = np.arange(n_w)
        out["lam"][sl] = lam[best, r]
        out["tau"][sl] = tau[best, r]
        out["lam_s"][sl] = lam_s[best, r]
        out["hinge"][sl] = best + 1

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
