"""Failure modes: the micro mechanism read in the macro model's terms.

The macro model's frame has the hinge O at ``x = 0`` on the base of the hinge
storey and the horizontal load pushing towards ``-x``: the moving macro-block
lies left of a crack rising to the right. A micro mechanism for the live load
in ``+x`` is mirrored (``x -> L - x``) into that frame.

From the block velocities of the mechanism:

* a block *moves* when the largest speed of its corners exceeds
  ``MOVING_TOL`` times the largest block speed of the wall;
* the *hinge storey* is the storey of the lowest moving block (1 = top), as
  the macro hinge at the base of storey ``k`` moves storeys ``1..k``;
* the *crack* is, course by course, the far edge of the moving blocks counted
  from the hinge side, over the courses where the wall does not move over its
  whole length; a straight line fitted to those edges gives the stepped crack's
  slope (the macro ``tan(alpha_c*)`` of Eq. 9), and the line from the hinge
  to the edge in the highest such course the conventional ``tan(alpha_c)``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: A block moves when its speed exceeds this fraction of the largest block speed.
MOVING_TOL = 1e-3


class Blocks(Protocol):
    """What the extraction needs of a block wall (``micro.BlockWall`` has it)."""

    @property
    def length(self) -> float: ...
    @property
    def block_height(self) -> float: ...
    @property
    def x0(self) -> FloatArray: ...
    @property
    def x1(self) -> FloatArray: ...
    @property
    def y0(self) -> FloatArray: ...
    @property
    def y1(self) -> FloatArray: ...
    @property
    def course(self) -> NDArray[np.int64]: ...
    @property
    def storey(self) -> NDArray[np.int64]: ...


@dataclass(frozen=True)
class FailureMode:
    """A micro collapse mechanism summarised like the macro one.

    Attributes:
        moving_blocks: number of moving blocks.
        moving_fraction: moving blocks / all blocks.
        hinge_storey: storey of the lowest moving block (1 = top).
        crack_courses: courses in which the crack was located.
        crack_slope: slope of the line fitted to the crack edges (``tan`` of
            the angle from the vertical), NaN with fewer than two courses.
        crack_angle_deg: ``atan(crack_slope)`` in degrees.
        conventional_angle_deg: angle from the vertical of the line from the
            hinge to the crack edge in its highest course (macro ``alpha_c``).
        whole_length_courses: courses moving over the whole wall length
            (above the crack's exit through the side).
        rotation: mean ``|omega|`` of the moving blocks over their mean speed
            per unit height; near 0 for a sliding mechanism.
        direction: live load direction the mechanism belongs to.
    """

    moving_blocks: int
    moving_fraction: float
    hinge_storey: int
    crack_courses: int
    crack_slope: float
    crack_angle_deg: float
    conventional_angle_deg: float
    whole_length_courses: int
    rotation: float
    direction: str

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (non-finite numbers as ``None``)."""
        return {k: None if isinstance(v, float) and not math.isfinite(v) else v for k, v in asdict(self).items()}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> FailureMode:
        """The failure mode :meth:`to_dict` wrote (``None`` read back as NaN)."""
        values: dict[str, Any] = {f.name: math.nan if d[f.name] is None else d[f.name] for f in fields(cls)}
        return cls(**values)


def block_speeds(blocks: Blocks, velocities: FloatArray) -> FloatArray:
    """Largest corner speed of every block for rigid velocities ``(u, v, omega)``.

    ``velocities`` are in the LP's scaled units (lengths in block heights).
    """
    s = blocks.block_height
    xc, yc = 0.5 * (blocks.x0 + blocks.x1) / s, 0.5 * (blocks.y0 + blocks.y1) / s
    u, v, w = velocities[:, 0], velocities[:, 1], velocities[:, 2]
    best = np.zeros(u.shape)
    for x in (blocks.x0 / s, blocks.x1 / s):
        for y in (blocks.y0 / s, blocks.y1 / s):
            best = np.maximum(best, np.hypot(u - w * (y - yc), v + w * (x - xc)))
    return best


def failure_mode(blocks: Blocks, velocities: FloatArray, direction: str) -> FailureMode:
    """Summarise a micro mechanism (see the module docstring).

    Args:
        blocks: the block wall.
        velocities: ``(n_blocks, 3)`` block velocities of the mechanism.
        direction: ``"+x"`` or ``"-x"``, the live load direction.

    Raises:
        ValueError: a bad direction, a velocity array of the wrong shape, or a
            mechanism in which nothing moves.
    """
    if direction not in ("+x", "-x"):
        raise ValueError(f"direction must be '+x' or '-x', got {direction!r}")
    vel = np.asarray(velocities, dtype=float)
    if vel.shape != (blocks.x0.size, 3):
        raise ValueError(f"velocities must have shape ({blocks.x0.size}, 3), got {vel.shape}")
    speed = block_speeds(blocks, vel)
    top = float(speed.max(initial=0.0))
    if not top > 0.0:
        raise ValueError("mechanism: no block moves")
    moving = speed > MOVING_TOL * top
    L = blocks.length
    # into the macro frame: hinge side at x = 0
    far = L - blocks.x0 if direction == "+x" else blocks.x1  # far edge of each block from the hinge side
    courses = np.unique(blocks.course[moving])
    lowest = int(courses.min())
    hinge_storey = int(blocks.storey[moving][blocks.course[moving] == lowest][0])
    y_base = float(blocks.y0[blocks.course == lowest].min())
    ys, xs, whole = [], [], 0
    tol = 1e-9 * L
    for c in courses:
        in_c = blocks.course == c
        edge = float(far[in_c & moving].max())
        if np.all(moving[in_c]) and edge >= L - tol:
            whole += 1
            continue
        ys.append(0.5 * float(blocks.y0[in_c][0] + blocks.y1[in_c][0]) - y_base)
        xs.append(edge)
    y, x = np.asarray(ys), np.asarray(xs)
    slope = float(np.polyfit(y, x, 1)[0]) if y.size >= 2 and np.ptp(y) > 0 else float("nan")
    if y.size:
        k = int(np.argmax(y))
        conventional = math.degrees(math.atan2(x[k], y[k] + 0.5 * blocks.block_height))
    else:
        conventional = float("nan")
    mv = vel[moving]
    mean_speed = float(np.mean(np.hypot(mv[:, 0], mv[:, 1])))
    rotation = float(np.mean(np.abs(mv[:, 2]))) / mean_speed if mean_speed > 0 else float("inf")
    return FailureMode(
        moving_blocks=int(moving.sum()),
        moving_fraction=float(moving.mean()),
        hinge_storey=hinge_storey,
        crack_courses=int(y.size),
        crack_slope=slope,
        crack_angle_deg=math.degrees(math.atan(slope)) if math.isfinite(slope) else float("nan"),
        conventional_angle_deg=conventional,
        whole_length_courses=whole,
        rotation=rotation,
        direction=direction,
    )
