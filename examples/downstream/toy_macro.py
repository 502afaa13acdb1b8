"""A deliberately simple macro model: the wall's corner wedge overturning as one rigid block.

The part of the wall beyond a crack that climbs the running bond's stair
(slope ``tan(alpha_b) = v/b = 1/(2m)`` from the base corner) rotates about the
toe under a horizontal load ``lambda`` times its weight; friction along the
crack is ignored, so the wedge only tips. With the toe at ``(L, 0)`` the load
factor is the toe's lever arm over the centroid's height, and the smaller of it,
the whole wall tipping (``L/H``) and the whole wall sliding on a bed joint (``f``)
governs::

    lambda = min((L - x_g) / y_g, L / H, f)

The example project tests it against the paper's Table 7 through the
``xcheck-masonry`` pytest plugin. It is far from the paper's model: Sets 11 and
12 (m = 1/3) are known gaps.
"""

from __future__ import annotations

import numpy as np


def wedge(t: float, m: float) -> np.ndarray:
    """Corners of the overturning wedge of a wall of unit height and length ``1/t`` (counter-clockwise)."""
    length, slope = 1.0 / t, 1.0 / (2.0 * m)
    if slope <= length:  # the crack reaches the top inside the wall
        return np.array([[length, 0.0], [length, 1.0], [length - slope, 1.0]])
    y_exit = 1.0 - length / slope  # the crack leaves through the far side
    return np.array([[length, 0.0], [length, 1.0], [0.0, 1.0], [0.0, y_exit]])


def centroid(poly: np.ndarray) -> tuple[float, float]:
    """Centroid of a simple polygon (shoelace formula)."""
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2.0
    return float(((x + xn) * cross).sum() / (6.0 * area)), float(((y + yn) * cross).sum() / (6.0 * area))


def load_factor(t: float, m: float, f: float) -> float:
    """The toy's load factor of a wall of shape ratio ``t = H/L``, unit shape ``m = b/l`` and friction ``f``."""
    x_g, y_g = centroid(wedge(t, m))
    return min((1.0 / t - x_g) / y_g, 1.0 / t, f)
