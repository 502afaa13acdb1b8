"""Running-bond block assemblage of a dry-joint wall (2-D, in-plane).

The builder :func:`build_wall` lays the wall out course by course from the
base up and lists every interface (bed-joint overlap, head joint, base) by its
two end points, which is exact for rigid blocks in 2-D. Everything is done
with whole-array numpy operations: the layout of each of the two course types
is computed once (in units of half a block length, so that it is exact) and
tiled over the courses.

Conventions
-----------
* ``x`` runs along the wall from its left end, ``y`` up from the base.
* Storeys are numbered as in the paper: storey 1 is the TOP storey. ``rows``,
  ``thickness`` and ``overload`` are given from the top storey down.
* A contact joins block ``a`` (below, or left; ``-1`` is the ground) to block
  ``b`` (above, or right). Its unit normal ``n`` points from ``a`` into ``b``;
  its tangent is ``t = (n_y, -n_x)`` (``n`` turned 90 degrees clockwise), so a
  bed joint has ``t = (1, 0)`` and a head joint ``t = (0, -1)``.
* Loads are given per block as ``(F_x, F_y, M)`` about the block centroid
  (``M`` counter-clockwise): ``dead`` is self weight plus floor overloads;
  ``live`` is the horizontal load in ``+x`` per unit load factor (the block's
  weight at its centroid plus the overload's mass at the floor level).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Contact kinds (values of :attr:`BlockWall.contact_kind`).
BASE, BED, HEAD = 0, 1, 2
CONTACT_KIND_NAMES = ("base", "bed", "head")

#: Rough memory footprint per block of building and solving the LP (bytes).
#: Measured: peak resident memory ~245 MB solving the 7,575-block wall with
#: Clarabel (~32 kB per block, ~100 MB of it interpreter and libraries);
#: doubled to leave room for cvxpy's canonicalisation copies.
BYTES_PER_BLOCK = 60_000


def available_memory_bytes() -> int | None:
    """Memory the process may still use, from ``/proc/meminfo`` (Linux).

    Returns:
        ``MemAvailable`` in bytes, or ``None`` when it cannot be read.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class BlockWall:
    """A running-bond assemblage of rigid blocks (dimensional units).

    Per-block arrays have length ``n_blocks`` (blocks are numbered course by
    course from the base, left to right); per-contact arrays have length
    ``n_contacts``; point arrays have shape ``(n_contacts, 2)`` (the two end
    points of each interface). All arrays are read-only.

    Attributes:
        length: wall length ``L``.
        block_length: unit block length ``l``.
        block_height: block height ``b``.
        rows: courses per storey, storey 1 (top) first.
        thickness: block thickness per storey, storey 1 first.
        overload: floor load per unit length on top of each storey.
        unit_weight: specific weight.
        friction: friction coefficient of bed joints, base and (unless
            frictionless) head joints.
        first_course: ``"full"`` or ``"half"``: how the bottom course starts.
        head_joints: ``"frictional"`` or ``"frictionless"``.
        x0, x1, y0, y1: block extents.
        course: course index of each block (0 = bottom).
        storey: storey of each block (1 = top).
        dead: ``(n_blocks, 3)`` dead load ``(F_x, F_y, M)`` about the centroid.
        live: ``(n_blocks, 3)`` live load per unit load factor, direction ``+x``.
        contact_a, contact_b: the two blocks of each contact (``a = -1``: ground).
        contact_kind: :data:`BASE`, :data:`BED` or :data:`HEAD`.
        normal: ``(n_contacts, 2)`` unit normal from ``a`` into ``b``.
        px, py: ``(n_contacts, 2)`` coordinates of the two end points.
        mu: friction coefficient of each contact.
    """

    length: float
    block_length: float
    block_height: float
    rows: tuple[int, ...]
    thickness: tuple[float, ...]
    overload: tuple[float, ...]
    unit_weight: float
    friction: float
    first_course: str
    head_joints: str
    x0: FloatArray = field(repr=False)
    x1: FloatArray = field(repr=False)
    y0: FloatArray = field(repr=False)
    y1: FloatArray = field(repr=False)
    course: IntArray = field(repr=False)
    storey: IntArray = field(repr=False)
    dead: FloatArray = field(repr=False)
    live: FloatArray = field(repr=False)
    contact_a: IntArray = field(repr=False)
    contact_b: IntArray = field(repr=False)
    contact_kind: IntArray = field(repr=False)
    normal: FloatArray = field(repr=False)
    px: FloatArray = field(repr=False)
    py: FloatArray = field(repr=False)
    mu: FloatArray = field(repr=False)

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            if isinstance(value, np.ndarray):
                object.__setattr__(self, name, _frozen(value))

    # ---------------------------------------------------------------- sizes
    @property
    def n_blocks(self) -> int:
        """Number of blocks."""
        return int(self.x0.shape[0])

    @property
    def n_contacts(self) -> int:
        """Number of interfaces (base, bed-joint overlaps, head joints)."""
        return int(self.contact_a.shape[0])

    @property
    def n_points(self) -> int:
        """Number of contact points (two per interface)."""
        return 2 * self.n_contacts

    @property
    def n_courses(self) -> int:
        """Number of courses (rows) in all."""
        return int(sum(self.rows))

    @property
    def height(self) -> float:
        """Wall height."""
        return self.n_courses * self.block_height

    # ---------------------------------------------------------------- blocks
    @property
    def xc(self) -> FloatArray:
        """Block centroid abscissae."""
        return 0.5 * (self.x0 + self.x1)

    @property
    def yc(self) -> FloatArray:
        """Block centroid ordinates."""
        return 0.5 * (self.y0 + self.y1)

    @property
    def block_lengths(self) -> FloatArray:
        """Length of each block (``l`` or ``l/2``)."""
        return self.x1 - self.x0

    @property
    def total_weight(self) -> float:
        """Total self weight of the blocks (without the overloads)."""
        t = np.asarray(self.thickness)[self.storey - 1]
        return float(self.unit_weight * self.block_height * np.sum(self.block_lengths * t))

    @property
    def total_dead_load(self) -> float:
        """Total vertical dead load: self weight plus floor overloads."""
        return float(-np.sum(self.dead[:, 1]))

    @property
    def reference_weight(self) -> float:
        """Weight of a full block of the thickest storey (the LP's force unit)."""
        return float(self.unit_weight * self.block_length * self.block_height * max(self.thickness))

    @property
    def mirror_symmetric(self) -> bool:
        """True when the wall is its own mirror image about ``x = L/2``.

        Decided from the geometry: every course's joint positions map onto
        themselves under ``x -> L - x`` (loads are symmetric by construction).
        Then the load factor is the same in ``+x`` and ``-x``.
        """
        tol = 1e-9 * self.length
        shift = np.concatenate([self.course, self.course]) * 4.0 * self.length
        a = np.sort(np.concatenate([self.x0, self.x1]) + shift)
        m = np.sort(np.concatenate([self.length - self.x1, self.length - self.x0]) + shift)
        return bool(a.shape == m.shape and np.all(np.abs(a - m) <= tol))

    def describe(self) -> str:
        """One-line summary."""
        return (
            f"{self.n_blocks} blocks, {self.n_contacts} contacts in {self.n_courses} courses "
            f"(L={self.length:g}, l={self.block_length:g}, b={self.block_height:g}, "
            f"first course {self.first_course}, head joints {self.head_joints})"
        )


