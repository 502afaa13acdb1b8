"""Drawing of a wall and its collapse mechanism (matplotlib, Agg back end)."""

from __future__ import annotations

import io
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.files import write_whole
from micro.geometry import BlockWall
from micro.limit_result import LimitResult

#: The largest virtual displacement drawn, as a fraction of the wall height (when no amplification is given).
LARGEST_DISPLACEMENT = 0.2


def draw_mechanism(
    ax: Any,
    wall: BlockWall,
    velocities: NDArray[np.float64],
    *,
    amplification: float | None = None,
    fig: Any = None,
    direction: str | None = None,
    floors: Sequence[float] = (),
    hinge: float | None = None,
    hinge_label: str = "hinge",
) -> float:
    """Draw the wall and a mechanism on matplotlib axes, in block heights.

    Each block is drawn displaced by its velocity ``(u, v, omega)`` (a
    virtual displacement, amplified so that the largest one is
    :data:`LARGEST_DISPLACEMENT` of the wall height, unless ``amplification``
    is given) and coloured by the magnitude of its translational velocity relative to the
    fastest block's (0 to 1); the
    undeformed outline is drawn in grey. The x label gives the amplification;
    when ``direction`` is given, an arrow shows the live load. Floor levels
    are drawn as dashed lines across the wall, each storey named beside it
    (1 = top), and a hinge as a marker at the toe the wall rotates about (the
    side the load pushes towards; both toes without a direction), labelled
    for a legend.

    Args:
        ax: matplotlib axes.
        wall: the wall.
        velocities: ``(n_blocks, 3)`` block velocities in the LP's scaled
            units (lengths in block heights).
        amplification: displacement scale; ``None`` chooses one.
        fig: when given, a colour bar is added to it.
        direction: the live load's direction, ``"+x"`` or ``"-x"`` (``None``: no arrow).
        floors: heights above the base of the floors between storeys, in the
            wall's length unit (``()``: none drawn).
        hinge: height above the base of a hinge to mark, in the wall's length
            unit (``None``: none).
        hinge_label: the hinge marker's legend label.

    Returns:
        The amplification used.
    """
    from matplotlib.collections import PolyCollection

    vel = np.asarray(velocities)
    u, v, w = vel[:, 0], vel[:, 1], vel[:, 2]  # block heights (the LP's scaled units)
    ls = wall.block_height
    xc, yc = wall.xc / ls, wall.yc / ls
    corners_x = np.stack([wall.x0, wall.x1, wall.x1, wall.x0], axis=1) / ls
    corners_y = np.stack([wall.y0, wall.y0, wall.y1, wall.y1], axis=1) / ls
    rx, ry = corners_x - xc[:, None], corners_y - yc[:, None]
    # largest corner displacement of the rigid motion
    dmax = float(np.max(np.hypot(u[:, None] - w[:, None] * ry, v[:, None] + w[:, None] * rx), initial=0.0))
    height = wall.height / ls
    if amplification is None:
        amplification = LARGEST_DISPLACEMENT * height / dmax if dmax > 0 else 1.0
    # finite rigid rotation of each block by amplification * omega
    th = amplification * w
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    X = xc[:, None] + amplification * u[:, None] + c * rx - s * ry
    Y = yc[:, None] + amplification * v[:, None] + s * rx + c * ry
    outline = [np.column_stack(q) for q in zip(corners_x, corners_y, strict=True)]
    ax.add_collection(PolyCollection(outline, facecolors="none", edgecolors="0.8", linewidths=0.3))
    moved = [np.column_stack(q) for q in zip(X, Y, strict=True)]
    speed = np.hypot(u, v)
    top = float(np.max(speed, initial=0.0))
    relative = speed / top if top > 0 else speed
    pc = PolyCollection(moved, array=relative, cmap="viridis", edgecolors="k", linewidths=0.2)
    pc.set_clim(0.0, 1.0)
    ax.add_collection(pc)
    if fig is not None:
        fig.colorbar(pc, ax=ax, label="block speed |(u, v)| / speed of the fastest block", shrink=0.8)
    if direction is not None:
        _load_arrow(ax, wall.length / ls, height, direction)
    if floors:
        _floors(ax, wall.length / ls, height, [f / ls for f in floors])
    if hinge is not None:
        toes = {"+x": [wall.length / ls], "-x": [0.0]}.get(direction or "", [0.0, wall.length / ls])
        ax.plot(toes, [hinge / ls] * len(toes), ls="none", marker="o", ms=9, mfc="none", mec="red", mew=2.0,
                zorder=5, label=hinge_label)  # fmt: skip
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel(f"x [block heights]; displacements × {amplification:.3g} (largest: {amplification * dmax:.2g})")
    ax.set_ylabel("y [block heights]")
    return float(amplification)


def _load_arrow(ax: Any, length: float, height: float, direction: str) -> None:
    """A horizontal arrow beside the wall, at two thirds of its height, pointing the live load's way
    (``λ W``: λ times the weight of each block)."""
    span = 0.18 * max(length, height)
    y = 0.66 * height
    tail, head = (-1.15 * span, -0.15 * span) if direction == "+x" else (length + 1.15 * span, length + 0.15 * span)
    ax.annotate(
        "", xy=(head, y), xytext=(tail, y),
        arrowprops={"arrowstyle": "-|>", "color": "C3", "lw": 2.0, "mutation_scale": 16},
    )  # fmt: skip
    ax.text((tail + head) / 2, y + 0.12 * span, "λ W", ha="center", va="bottom", fontsize=9, color="C3")
    ax.update_datalim([(tail, y), (head, y)])


