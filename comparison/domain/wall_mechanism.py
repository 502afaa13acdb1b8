"""The wall as built and, where a sliver allows a local mechanism, the held wall: :func:`solve_wall_mechanism`.

A sliver (a piece narrower than a closer, laid only with ``ends="cut"``) lets a corner of the block model
collapse on its own: the piece tips over alone, or the block above rocks out over it (:mod:`micro.local_mechanisms`).
That is a true mechanism of the wall as built, and the value every comparison rests on; but it says
little about the wall's own strength. So where one governs, the same analysis runs again with every sliver
of the wall held to the block that carries it (:func:`micro.hold_blocks`; the held wall has no sliver left,
so no local mechanism either), and its value is reported beside the wall as built's: ``held_load_factor``.

The held wall is another structure (a held joint carries whatever force the held piece needs, tension
included): its values never stand in for the wall as built's, in a verdict or a table.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import micro
from micro import HeldWall, LimitResult, LocalMechanism, NonAssociativeResult, hold_blocks, local_mechanism
from micro.columns import FlatRecord, LoadFactor, column, json_number, record_of
from micro.local_mechanisms import slivers

MicroResult = LimitResult | NonAssociativeResult
Solve = Callable[[micro.BlockWall], MicroResult]

#: Values of :attr:`WallMechanism.status`: the held wall's value was found, or its analysis failed.
WALL, FAILED = "wall", "failed"


@dataclass(frozen=True)
class LocalRecord(FlatRecord):
    """A local mechanism that governs the wall as built and the held wall's value beside it, flat: the
    record of the runner and the cache, and the ``local_mechanism`` object of ``xcheck micro --json``
    (made from a :class:`WallMechanism` that has one). Each field's meaning is its declaration."""

    description: str = column("What moves, in words.", source="local.description")
    load_factor: LoadFactor = column("Its lambda: the wall as built's value to quote.", source="local.load_factor")
    weight_share: float = column("The moving blocks' share of the wall's dead load.", source="local.weight_share",
                                 schema={"type": "number", "minimum": 0, "maximum": 1})
    blocks: tuple[int, ...] = column(
        "The moving blocks (numbered course by course from the base, left to right).", source="local.blocks")
    slivers: tuple[int, ...] = column("The slivers it moves or rests on: the pieces held for the held wall.",
                                      source="local.slivers")
    direction: str = column("The load direction.", source="local.direction", schema={"enum": ["+x", "-x"]})
    held_load_factor: LoadFactor = column(
        "The held wall's lambda (the same analysis with the slivers held to the blocks that carry them: "
        "another wall, never compared); null when its analysis failed (status says so).")
    held: tuple[int, ...] = column("The slivers held to the blocks that carry them: every sliver of the wall.")
    status: str = column("wall: held_load_factor is the held wall's (its mechanism is not local); otherwise "
                         "held_load_factor is null and message says why.", schema={"enum": [WALL, FAILED]})
    message: str = column("Why the held wall's value is missing (empty when found).")


@dataclass(frozen=True, eq=False)
class WallMechanism:
    """The wall as built's analysis and, where a local mechanism governs it, the held wall's.

    Attributes:
        local: the local mechanism that governs the wall as built (``None``: none; nothing was held).
        result: the analysis of the wall as built: its value is the one to quote and compare.
        held_result: the held wall's analysis (``None`` when nothing local governs).
        held: the slivers held, every sliver of the wall (indices in the wall as built; empty when nothing
            local governs).
        held_wall: the held wall ``held_result`` was computed on (``None`` when nothing is held).
        status: :data:`WALL`, or :data:`FAILED` (the held analysis failed: ``held_load_factor`` is NaN,
            ``message`` says why).
        message: why the held wall's value is missing.
    """

    local: LocalMechanism | None
    result: MicroResult = field(repr=False)
    held_result: MicroResult | None = field(default=None, repr=False)
    held: tuple[int, ...] = ()
    held_wall: HeldWall | None = field(default=None, repr=False)
    status: str = WALL
    message: str = ""

    @property
    def load_factor(self) -> float:
        """The wall as built's load factor (its value to quote): the one compared with the macro model."""
        return self.result.load_factor

    @property
    def held_load_factor(self) -> float:
        """The held wall's load factor (NaN when nothing local governs, or it was not found)."""
        if self.held_result is None or self.status != WALL:
            return math.nan
        return self.held_result.load_factor

    def to_record(self) -> LocalRecord | None:
        """The flat :class:`LocalRecord` (``None`` when nothing local governs)."""
        return None if self.local is None else record_of(LocalRecord, self)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``held_load_factor`` and ``local_mechanism`` (its :class:`LocalRecord`, or ``None``)."""
        rec = self.to_record()
        return {"held_load_factor": json_number(self.held_load_factor),
                "local_mechanism": None if rec is None else rec.to_dict()}


def solve_wall_mechanism(wall: micro.BlockWall, solve: Solve, *, first: MicroResult | None = None) -> WallMechanism:
    """Run a micro method on ``wall``, tell a sliver's local mechanism apart, and, where one governs, analyse the
    held wall beside it (module docstring).

    One call gives what a comparison with the macro model needs::

        wm = solve_wall_mechanism(wall, micro.solve_nonassociative)
        wm.load_factor        # the wall as built's lambda: compare the macro model with this
        wm.local              # None, or the LocalMechanism that governs it (what moves, which sliver)
        wm.held_load_factor   # the held wall's lambda (NaN when nothing local governs)

    Args:
        wall: the wall as built (:meth:`comparison.domain.wall.WallSpec.to_micro`).
        solve: the micro method, a function of a wall (``micro.solve_associative``,
            ``micro.solve_nonassociative``, or a ``functools.partial`` of either with its options).
        first: the method's result on ``wall`` when already computed (it is not computed again).

    Returns:
        The :class:`WallMechanism`. Where nothing local governs, no analysis but the first is run.
    """
    base = solve(wall) if first is None else first
    local = local_mechanism(wall, base)
    if local is None:
        return WallMechanism(None, base)
    held = tuple(int(b) for b in np.flatnonzero(slivers(wall)))
    hw = hold_blocks(wall, held)
    result = solve(hw.wall)
    if not result.ok:
        return WallMechanism(local, base, result, held, hw, FAILED,
                             f"the analysis of the held wall failed: {result.status} {result.message}".strip())
    return WallMechanism(local, base, result, held, hw)
