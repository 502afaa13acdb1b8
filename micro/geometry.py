"""Running-bond block assemblage of a dry-joint wall (2-D, in-plane).

The builder :func:`build_wall` lays the wall out course by course from the
base up and lists every interface (bed-joint overlap, head joint, base) by its
two end points, which is exact for rigid blocks in 2-D. Everything is done
with whole-array numpy operations: the layout of each of the two course types
is computed once and tiled over the courses.

Walls of any length (at least half a block) are built. Head joints sit at
whole half blocks from ``x = 0`` (``k * l/2``, the same float in every
course, so bed-joint overlaps are found by exact comparisons); each course
ends at ``x = L`` with whatever remains after its last joint. When ``L`` is a
whole number of half blocks that is a full or a half block, as in the paper;
otherwise the last block of each course is CUT, to a length in ``(0, l/2)``
in one course type and in ``(l/2, l)`` in the other. Only the last block of
a course is cut; a sliver is kept however thin (it did
not hurt the LP's conditioning, and merging it into its neighbour made the
load factor jump with ``L``; see ``docs/micro/walls.md``). A cut piece of the
TOP course carries nothing and tips over alone at a load factor that goes to 0
with its width: :mod:`micro.local_mechanisms` tells that mechanism apart.

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
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from micro.courses import blocks_in_course, closed_edges, closer_width, course_edges, half_block_count
from micro.memory import guard_memory
from micro.wall_checks import _number, _per_storey, _positive_int, physical_bounds

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Contact kinds (values of :attr:`BlockWall.contact_kind`).
BASE, BED, HEAD = 0, 1, 2
CONTACT_KIND_NAMES = ("base", "bed", "head")

#: How a course ends when the wall's length is not a whole number of half blocks (:func:`build_wall`'s
#: ``ends``): ``"closers"`` (the default) as a mason closes a course, with no piece narrower than half a
#: block and head joints at least a quarter block apart from course to course; ``"cut"`` with whatever
#: remains after the last regular joint, down to slivers of any width.
ENDS = ("closers", "cut")


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
        ends: how the courses end when ``L`` is not a whole number of half
            blocks (:data:`ENDS`): ``"closers"`` or ``"cut"``.
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
    ends: str
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
        """Length of each block (``l`` or ``l/2``, or shorter at a cut end)."""
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

    @property
    def half_blocks(self) -> float:
        """The wall length in half blocks ``L/(l/2)`` (an integer-valued float when whole)."""
        return half_block_count(self.length, 0.5 * self.block_length)[0]

    @property
    def end_blocks_cut(self) -> bool:
        """True when ``L`` is not a whole number of half blocks: the last block of every course is cut
        (module docstring)."""
        return not half_block_count(self.length, 0.5 * self.block_length)[1]

    def describe(self) -> str:
        """One-line summary."""
        return (
            f"{self.n_blocks} blocks, {self.n_contacts} contacts in {self.n_courses} courses "
            f"(L={self.length:g}, l={self.block_length:g}, b={self.block_height:g}, "
            f"first course {self.first_course}, head joints {self.head_joints})"
        )


def check_block_wall(wall: object) -> BlockWall:
    """``wall`` when it is a :class:`BlockWall`: the entry points refuse anything else at once, naming it.

    Raises:
        TypeError: ``"wall must be a micro.BlockWall (micro.build_wall(...) or WallSpec.to_micro() gives
            one), got WallSpec"``.
    """
    if not isinstance(wall, BlockWall):
        raise TypeError("wall must be a micro.BlockWall (micro.build_wall(...) or WallSpec.to_micro() gives one), "
                        f"got {type(wall).__name__}")
    return wall


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
    ends: Literal["closers", "cut"] = "closers",
    max_bytes: int | None = None,
) -> BlockWall:
    """Build a running-bond wall of rigid blocks.

    Courses alternate between one that starts at ``x = 0`` with a full block
    and one that starts with a half block (overlap ``v = l/2``); each course
    ends with whatever remains: a full or a half block when ``L`` is a whole
    number of half blocks, else a cut block (see the module docstring). The
    base is a fixed support with a frictional interface under every bottom
    block.

    Args:
        length: wall length ``L``, at least half a block (``l/2``).
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

    Examples:
        A one-storey wall three blocks long and six courses high (21 blocks:
        the half-block courses end with a half block):

        >>> import micro
        >>> wall = micro.build_wall(length=3.0, block_length=1.0, block_height=0.5, rows=(6,),
        ...                         thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=0.75)
        >>> wall.n_blocks, wall.mirror_symmetric
        (21, True)
    """
    L = _number("length", length)
    lb = _number("block_length", block_length)
    hb = _number("block_height", block_height)
    gamma = _number("unit_weight", unit_weight)
    mu = _number("friction", friction)
    if isinstance(rows, (str, bytes)) or not hasattr(rows, "__len__"):
        raise ValueError(f"rows must be a tuple with one value per storey (storey 1 = top), got {rows!r}")
    if len(rows) == 0:
        raise ValueError("rows: a wall needs at least one storey")
    rows_t = tuple(_positive_int(f"rows[{i}]", r) for i, r in enumerate(tuple(rows)))
    thick = _per_storey("thickness", thickness, len(rows_t), positive=True)
    over = _per_storey("overload", overload, len(rows_t), positive=False)
    if first_course not in ("full", "half"):
        raise ValueError(f"first_course must be 'full' or 'half', got {first_course!r}")
    if head_joints not in ("frictional", "frictionless"):
        raise ValueError(f"head_joints must be 'frictional' or 'frictionless', got {head_joints!r}")
    if ends not in ENDS:
        raise ValueError(f"ends must be 'closers' or 'cut', got {ends!r}")
    if max_bytes is not None and (isinstance(max_bytes, bool) or not isinstance(max_bytes, (int, np.integer))
                                  or max_bytes <= 0):
        raise ValueError(f"max_bytes must be a positive integer (bytes) or None, got {max_bytes!r}")
    physical_bounds(L, lb, hb, gamma, mu, rows_t, thick, over)

    half = 0.5 * lb
    r, whole = half_block_count(L, half)
    if r < 1.0:
        raise ValueError(f"length must be at least half a block (block_length/2 = {half:g}), got {length!r}")
    last = math.ceil(r) - 1  # the last head joint (half blocks) before the end
    bottom_full = first_course == "full"
    n_courses = sum(rows_t)
    n_even = (n_courses + 1) // 2  # courses 0, 2, 4, ... (same type as the bottom one)
    n_blocks = n_even * blocks_in_course(last, bottom_full) + (n_courses // 2) * blocks_in_course(last, not bottom_full)
    guard_memory(n_blocks, max_bytes)

    end = r * half if whole else L
    edges = (course_edges(last, end, half, bottom_full), course_edges(last, end, half, not bottom_full))
    if not whole and ends == "closers":
        edges = closed_edges(edges, L, closer_width(lb, hb, mu))
    blocks = _lay_blocks(edges, n_courses, hb)
    dead, live, storey = _block_loads(blocks, rows_t, thick, over, gamma, hb)
    contacts = _contacts(edges, blocks, hb)
    contact_kind = contacts["contact_kind"]
    mu_c = np.full(contact_kind.size, mu)
    if head_joints == "frictionless":
        mu_c[contact_kind == HEAD] = 0.0
    y0 = blocks.course.astype(np.float64) * hb
    return BlockWall(
        length=L, block_length=lb, block_height=hb, rows=rows_t, thickness=thick, overload=over,
        unit_weight=gamma, friction=mu, first_course=first_course, head_joints=head_joints, ends=ends,
        x0=blocks.x0, x1=blocks.x1, y0=y0, y1=y0 + hb, course=blocks.course,
        storey=storey, dead=dead, live=live, mu=mu_c, **contacts,
    )


@dataclass(frozen=True)
class _Blocks:
    """Blocks laid course by course: extents, course, and where each course
    starts in the block numbering (``offset``) and which type it is (``ctype``:
    0 like the bottom course, 1 the other)."""

    x0: FloatArray
    x1: FloatArray
    course: IntArray
    offset: IntArray
    ctype: IntArray


def _lay_blocks(edges: tuple[FloatArray, FloatArray], n_courses: int, hb: float) -> _Blocks:
    """Tile the two course types' edges over ``n_courses`` alternating courses."""
    counts = np.array([edges[0].size - 1, edges[1].size - 1], dtype=np.int64)
    ctype = np.arange(n_courses, dtype=np.int64) % 2
    per_course = counts[ctype]
    offset = np.concatenate([[0], np.cumsum(per_course)]).astype(np.int64)
    n_blocks = int(offset[-1])
    course = np.repeat(np.arange(n_courses, dtype=np.int64), per_course)
    local = np.arange(n_blocks, dtype=np.int64) - offset[course]
    even = ctype[course] == 0
    e0, e1 = edges
    x0 = np.where(even, e0[np.minimum(local, e0.size - 1)], e1[np.minimum(local, e1.size - 1)])
    x1 = np.where(even, e0[np.minimum(local + 1, e0.size - 1)], e1[np.minimum(local + 1, e1.size - 1)])
    return _Blocks(x0, x1, course, offset, ctype)