def _floors(ax: Any, length: float, height: float, floors: list[float]) -> None:
    """Dashed lines across the wall at the floor levels (block heights), and on a second y axis at the right
    each storey's number at its mid-height (1 = top), clear of the displaced blocks."""
    from matplotlib import patheffects

    halo = [patheffects.withStroke(linewidth=2.2, foreground="white")]  # readable over dark and light blocks
    for i, y in enumerate(sorted(floors)):
        ax.plot([0.0, length], [y, y], ls="--", color="0.1", lw=1.0, zorder=4, path_effects=halo,
                label="floor" if i == 0 else None)  # fmt: skip
    levels = [0.0, *sorted(floors), height]
    n = len(levels) - 1
    storeys = ax.secondary_yaxis("right")
    storeys.set_yticks([(levels[k] + levels[k + 1]) / 2 for k in range(n)], [f"storey {n - k}" for k in range(n)])
    storeys.tick_params(length=0, labelsize=7, labelrotation=90)


def plot_velocities(
    wall: BlockWall,
    velocities: NDArray[np.float64],
    path: str | Path,
    *,
    amplification: float | None = None,
    title: str = "",
    direction: str | None = None,
    floors: Sequence[float] = (),
    hinge: float | None = None,
    hinge_label: str = "hinge",
) -> Path:
    """Draw the wall and a mechanism (see :func:`draw_mechanism`) to an image file.

    Args:
        wall: the wall.
        velocities: ``(n_blocks, 3)`` block velocities (scaled units).
        path: output file (``.png``, ``.pdf``, ``.svg``).
        amplification: displacement scale; ``None`` chooses one.
        title: figure title.
        direction: the live load's direction (an arrow), or ``None``.
        floors, hinge, hinge_label: floor levels and a hinge to mark (:func:`draw_mechanism`); a legend
            names them.

    Returns:
        The written path.
    """
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    aspect = wall.height / wall.length
    fig, ax = plt.subplots(figsize=(9, max(3.0, min(9.0, 9 * aspect + 1.5))), dpi=110)
    draw_mechanism(ax, wall, velocities, amplification=amplification, fig=fig, direction=direction, floors=floors,
                   hinge=hinge, hinge_label=hinge_label)  # fmt: skip
    marks = len(ax.get_legend_handles_labels()[0])
    if marks:  # one row over the axes, the title above it
        ax.legend(fontsize=8, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=marks, frameon=False)
    _fit_title(fig, ax, title, pad=24 if marks else 6)
    try:
        return save_figure(fig, path, bbox_inches="tight")
    finally:
        plt.close(fig)


def save_figure(fig: Any, path: str | Path, **savefig: Any) -> Path:
    """Write ``fig`` to ``path`` whole or not at all, in the format its name ends with.

    The image is rendered in memory, written to a temporary file beside
    ``path`` and renamed over it: a disk that fills up (or any error) leaves
    no file, where ``savefig`` left a 0-byte or cut one; a name that is only an
    extension (``.png``) is written as it is (``savefig`` made it
    ``.png.png``). A symbolic link is written through, as ``open()`` writes
    it: the file it points to is replaced (beside it, by the same rename)
    and the link stays, where a rename over the link replaced the link.

    Args:
        fig: a matplotlib figure.
        path: the image file; its extension (``.png``, ``.pdf``, ``.svg``)
            is the format, matplotlib's default format where it has none.
        **savefig: passed on to ``fig.savefig`` (``dpi``, ``bbox_inches``).

    Returns:
        The written path.
    """
    out = Path(path)
    name = out.name
    fmt = name.rsplit(".", 1)[1].lower() if "." in name else None
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, **savefig)
    return write_whole(out, buf.getvalue())


def _fit_title(fig: Any, ax: Any, title: str, pad: float) -> None:
    """``title`` over ``ax``, broken into lines at its commas and semicolons where it is wider than the axes:
    a title one line wide ran under the colour bar beside the axes (``..., 54 blocks`` hidden)."""
    text = ax.set_title(title, pad=pad)
    renderer = fig.canvas.get_renderer()
    room = ax.get_window_extent(renderer).width

    def fits(candidate: str) -> bool:
        text.set_text(candidate)
        return bool(text.get_window_extent(renderer).width <= room)

    if fits(title):
        return
    pieces = re.split(r"(?<=[,;]) ", title)
    lines: list[str] = []
    for piece in pieces:
        if lines and fits(f"{lines[-1]} {piece}"):
            lines[-1] = f"{lines[-1]} {piece}"
        else:
            lines.append(piece)
    text.set_text("\n".join(lines))


def plot_mechanism(
    wall: BlockWall,
    result: LimitResult,
    path: str | Path,
    *,
    amplification: float | None = None,
    title: str | None = None,
    floors: Sequence[float] = (),
    hinge: float | None = None,
    hinge_label: str = "hinge",
) -> Path:
    """Draw the wall and the collapse mechanism of an associative result to an image file.

    Args:
        wall: the wall.
        result: its :class:`LimitResult` (optimal, with velocities).
        path: output file (``.png``, ``.pdf``, ``.svg``).
        amplification: displacement scale; ``None`` chooses one.
        title: figure title; default: load factor, direction, friction law (associative), blocks and back end.
        floors, hinge, hinge_label: floor levels and a hinge to mark (:func:`draw_mechanism`).

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
        title=title
        or f"lambda = {result.load_factor:.4f} ({result.direction}), associative friction, {result.blocks} blocks, "
        f"{result.solver}",
        direction=result.direction or None,
        floors=floors,
        hinge=hinge,
        hinge_label=hinge_label,
    )