# ---------------------------------------------------------------- validation
def _number(name: str, value: object, *, positive: bool = True) -> float:
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {value!r}")
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x) or (x <= 0.0 if positive else x < 0.0):
        kind = "a positive number" if positive else "zero or a positive number"
        raise ValueError(f"{name} must be {kind}, got {value!r}")
    return x


def _per_storey(name: str, values: object, n: int | None, *, positive: bool) -> tuple[float, ...]:
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ValueError(f"{name} must be a tuple with one value per storey (storey 1 = top), got {values!r}")
    vals = tuple(values)  # type: ignore[arg-type]
    if n is not None and len(vals) != n:
        raise ValueError(f"{name} must have one value per storey: got {len(vals)} values for {n} storeys")
    return tuple(_number(f"{name}[{i}]", v, positive=positive) for i, v in enumerate(vals))


#: Physical bounds, the values of ``macro.checks`` (``micro`` may not import
#: ``macro``; a parity test holds them together). Dimensional values lie in
#: (MIN_MAGNITUDE, MAX_MAGNITUDE]; lengths are at most MAX_RATIO block heights
#: (a thickness and a block length at least 1/MAX_RATIO of one); a floor load
#: is at most MAX_RATIO row weights; the friction coefficient lies in
#: (MIN_FRICTION, MAX_FRICTION]. Inside them every LP coefficient (lever arms
#: in block heights, loads in block weights) stays within the range the solvers
#: scale, and nothing overflows when the loads are built; beyond them HiGHS
#: refused the model (``--p 1e300``).
MIN_MAGNITUDE, MAX_MAGNITUDE = 1e-30, 1e30
MAX_RATIO = 1e6
MIN_FRICTION, MAX_FRICTION = 1e-3, 10.0