def _block_loads(
    blocks: _Blocks, rows: tuple[int, ...], thick: tuple[float, ...], over: tuple[float, ...], gamma: float, hb: float
) -> tuple[FloatArray, FloatArray, IntArray]:
    """Dead and live loads ``(F_x, F_y, M)`` per block and each block's storey."""
    n_storeys = len(rows)
    # storey of each course: storey N (bottom) holds the first rows[N-1] courses
    storey_of_course = np.repeat(np.arange(n_storeys, 0, -1, dtype=np.int64), rows[::-1])
    storey = storey_of_course[blocks.course]
    t_block = np.asarray(thick)[storey - 1]
    top_course_of_storey = np.cumsum(rows[::-1])[::-1] - 1  # index i -> storey i+1
    is_floor = blocks.course == top_course_of_storey[storey - 1]
    lengths = blocks.x1 - blocks.x0
    weight = gamma * lengths * hb * t_block
    q_block = np.where(is_floor, np.asarray(over)[storey - 1] * lengths, 0.0)
    dead = np.zeros((lengths.size, 3))
    dead[:, 1] = -(weight + q_block)
    live = np.zeros((lengths.size, 3))
    live[:, 0] = weight + q_block
    live[:, 2] = -q_block * 0.5 * hb  # overload mass acts at the top face
    return dead, live, storey


