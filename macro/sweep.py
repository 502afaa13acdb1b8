"""Vectorised path: arrays of the paper's parameters in, arrays of results out.

Walls are described by the paper's Table 4 parameters and normalised as in
:meth:`comparison.spec.WallSpec.from_paper` (block height 1, thickness 1,
unit weight 1, rows split equally over the storeys, the same overload ratio
``p`` on every floor); a test pins that both give the same numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from macro.search import DEFAULT_SEARCH, SearchSettings, minimise_walls

MECHANISMS = ("rocking-sliding", "rocking", "sliding")


@dataclass(frozen=True)
class SweepResult:
    """Results of :func:`sweep`, one entry per wall (broadcast shape).

    ``mechanism`` holds indices into :data:`MECHANISMS`.
    """

    load_factor: NDArray[np.float64]
    rocking_load_factor: NDArray[np.float64]
    sliding_load_factor: NDArray[np.float64]
    tan_alpha_c: NDArray[np.float64]
    alpha_c_deg: NDArray[np.float64]
    alpha_ratio: NDArray[np.float64]
    hinge_storey: NDArray[np.int_]
    mechanism: NDArray[np.int_]


def _check(name: str, a: NDArray[np.float64], ok: NDArray[np.bool_], rule: str) -> None:
    if not np.all(ok):
        i = int(np.flatnonzero(~ok.ravel())[0])
        raise ValueError(f"{name} must be {rule}, got {a.ravel()[i]!r} (entry {i})")


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
        t, m, rows, f, p: the paper's parameters, broadcast together.
        storeys: number of storeys ``N`` of every wall.
        p_height: ``"wall"`` or ``"storey"``, the reading of ``p``
            (see :mod:`comparison.spec`).
        settings: search resolution.
        chunk: walls per vectorised batch (memory vs. speed).

    Raises:
        ValueError: naming the first invalid parameter.
    """
    t, m, o, f, p = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (t, m, rows, f, p)))
    shape = t.shape
    t, m, o, f, p = (x.ravel() for x in (t, m, o, f, p))
    if isinstance(storeys, bool) or not float(storeys).is_integer() or storeys < 1:
        raise ValueError(f"storeys must be a positive integer, got {storeys!r}")
    N = int(storeys)
    _check("t", t, np.isfinite(t) & (t > 0), "a positive number")
    _check("m", m, np.isfinite(m) & (m > 0) & (m <= 1), "in (0, 1]")
    _check("rows", o, (o > 0) & (o == np.round(o)), "a positive integer")
    _check("rows", o, np.mod(o, N) == 0, f"divisible by storeys={N}")
    _check("f", f, np.isfinite(f) & (f > 0), "a positive number")
    _check("p", p, np.isfinite(p) & (p >= 0), "zero or positive")
    if p_height not in ("wall", "storey"):
        raise ValueError(f"p_height must be 'wall' or 'storey', got {p_height!r}")

    W = t.size
    out = {k: np.empty(W) for k in ("lam", "lam_s", "tau", "hinge")}
    for s in range(0, W, chunk):
        sl = slice(s, min(s + chunk, W))
        n_w = sl.stop - sl.start
        per = np.repeat((o[sl] / N)[:, None], N, axis=1)
        q = np.repeat((p[sl] * (o[sl] if p_height == "wall" else o[sl] / N))[:, None], N, axis=1)
        ones = np.ones(n_w)
        found = minimise_walls(
            o[sl] / t[sl], 0.5 / m[sl], ones, ones, f[sl], per, np.ones((n_w, N)), q, settings, wall_minimum_only=True
        )
        r = np.arange(n_w)
        out["hinge"][sl] = found.hinge_storey
        out["lam"][sl] = found.rocking_load_factor[r, found.hinge_storey - 1]
        out["tau"][sl] = found.tan_alpha_c[r, found.hinge_storey - 1]
        out["lam_s"][sl] = found.sliding_load_factor

    lam, tau = out["lam"], out["tau"]
    ratio = np.arctan(tau) / np.arctan(0.5 / m)
    mech = np.where(f < lam, 2, np.where(ratio >= 1.0 - 1e-9, 1, 0))
    rs = lambda a: a.reshape(shape)  # noqa: E731
    return SweepResult(
        load_factor=rs(np.minimum(lam, f)),
        rocking_load_factor=rs(lam),
        sliding_load_factor=rs(out["lam_s"]),
        tan_alpha_c=rs(tau),
        alpha_c_deg=rs(np.degrees(np.arctan(tau))),
        alpha_ratio=rs(ratio),
        hinge_storey=rs(out["hinge"].astype(int)),
        mechanism=rs(mech.astype(int)),
    )