def _within(name: str, x: float, lo: float, hi: float, why: str) -> None:
    if not lo < x <= hi:
        raise ValueError(f"{name} must be in ({lo:g}, {hi:g}], got {x!r}: {why}")


def physical_bounds(
    length: float,
    block_length: float,
    block_height: float,
    unit_weight: float,
    friction: float,
    rows: Sequence[int],
    thickness: Sequence[float],
    overload: Sequence[float],
) -> None:
    """The physical bounds above, on values already checked one by one.

    Raises:
        ValueError: naming the first parameter out of bounds, worded as ``macro.checks`` words it.
    """
    for name, x in (
        ("length", length),
        ("block_length", block_length),
        ("block_height", block_height),
        ("unit_weight", unit_weight),
    ):
        _within(name, x, MIN_MAGNITUDE, MAX_MAGNITUDE, "dimensional values are limited to this range")
    _within("friction", friction, MIN_FRICTION, MAX_FRICTION, "dry-joint friction coefficients lie near 0.3-1")
    b, R = block_height, MAX_RATIO
    _within("block_length", block_length, b / R, b * R, f"at most {R:g} block heights")
    if length > b * R:
        raise ValueError(f"length must be at most {b * R:g}, got {length!r}: at most {R:g} block heights")
    if sum(rows) > R:
        raise ValueError(f"rows must be at most {R:g}, got {sum(rows)!r}: rows in all")
    for i, (t, q) in enumerate(zip(thickness, overload, strict=True)):
        _within(f"thickness[{i}]", t, b / R, b * R, f"at most {R:g} block heights")
        if q > R * unit_weight * b * t:
            raise ValueError(
                f"overload[{i}] must be at most {R * unit_weight * b * t:g}, got {q!r}: "
                f"at most {R:g} times the weight of one row per unit length"
            )


def _course_edges(n_half: int, starts_full: bool) -> IntArray:
    """Joint positions of one course in half-block units, ``0 ... n_half``."""
    if starts_full:
        inner = np.arange(2, n_half, 2, dtype=np.int64)
    else:
        inner = np.arange(1, n_half, 2, dtype=np.int64)
    return np.concatenate([[0], inner, [n_half]]).astype(np.int64)


def _count_blocks(n_half: int, starts_full: bool) -> int:
    """Blocks in one course (``len(_course_edges) - 1``) without building it."""
    if starts_full:
        return (n_half - 1) // 2 + 1
    return n_half // 2 + 1


def estimate_bytes(n_blocks: int) -> int:
    """Estimated peak memory of building and solving a wall of ``n_blocks``."""
    return int(n_blocks) * BYTES_PER_BLOCK


