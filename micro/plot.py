"""Drawing of a wall and its collapse mechanism (matplotlib, Agg back end)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall
from micro.results import LimitResult


def draw_mechanism(
    ax: Any,
    wall: BlockWall,
    velocities: NDArray[np.float64],
    *,
    amplification: float | None = None,
    fig: Any = None,
) -> float:
    """Draw the wall and a mechanism on matplotlib axes.

    Each block is drawn displaced by its velocity ``(u, v, omega)`` (a
    virtual displacement, amplified so that the largest one is about a fifth
    of the wall height) and coloured by the magnitude of its translational
    velocity; the undeformed outline is drawn in grey.

    Args:
        ax: matplotlib axes.
        wall: the wall.
        velocities: ``(n_blocks, 3)`` block velocities in the LP's scaled
            units (lengths in block heights).
        amplification: displacement scale; ``None`` chooses one.
        fig: when given, a colour bar is added to it.

    Returns:
        The amplification used.
    """
    from matplotlib.collections import PolyCollection

    ls = wall.block_height
    vel = np.asarray(velocities)
    u, v, w = vel[:, 0] * ls, vel[:, 1] * ls, vel[:, 2]  # lengths back to wall units
    xc, yc = wall.xc, wall.yc
    corners_x = np.stack([wall.x0, wall.x1, wall.x1, wall.x0], axis=1)
    corners_y = np.stack([wall.y0, wall.y0, wall.y1, wall.y1], axis=1)
    rx, ry = corners_x - xc[:, None], corners_y - yc[:, None]
    # largest corner displacement of the rigid motion
    dx = u[:, None] - w[:, None] * ry
    dy = v[:, None] + w[:, None] * rx
    dmax = float(np.max(np.hypot(dx, dy), initial=0.0))
    if amplification is None:
        amplification = 0.2 * wall.height / dmax if dmax > 0 else 1.0
    # finite rigid rotation of each block by amplification * omega
    th = amplification * w
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    X = xc[:, None] + amplification * u[:, None] + c * rx - s * ry
    Y = yc[:, None] + amplification * v[:, None] + s * rx + c * ry
    speed = np.hypot(u, v)
    ax.add_collection(
        PolyCollection(np.stack([corners_x, corners_y], axis=2), facecolors="none", edgecolors="0.8", linewidths=0.3)
    )
    pc = PolyCollection(np.stack([X, Y], axis=2), array=speed, cmap="viridis", edgecolors="k", linewidths=0.2)
    ax.add_collection(pc)
    if fig is not None:
        fig.colorbar(pc, ax=ax, label="|velocity| (live load does unit work)")
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    return float(amplification)


def plot_velocities(
    wall: BlockWall,
    velocities: NDArray[np.float64],
    path: str | Path,
    *,
    amplification: float | None = None,
    title: str = "",
) -> Path:
    """Draw the wall and a mechanism (see :func:`draw_mechanism`) to an image file.

    Args:
        wall: the wall.
        velocities: ``(n_blocks, 3)`` block velocities (scaled units).
        path: output file (``.png``, ``.pdf``, ``.svg``).
        amplification: displacement scale; ``None`` chooses one.
        title: figure title.

    Returns:
        The written path.
    """
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    aspect = wall.height / wall.length
    fig, ax = plt.subplots(figsize=(9, max(3.0, min(9.0, 9 * aspect + 1.5))), dpi=110)
    draw_mechanism(ax, wall, velocities, amplification=amplification, fig=fig)
    ax.set_title(title)
    out = Path(path)
    fig.savefig(out, bbox_inches="tight")
    plt.close(fig)
    return out


def plot_mechanism(
    wall: BlockWall,
    result: LimitResult,
    path: str | Path,
    *,
    amplification: float | None = None,
    title: str | None = None,
) -> Path:
    """Draw the wall and the collapse mechanism of an associative result to an image file.

    Args:
        wall: the wall.
        result: its :class:`LimitResult` (optimal, with velocities).
        path: output file (``.png``, ``.pdf``, ``.svg``).
        amplification: displacement scale; ``None`` chooses one.
        title: figure title; default: load factor, direction and back end.

    Returns:
        The written path.

    Raises:
        ValueError: the result has no mechanism (not optimal).
    """
    if result.velocities is None:
        raise ValueError(f"no mechanism to draw: the solve ended with status {result.status}")
    return plot_velocities(
        wall,
        result.velocities,
        path,
        amplification=amplification,
        title=title or f"lambda = {result.load_factor:.4f} ({result.direction}), {result.blocks} blocks, {result.solver}",
    )
