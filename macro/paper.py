"""The paper's Table 4 parameters as dimensional walls: the one normalisation.

Lengths are measured in block heights and forces in unit-weight units, which
does not change the load factor:

* block height ``b = 1``, every storey as thick as a block (the paper's unit
  block is ``l x b x b``), unit weight 1;
* ``o = H/b`` rows in all, split equally over the ``N`` storeys: ``H = o``;
* ``t = H/L``: wall length ``L = o/t``;
* ``m = b/l``: block length ``l = 1/m``, overlap ``v = l/2``;
* ``p``: the floor load per unit length on every floor over the wall's
  self-weight per unit length, ``q = p H`` (``p_height="wall"``, the default);
  the OCR prints ``q/(H b nu)``, and reading ``H`` as the storey height
  (``p_height="storey"``) gives ``q = p H/N``.

:func:`paper_walls` is used by :func:`macro.sweep` and by
``comparison.wall.WallSpec.from_paper``, so that both read the parameters alike.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from macro import checks

FloatArray = NDArray[np.float64]

#: Block height of a wall built from the paper's parameters (the unit of length).
BLOCK_HEIGHT = 1.0
#: Readings of ``p`` (see the module docstring).
P_HEIGHTS = ("wall", "storey")


@dataclass(frozen=True)
class PaperWalls:
    """Walls built from Table 4's parameters, flattened (``shape`` is the broadcast shape).

    Every wall has block height, storey thickness and unit weight 1 and the
    same number of storeys.

    Attributes:
        shape: broadcast shape of the parameters.
        storeys: number of storeys ``N``.
        length: wall length ``L = o/t``.
        block_length: block length ``l = 1/m``.
        overlap: ``v = l/2``.
        rows_per_storey: ``o/N``.
        overload: ``q`` on every floor.
        friction: ``f``.
    """

    shape: tuple[int, ...]
    storeys: int
    length: FloatArray
    block_length: FloatArray
    overlap: FloatArray
    rows_per_storey: FloatArray
    overload: FloatArray
    friction: FloatArray

    @property
    def size(self) -> int:
        """Number of walls."""
        return int(self.length.size)


def _m(name: str, value: object) -> float:
    return checks.in_range(name, value, 0.0, 1.0)


def _checked(
    name: str, value: ArrayLike, check: Callable[[str, object], float], ok: Callable[[FloatArray], NDArray[np.bool_]]
) -> FloatArray:
    """``value`` as a flat float array, every entry passing ``check`` (vectorised as ``ok``).

    A scalar gets exactly the message of ``check``; an array entry the same
    message followed by ``(entry i)``.
    """
    a = np.asarray(value)
    if a.ndim == 0:
        return np.array([check(name, a.item() if isinstance(value, (np.ndarray, np.generic)) else value)], dtype=float)
    flat = a.ravel()
    if a.dtype.kind not in "iuf":  # bools, strings, objects: the first entry the check refuses
        for i, v in enumerate(flat):
            try:
                check(name, v.item() if isinstance(v, np.generic) else v)
            except ValueError as exc:
                raise ValueError(f"{exc} (entry {i})") from None
    x = flat.astype(float)
    bad = np.flatnonzero(~ok(x))
    if bad.size:
        i = int(bad[0])
        try:
            check(name, flat[i].item())
        except ValueError as exc:
            raise ValueError(f"{exc} (entry {i})") from None
    return x


def _positive(a: FloatArray) -> NDArray[np.bool_]:
    return np.isfinite(a) & (a > 0)


def paper_walls(
    t: ArrayLike,
    m: ArrayLike,
    rows: ArrayLike,
    f: ArrayLike,
    p: ArrayLike = 0.0,
    storeys: int = 1,
    p_height: Literal["wall", "storey"] | str = "wall",
) -> PaperWalls:
    """Validate Table 4's parameters and build the dimensional walls.

    Args:
        t: wall shape ratio ``H/L``.
        m: unit shape ratio ``b/l``, in (0, 1].
        rows: rows ``o`` in all, split equally over the storeys.
        f: friction coefficient.
        p: overloading ratio (the same on every floor).
        storeys: number of storeys ``N`` of every wall.
        p_height: ``"wall"`` or ``"storey"``, the reading of ``p``.

    Raises:
        ValueError: naming the first invalid parameter (messages of
            :mod:`macro.checks`).
    """
    n = checks.positive_int("storeys", storeys)
    t_ = _checked("t", t, checks.positive, _positive)
    m_ = _checked("m", m, _m, lambda a: _positive(a) & (a <= 1.0))
    o = _checked("rows", rows, checks.positive_int, lambda a: _positive(a) & (a == np.round(a)))
    split = np.flatnonzero(np.mod(o, n) != 0)
    if split.size:
        i = int(split[0])
        message = checks.UNEQUAL_STOREYS.format(rows=int(o[i]), storeys=n)
        raise ValueError(message if np.ndim(rows) == 0 else f"{message} (entry {i})")
    f_ = _checked("f", f, checks.positive, _positive)
    p_ = _checked("p", p, checks.non_negative, lambda a: np.isfinite(a) & (a >= 0))
    checks.choice("p_height", p_height, P_HEIGHTS)
    given = ((t_, t), (m_, m), (o, rows), (f_, f), (p_, p))
    t_, m_, o, f_, p_ = np.broadcast_arrays(*(x.reshape(np.shape(v)) for x, v in given))
    shape = t_.shape
    t_, m_, o, f_, p_ = (np.ascontiguousarray(x).ravel() for x in (t_, m_, o, f_, p_))
    per = o / n
    block_length = BLOCK_HEIGHT / m_
    return PaperWalls(
        shape=shape,
        storeys=n,
        length=o * BLOCK_HEIGHT / t_,
        block_length=block_length,
        overlap=0.5 * block_length,
        rows_per_storey=per,
        overload=p_ * (o if p_height == "wall" else per) * BLOCK_HEIGHT,
        friction=f_,
    )