def build_wall(
    *,
    length: float,
    block_length: float,
    block_height: float,
    rows: tuple[int, ...],
    thickness: tuple[float, ...],
    overload: tuple[float, ...],
    unit_weight: float,
    friction: float,
    first_course: Literal["full", "half"] = "full",
    head_joints: Literal["frictional", "frictionless"] = "frictional",
    max_bytes: int | None = None,
) -> BlockWall:
    """Build a running-bond wall of rigid blocks.

    Courses alternate between one that starts at ``x = 0`` with a full block
    and one that starts with a half block (overlap ``v = l/2``); each course
    ends with whatever remains (a full or a half block). The base is a fixed
    support with a frictional interface under every bottom block.

    Args:
        length: wall length ``L``; must be a whole number of half blocks.
        block_length: block length ``l``.
        block_height: block height ``b``.
        rows: courses per storey, storey 1 (TOP) first.
        thickness: block thickness per storey, storey 1 first.
        overload: floor load per unit length on top of each storey, storey 1
            first. It loads the top course of the storey (each block gets
            ``q * block length`` at the centre of its top face) and its mass
            takes part in the horizontal live load at floor level.
        unit_weight: specific weight of the blocks.
        friction: friction coefficient ``mu`` of all joints and of the base.
        first_course: ``"full"`` (default): the bottom course starts at
            ``x = 0`` with a full block; ``"half"``: with a half block.
        head_joints: ``"frictional"`` (default, friction ``mu``) or
            ``"frictionless"`` (``mu = 0`` on head joints).
        max_bytes: memory budget for the guard; default: the memory
            currently available (``/proc/meminfo``).

    Returns:
        The :class:`BlockWall`.

    Raises:
        ValueError: a bad parameter (the message names it), or a wall whose
            estimated memory exceeds the budget (the message quotes both).
    """
    L = _number("length", length)
    lb = _number("block_length", block_length)
    hb = _number("block_height", block_height)
    gamma = _number("unit_weight", unit_weight)
    mu = _number("friction", friction)
    if isinstance(rows, (str, bytes)) or not hasattr(rows, "__len__") or len(rows) == 0:  # type: ignore[arg-type]
        raise ValueError(f"rows must be a non-empty tuple of positive integers, storey 1 = top; got {rows!r}")
    rows_t: list[int] = []
    for i, r in enumerate(tuple(rows)):
        if isinstance(r, bool) or not isinstance(r, (int, np.integer, float)) or float(r) != int(r) or int(r) <= 0:
            raise ValueError(f"rows[{i}] must be a positive integer, got {r!r}")
        rows_t.append(int(r))
    n_storeys = len(rows_t)
    thick = _per_storey("thickness", thickness, n_storeys, positive=True)
    over = _per_storey("overload", overload, n_storeys, positive=False)
    if first_course not in ("full", "half"):
        raise ValueError(f"first_course must be 'full' or 'half', got {first_course!r}")
    if head_joints not in ("frictional", "frictionless"):
        raise ValueError(f"head_joints must be 'frictional' or 'frictionless', got {head_joints!r}")
    physical_bounds(L, lb, hb, gamma, mu, rows_t, thick, over)

    half = 0.5 * lb
    ratio = L / half
    n_half = int(round(ratio))
    if n_half < 1 or abs(ratio - n_half) > 1e-9 * max(1.0, ratio):
        raise ValueError(
            f"length must be a whole number of half blocks (l/2 = {half:g}); got length={L:g} = {ratio:.6g} half blocks"
        )

    # ---- memory guard (arithmetic only; nothing large is allocated yet)
    n_courses = sum(rows_t)
    bottom_full = first_course == "full"
    n_even = (n_courses + 1) // 2  # courses 0, 2, 4, ... (same type as the bottom one)
    n_odd = n_courses // 2
    per_even = _count_blocks(n_half, bottom_full)
    per_odd = _count_blocks(n_half, not bottom_full)
    n_blocks_est = n_even * per_even + n_odd * per_odd
    need = estimate_bytes(n_blocks_est)
    budget = available_memory_bytes() if max_bytes is None else int(max_bytes)
    if budget is not None and need > budget:
        raise ValueError(
            f"wall too large: {n_blocks_est:,} blocks need an estimated {need / 1e9:.3g} GB "
            f"({need:,} bytes) but only {budget / 1e9:.3g} GB ({budget:,} bytes) are available"
        )

    # ---- the two course types, laid out once in half-block units
    e_even = _course_edges(n_half, bottom_full)
    e_odd = _course_edges(n_half, not bottom_full)
    edges = (e_even, e_odd)
    counts = np.array([e_even.size - 1, e_odd.size - 1], dtype=np.int64)
    ctype = np.arange(n_courses, dtype=np.int64) % 2
    per_course = counts[ctype]
    offset = np.concatenate([[0], np.cumsum(per_course)]).astype(np.int64)
    n_blocks = int(offset[-1])
    assert n_blocks == n_blocks_est

    block_course = np.repeat(np.arange(n_courses, dtype=np.int64), per_course)
    local = np.arange(n_blocks, dtype=np.int64) - offset[block_course]
    btype = ctype[block_course]
    left_h = np.where(btype == 0, e_even[np.minimum(local, e_even.size - 1)], e_odd[np.minimum(local, e_odd.size - 1)])
    right_h = np.where(
        btype == 0, e_even[np.minimum(local + 1, e_even.size - 1)], e_odd[np.minimum(local + 1, e_odd.size - 1)]
    )
    x0 = left_h * half
    x1 = right_h * half
    y0 = block_course * hb
    y1 = y0 + hb

    # storey of each course: storey N (bottom) holds the first rows[N-1] courses
    storey_of_course = np.repeat(np.arange(n_storeys, 0, -1, dtype=np.int64), rows_t[::-1])
    b_storey = storey_of_course[block_course]
    t_block = np.asarray(thick)[b_storey - 1]
    top_course_of_storey = np.cumsum(rows_t[::-1])[::-1] - 1  # index i -> storey i+1
    is_floor = block_course == top_course_of_storey[b_storey - 1]

    lengths = x1 - x0
    weight = gamma * lengths * hb * t_block
    q_block = np.where(is_floor, np.asarray(over)[b_storey - 1] * lengths, 0.0)
    dead = np.zeros((n_blocks, 3))
    dead[:, 1] = -(weight + q_block)
    live = np.zeros((n_blocks, 3))
    live[:, 0] = weight + q_block
    live[:, 2] = -q_block * 0.5 * hb  # overload mass acts at the top face

    # ---- contacts ------------------------------------------------------
    ca: list[IntArray] = []
    cb: list[IntArray] = []
    kind: list[IntArray] = []
    nrm: list[FloatArray] = []
    pxs: list[FloatArray] = []
    pys: list[FloatArray] = []

    # base: under every block of course 0
    nb0 = int(per_course[0])
    ca.append(np.full(nb0, -1, dtype=np.int64))
    cb.append(np.arange(nb0, dtype=np.int64))
    kind.append(np.full(nb0, BASE, dtype=np.int64))
    nrm.append(np.tile([0.0, 1.0], (nb0, 1)))
    pxs.append(np.column_stack([x0[:nb0], x1[:nb0]]))
    pys.append(np.zeros((nb0, 2)))

    # head joints: interior edges of each course type, tiled over the courses
    for typ in (0, 1):
        courses = np.flatnonzero(ctype == typ)
        e = edges[typ]
        k = e.size - 2
        if k <= 0 or courses.size == 0:
            continue
        left = (offset[courses][:, None] + np.arange(k)[None, :]).ravel()
        xh = np.tile(e[1:-1] * half, courses.size)
        yb = np.repeat(courses * hb, k)
        m = left.size
        ca.append(left)
        cb.append(left + 1)
        kind.append(np.full(m, HEAD, dtype=np.int64))
        nrm.append(np.tile([1.0, 0.0], (m, 1)))
        pxs.append(np.column_stack([xh, xh]))
        pys.append(np.column_stack([yb, yb + hb]))

    # bed joints: overlaps of course j (below) with course j+1 (above)
    for typ in (0, 1):
        lower = np.flatnonzero(ctype[:-1] == typ)
        if lower.size == 0:
            continue
        el, eu = edges[typ], edges[1 - typ]
        cuts = np.union1d(el, eu)
        mid2 = cuts[:-1] + cuts[1:]  # twice the segment midpoints (exact)
        il = np.searchsorted(2 * el, mid2, side="right") - 1
        iu = np.searchsorted(2 * eu, mid2, side="right") - 1
        k = mid2.size
        a = (offset[lower][:, None] + il[None, :]).ravel()
        b = (offset[lower + 1][:, None] + iu[None, :]).ravel()
        ys = np.repeat((lower + 1) * hb, k)
        m = a.size
        ca.append(a)
        cb.append(b)
        kind.append(np.full(m, BED, dtype=np.int64))
        nrm.append(np.tile([0.0, 1.0], (m, 1)))
        pxs.append(np.column_stack([np.tile(cuts[:-1] * half, lower.size), np.tile(cuts[1:] * half, lower.size)]))
        pys.append(np.column_stack([ys, ys]))

    contact_kind = np.concatenate(kind)
    mu_c = np.full(contact_kind.size, mu)
    if head_joints == "frictionless":
        mu_c[contact_kind == HEAD] = 0.0

    return BlockWall(
        length=L,
        block_length=lb,
        block_height=hb,
        rows=tuple(rows_t),
        thickness=thick,
        overload=over,
        unit_weight=gamma,
        friction=mu,
        first_course=first_course,
        head_joints=head_joints,
        x0=x0,
        x1=x1,
        y0=y0,
        y1=y1,
        course=block_course,
        storey=b_storey,
        dead=dead,
        live=live,
        contact_a=np.concatenate(ca),
        contact_b=np.concatenate(cb),
        contact_kind=contact_kind,
        normal=np.concatenate(nrm),
        px=np.concatenate(pxs),
        py=np.concatenate(pys),
        mu=mu_c,
    )
