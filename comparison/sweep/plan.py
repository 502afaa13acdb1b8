"""A sweep's cells: every wall of the grid, every method, every bond of a micro method.

A :class:`Cell` is one row of the sweep's table. The cells are numbered in the
grid's order (axes in the order ``t, m, rows, f, p, storeys``, then the
methods, then the bonds: ``first_course``, ``head_joints``, ``ends``), which is the
order of the table whatever order they were computed in. A bond's ``ends`` is the
micro wall's (:attr:`comparison.domain.wall.WallSpec.ends`), its other options the method's.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from comparison.domain.wall import WallSpec
from comparison.runner import Method, approximate_blocks
from comparison.sweep.grid import PER_WALL, Grid, GridMethod
from comparison.sweep.usermodel import UserModel
from macro.checks import UNEQUAL_STOREYS

#: Why a cell is not computed: its parameters make no wall (rows that do not split over its storeys, a wall
#: outside the physical bounds), or its wall is over a block limit.
NOT_APPLICABLE, NOT_RUN = "not_applicable", "not_run"


@dataclass(frozen=True)
class WallPoint:
    """One combination of the grid's axes (the paper's Table 4 parameters).

    Attributes:
        t, m, rows, f, p, storeys: the parameters.
    """

    t: float
    m: float
    rows: int
    f: float
    p: float
    storeys: int

    @property
    def label(self) -> str:
        """Short name, e.g. ``t=1 m=0.3333 o=60 f=0.6 p=0 N=3``."""
        return f"t={self.t:g} m={self.m:.4g} o={self.rows} f={self.f:g} p={self.p:g} N={self.storeys}"

    def spec(self) -> WallSpec:
        """The dimensional wall.

        Raises:
            ValueError: the rows do not split equally over the storeys.
        """
        return WallSpec.from_paper(
            t=self.t, m=self.m, rows=self.rows, f=self.f, p=self.p, storeys=self.storeys, name=self.label
        )


@dataclass(frozen=True)
class Cell:
    """One row of a sweep: a method on a wall (with a bond, for a micro method).

    Attributes:
        index: position in the grid's order.
        point: the wall's parameters.
        method: the method, bond options included, or a user's macro model.
        spec: the micro wall the method runs on, storeys that differ in
            nothing merged (see :func:`micro_spec`); ``None`` for the macro
            model (its side is vectorised over the points), a user's model
            and when the parameters make no wall.
        blocks: blocks of the micro wall, approximately (0 for the macro model).
        skip: ``""``, or :data:`NOT_APPLICABLE` / :data:`NOT_RUN`.
        message: why it is skipped.
        where_needed: a non-associative cell over the block limit of a grid with ``where_needed``: it runs
            after all if the associative bound does not settle its wall's verdict
            (:func:`comparison.sweep.run.needed`).
    """

    index: int
    point: WallPoint
    method: Method | UserModel
    spec: WallSpec | None
    blocks: int = 0
    skip: str = ""
    message: str = ""
    where_needed: bool = False

    @property
    def micro(self) -> bool:
        """A micro method's cell."""
        return self.method.kind not in PER_WALL

    @property
    def item(self) -> tuple[WallSpec, Method] | None:
        """What the runner computes for a micro cell with a wall (its cache key), else ``None``."""
        if self.spec is None or not isinstance(self.method, Method) or not self.micro:
            return None
        return self.spec, self.method


def micro_spec(spec: WallSpec) -> WallSpec:
    """``spec`` with its storeys merged into one when they differ in nothing but their rows and carry no floor load.

    The block walls of the two are the same, so their micro results are:
    merged, they share one cache entry (a one- and a three-storey wall without
    overload are computed once).
    """
    first = spec.storeys[0]
    if len(spec.storeys) == 1 or any(s.thickness != first.thickness or s.overload for s in spec.storeys):
        return spec
    return replace(spec, storeys=(replace(first, rows=spec.rows),))


