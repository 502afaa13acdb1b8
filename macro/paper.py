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
``comparison.domain.wall.WallSpec.from_paper``, so that both read the parameters alike.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

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
    x = checks.in_range(name, value, 0.0, 1.0)  # the paper's range first
    return checks.in_range(
        name, x, 1.0 / checks.MAX_RATIO, 1.0, f"a block at most {checks.MAX_RATIO:g} times as long as high"
    )


def _rows(name: str, value: object) -> int:
    o = checks.positive_int(name, value)
    if o > checks.MAX_RATIO:
        raise ValueError(checks.AT_MOST.format(name=name, hi=checks.exact(checks.MAX_RATIO), value=value)
                         + ": rows in all")
    return o


def _first_bad(bad: NDArray[np.bool_], message: Callable[[int], str], entry: bool = True) -> None:
    """Raise ``message(i)`` for the first ``i`` where ``bad`` holds, followed by ``(entry i)`` when ``entry``."""
    index = np.flatnonzero(bad)
    if index.size:
        i = int(index[0])
        raise ValueError(f"{message(i)} (entry {i})" if entry else message(i))


def _checked(
    name: str, value: ArrayLike, check: Callable[[str, object], float], ok: Callable[[FloatArray], NDArray[np.bool_]]
) -> FloatArray:
    """``value`` as a flat float array, every entry passing ``check`` (vectorised as ``ok``).

    A scalar gets exactly the message of ``check``; an array entry the same
    message followed by ``(entry i)``.
    """
    a = _array(name, value)
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


def _array(name: str, value: object) -> NDArray[Any]:
    """``value`` as an array; a ragged nesting of lists names the parameter (numpy's message does not)."""
    try:
        return np.asarray(value)
    except (ValueError, TypeError):
        raise ValueError(f"{name} must be a number or an array of numbers, got {value!r}") from None


def broadcast_shape(**params: ArrayLike) -> tuple[int, ...]:
    """The shape the paper's parameters broadcast to, computed without building the walls.

    Raises:
        ValueError: a ragged parameter, or shapes that do not broadcast together, naming the parameters
            and their shapes (numpy's message numbers them ``arg 0``, ``arg 1``).
    """
    shapes = {name: np.shape(_array(name, value)) for name, value in params.items()}
    try:
        return tuple(np.broadcast_shapes(*shapes.values()))
    except ValueError:
        given = ", ".join(f"{name} {shape}" for name, shape in shapes.items() if shape)
        raise ValueError(f"{', '.join(shapes)} must broadcast to one shape, got the shapes {given}") from None


def _positive(a: FloatArray) -> NDArray[np.bool_]:
    return np.isfinite(a) & (a > 0)


def _paper_bounds(
    t: FloatArray,
    m: FloatArray,
    o: FloatArray,
    p: FloatArray,
    p_rows: FloatArray,
    shown: Callable[[str, int], object],
    *,
    entry: bool,
) -> None:
    """The physical bounds of :mod:`macro.checks` in the paper's terms (entries broadcast and flat).

    A wall at least one block long and at most ``MAX_RATIO`` block heights,
    ``o/MAX_RATIO <= t <= o m``; a floor load of at most ``MAX_RATIO`` row
    weights, ``p p_rows <= MAX_RATIO`` (``p_rows``: the rows of the height
    ``p`` refers to). ``shown(name, i)`` is the value to quote; ``entry``:
    messages end with ``(entry i)``.
    """
    R = checks.MAX_RATIO
    lo = o / R
    bad_t = (t > o * m * (1.0 + checks.LENGTH_SLACK)) | (t < lo * (1.0 - checks.LENGTH_SLACK))
    _first_bad(
        bad_t,
        lambda i: (
            checks.IN_CLOSED_RANGE.format(name="t", lo=checks.exact(lo[i]), hi=checks.exact(o[i] * m[i]),
                                          value=shown("t", i))
            + f": a wall at least one block long (o/t >= 1/m) and at most {R:g} block heights (o/t <= {R:g})"
        ),
        entry,
    )
    with np.errstate(over="ignore"):  # p near the double range: an infinite product is over the bound too
        too_heavy = p * p_rows > R
    _first_bad(
        too_heavy,
        lambda i: (
            checks.AT_MOST.format(name="p", hi=checks.exact(R / p_rows[i]), value=shown("p", i))
            + f": a floor load of at most {R:g} times the weight of one row"
        ),
        entry,
    )


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
    broadcast_shape(t=t, m=m, rows=rows, f=f, p=p)
    t_ = _checked("t", t, checks.positive, _positive)
    m_ = _checked("m", m, _m, lambda a: (a > 1.0 / checks.MAX_RATIO) & (a <= 1.0))
    o = _checked("rows", rows, _rows, lambda a: _positive(a) & (a == np.round(a)) & (a <= checks.MAX_RATIO))
    _first_bad(np.mod(o, n) != 0, lambda i: checks.UNEQUAL_STOREYS.format(rows=int(o[i]), storeys=n), np.ndim(rows) > 0)
    f_ = _checked("f", f, checks.friction, lambda a: (a > checks.MIN_FRICTION) & (a <= checks.MAX_FRICTION))
    p_ = _checked("p", p, checks.non_negative, lambda a: np.isfinite(a) & (a >= 0))
    checks.choice("p_height", p_height, P_HEIGHTS)
    given = ((t_, t), (m_, m), (o, rows), (f_, f), (p_, p))
    t_, m_, o, f_, p_ = np.broadcast_arrays(*(x.reshape(np.shape(v)) for x, v in given))
    shape = t_.shape
    t_, m_, o, f_, p_ = (np.ascontiguousarray(x).ravel() for x in (t_, m_, o, f_, p_))
    scalar = not shape
    flat = {"t": t_, "p": p_}
    inputs = {"t": t, "p": p}
    _paper_bounds(
        t_, m_, o, p_, o if p_height == "wall" else o / n,
        lambda name, i: inputs[name] if scalar else float(flat[name][i]),
        entry=not scalar,
    )  # fmt: skip
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