def _contacts(edges: tuple[FloatArray, FloatArray], blocks: _Blocks, hb: float) -> dict[str, np.ndarray]:
    """Every interface: the base under course 0, the head joints of every
    course, the bed-joint overlaps of every pair of courses (in that order).

    Returns:
        ``contact_a``, ``contact_b``, ``contact_kind``, ``normal``, ``px``,
        ``py`` as :class:`BlockWall` wants them.
    """
    offset, ctype = blocks.offset, blocks.ctype
    nb0 = int(offset[1])
    parts: list[tuple[IntArray, IntArray, int, tuple[float, float], FloatArray, FloatArray]] = [
        (np.full(nb0, -1, dtype=np.int64), np.arange(nb0, dtype=np.int64), BASE, (0.0, 1.0),
         np.column_stack([blocks.x0[:nb0], blocks.x1[:nb0]]), np.zeros((nb0, 2)))
    ]
    # head joints: interior edges of each course type, tiled over the courses
    for typ in (0, 1):
        courses = np.flatnonzero(ctype == typ)
        e = edges[typ]
        k = e.size - 2
        if k <= 0 or courses.size == 0:
            continue
        left = (offset[courses][:, None] + np.arange(k)[None, :]).ravel()
        xh = np.tile(e[1:-1], courses.size)
        yb = np.repeat(courses * hb, k)
        parts.append((left, left + 1, HEAD, (1.0, 0.0), np.column_stack([xh, xh]), np.column_stack([yb, yb + hb])))
    # bed joints: overlaps of course j (below) with course j+1 (above)
    for typ in (0, 1):
        lower = np.flatnonzero(ctype[:-1] == typ)
        if lower.size == 0:
            continue
        el, eu = edges[typ], edges[1 - typ]
        cuts = np.union1d(el, eu)  # the edges are exact copies of one another: no tolerance
        il = np.searchsorted(el, cuts[:-1], side="right") - 1  # block holding each overlap's left end
        iu = np.searchsorted(eu, cuts[:-1], side="right") - 1
        a = (offset[lower][:, None] + il[None, :]).ravel()
        b = (offset[lower + 1][:, None] + iu[None, :]).ravel()
        ys = np.repeat((lower + 1) * hb, cuts.size - 1)
        px = np.column_stack([np.tile(cuts[:-1], lower.size), np.tile(cuts[1:], lower.size)])
        parts.append((a, b, BED, (0.0, 1.0), px, np.column_stack([ys, ys])))
    return {
        "contact_a": np.concatenate([p[0] for p in parts]),
        "contact_b": np.concatenate([p[1] for p in parts]),
        "contact_kind": np.concatenate([np.full(p[0].size, p[2], dtype=np.int64) for p in parts]),
        "normal": np.concatenate([np.tile(p[3], (p[0].size, 1)) for p in parts]),
        "px": np.concatenate([p[4] for p in parts]),
        "py": np.concatenate([p[5] for p in parts]),
    }