def wall_points(grid: Grid) -> list[WallPoint]:
    """Every combination of the grid's axes, in the grid's order."""
    a = grid.axes
    combos = itertools.product(a["t"], a["m"], a["rows"], a["f"], a["p"], a["storeys"])
    return [WallPoint(float(t), float(m), int(o), float(f), float(p), int(n)) for t, m, o, f, p, n in combos]


def cells(grid: Grid) -> list[Cell]:
    """The cells of ``grid``, numbered in its order (a micro wall is built once per wall, none for the macro model)."""
    out: list[Cell] = []
    bonds = list(itertools.product(grid.bond["first_course"], grid.bond["head_joints"], grid.bond["ends"]))
    micro = any(gm.method.kind not in PER_WALL for gm in grid.methods)
    points = wall_points(grid)
    no_wall = unbuildable(points)
    for k, point in enumerate(points):
        why = "" if point.rows % point.storeys == 0 else UNEQUAL_STOREYS.format(rows=point.rows, storeys=point.storeys)
        why = why or no_wall.get(k, "")
        spec = micro_spec(point.spec()) if micro and not why else None
        for gm in grid.methods:
            if isinstance(gm.method, UserModel) or gm.method.kind == "macro":
                out.append(Cell(len(out), point, gm.method, None, skip=NOT_APPLICABLE if why else "", message=why))
                continue
            for fc, hj, ends in bonds:
                method = replace(gm.method, first_course=fc, head_joints=hj)
                built = None if spec is None else replace(spec, ends=ends)
                out.append(_micro_cell(len(out), point, method, built, why, _limit(grid, gm),
                                       grid.where_needed and method.kind == "micro-nonassoc"))
    return out


def unbuildable(points: Sequence[WallPoint]) -> dict[int, str]:
    """Why the points whose parameters make no wall make none (e.g. a wall shorter than one block), by index.

    The physical bounds of :mod:`macro.checks`, checked in one vectorised call per number of storeys; only
    a group with a bad point is checked point by point (to quote each one's message). Points whose rows
    do not split over their storeys are left to the caller.
    """
    from macro.paper import paper_walls

    out: dict[int, str] = {}
    for n in sorted({p.storeys for p in points}):
        group = [i for i, p in enumerate(points) if p.storeys == n and p.rows % n == 0]
        t, m, rows, f, p = (np.array([getattr(points[i], k) for i in group]) for k in ("t", "m", "rows", "f", "p"))
        try:
            paper_walls(t, m, rows, f, p, storeys=n)
        except ValueError:
            for i in group:
                try:
                    points[i].spec()
                except ValueError as exc:
                    out[i] = str(exc)
    return out


def _limit(grid: Grid, gm: GridMethod) -> int | None:
    """A micro method's block limit: its own ``max_blocks``, and the grid's except for the associative LP, which
    runs on every wall up to its own limit: one LP (seconds for thousands of blocks) whose bound settles the
    verdict wherever the macro value lies above it (:func:`comparison.domain.proof.judge`), so that a wall above the
    non-associative limit still gets a verdict."""
    grid_limit = None if gm.method.kind == "micro-assoc" else grid.max_blocks
    limits = [x for x in (grid_limit, gm.max_blocks) if x is not None]
    return min(limits) if limits else None


def _micro_cell(
    index: int, point: WallPoint, method: Method, spec: WallSpec | None, why: str, limit: int | None,
    where_needed: bool = False,
) -> Cell:
    if spec is None:
        return Cell(index, point, method, None, skip=NOT_APPLICABLE, message=why)
    blocks = approximate_blocks(spec)
    if limit is not None and blocks > limit:
        return Cell(index, point, method, spec, blocks, NOT_RUN, f"about {blocks} blocks: above max_blocks = {limit}",
                    where_needed)
    return Cell(index, point, method, spec, blocks)
