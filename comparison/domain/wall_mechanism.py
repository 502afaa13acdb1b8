"""The wall's own mechanism where a local one governs the block model: :func:`solve_wall_mechanism`.

A cut end piece of the top course tips over alone at ``lambda = width/height``
(:mod:`micro.local_mechanisms`): a mechanism of the block model, not of the wall. The
value compared with the macro model is the wall's own: the same analysis with
the local blocks held to the block that carries them (:func:`micro.hold_blocks`),
repeated while the held wall's governing mechanism is itself local, at most
:data:`MAX_HOLD_ROUNDS` times.

What each output says:

* ``load_factor`` of a micro result (Python, ``xcheck micro --json``, the
  records) stays the block model's governing value, the one its collapse state
  certifies;
* ``wall_load_factor`` is the wall's own value (:attr:`WallMechanism.load_factor`):
  the same number when no local mechanism governs, the held wall's otherwise.
  It is the value compared with the macro model;
* ``local_mechanism`` says what moves (``null`` when nothing local governs).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import micro
from micro import HeldWall, LimitResult, LocalMechanism, NonAssociativeResult, hold_blocks, local_mechanism
from micro.records import json_number

#: The most times the held analysis is repeated when the held wall's mechanism is local again.
MAX_HOLD_ROUNDS = 3

MicroResult = LimitResult | NonAssociativeResult
Solve = Callable[[micro.BlockWall], MicroResult]

#: Values of :attr:`WallMechanism.status`.
WALL, LOCAL_LEFT, FAILED = "wall", "local after the last round", "failed"


@dataclass(frozen=True)
class LocalRecord:
    """A local mechanism and the wall's own value, flat, for the records, the cache and the tables.

    Attributes:
        description: what moves (:attr:`micro.LocalMechanism.description`).
        load_factor: the local mechanism's ``lambda`` (the block model's value to quote).
        weight_share: the moving blocks' share of the dead load.
        blocks: the moving blocks.
        wall_load_factor: the wall's own ``lambda`` (NaN when not found: ``status`` says why).
        held: the blocks held for it.
        rounds: held analyses run.
        status: :attr:`WallMechanism.status`.
        message: why the wall's own value is missing.
    """

    description: str
    load_factor: float
    weight_share: float
    blocks: tuple[int, ...]
    wall_load_factor: float
    held: tuple[int, ...]
    rounds: int
    status: str
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON form (NaN -> ``None``, tuples -> lists)."""
        return {"description": self.description, "load_factor": json_number(self.load_factor),
                "weight_share": json_number(self.weight_share), "blocks": list(self.blocks),
                "wall_load_factor": json_number(self.wall_load_factor), "held": list(self.held),
                "rounds": self.rounds, "status": self.status, "message": self.message}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> LocalRecord:
        """The record :meth:`to_dict` wrote."""
        def num(x: Any) -> float:
            return math.nan if x is None else float(x)

        return cls(d["description"], num(d["load_factor"]), num(d["weight_share"]), tuple(d["blocks"]),
                   num(d["wall_load_factor"]), tuple(d["held"]), int(d["rounds"]), d["status"], d.get("message", ""))


@dataclass(frozen=True, eq=False)
class WallMechanism:
    """The block model's governing mechanism and the wall's own.

    Attributes:
        local: the local mechanism that governs the block model (``None``: the block model's mechanism is the
            wall's, and ``result is result_local``).
        result_local: the analysis of the wall as built (the block model's value).
        result: the analysis that gives the wall's own mechanism: ``result_local`` when nothing local governs,
            else the last held wall's.
        held: the blocks held (indices in the wall as built; empty when nothing local governs).
        held_wall: the held wall ``result`` was computed on (``None`` when nothing is held).
        rounds: held analyses run (0 when nothing local governs).
        status: :data:`WALL` (``result`` is the wall's own mechanism), :data:`LOCAL_LEFT` (still local after
            :data:`MAX_HOLD_ROUNDS` rounds: ``load_factor`` is NaN), or :data:`FAILED` (an analysis failed:
            ``load_factor`` is NaN, ``message`` says which).
        message: why the wall's own value is missing.
    """

    local: LocalMechanism | None
    result_local: MicroResult = field(repr=False)
    result: MicroResult = field(repr=False)
    held: tuple[int, ...] = ()
    held_wall: HeldWall | None = field(default=None, repr=False)
    rounds: int = 0
    status: str = WALL
    message: str = ""

    @property
    def load_factor(self) -> float:
        """The wall's own load factor (the value to quote of :attr:`result`; NaN unless :attr:`status` is
        :data:`WALL`): the value compared with the macro model."""
        return self.result.load_factor if self.status == WALL else math.nan

    @property
    def local_load_factor(self) -> float:
        """The local mechanism's load factor (NaN when nothing local governs)."""
        return self.local.load_factor if self.local is not None else math.nan

    def to_record(self) -> LocalRecord | None:
        """The flat :class:`LocalRecord` (``None`` when nothing local governs)."""
        if self.local is None:
            return None
        loc = self.local
        return LocalRecord(loc.description, loc.load_factor, loc.weight_share, loc.blocks, self.load_factor,
                           self.held, self.rounds, self.status, self.message)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``wall_load_factor``, ``local_mechanism`` (object or ``None``) and how it was found."""
        num = json_number
        return {
            "wall_load_factor": num(self.load_factor),
            "local_mechanism": None if self.local is None else {
                **self.local.to_dict(), "held": list(self.held), "rounds": self.rounds, "status": self.status,
                "message": self.message},
        }


def solve_wall_mechanism(wall: micro.BlockWall, solve: Solve, *, first: MicroResult | None = None,
                         max_rounds: int = MAX_HOLD_ROUNDS) -> WallMechanism:
    """Run a micro method on ``wall``, tell a local mechanism apart, and compute the wall's own.

    One call gives what a comparison with the macro model needs::

        wm = solve_wall_mechanism(wall, micro.solve_nonassociative)
        wm.load_factor        # the wall's own lambda: compare the macro model with this
        wm.local              # None, or the LocalMechanism of the block model (what moves, its lambda)
        wm.result_local       # the block model's analysis (its load_factor is the local lambda if local)

    Args:
        wall: the wall as built (:meth:`comparison.domain.wall.WallSpec.to_micro`).
        solve: the micro method, a function of a wall (``micro.solve_associative``,
            ``micro.solve_nonassociative``, or a ``functools.partial`` of either with its options).
        first: the method's result on ``wall`` when already computed (it is not computed again).
        max_rounds: the most held analyses (:data:`MAX_HOLD_ROUNDS`).

    Returns:
        The :class:`WallMechanism`. Where nothing local governs, ``result`` is ``result_local`` and no
        analysis but the first is run.

    Raises:
        ValueError: ``max_rounds`` is not a positive integer.
    """
    if isinstance(max_rounds, bool) or not isinstance(max_rounds, int) or max_rounds < 1:
        raise ValueError(f"max_rounds must be a positive integer, got {max_rounds!r}")
    base = solve(wall) if first is None else first
    local = local_mechanism(wall, base)
    if local is None:
        return WallMechanism(None, base, base)
    held: tuple[int, ...] = local.blocks
    for rounds in range(1, max_rounds + 1):
        hw = hold_blocks(wall, held)
        result = solve(hw.wall)
        if not result.ok:
            return WallMechanism(local, base, result, held, hw, rounds, FAILED,
                                 f"the analysis of the held wall failed: {result.status} {result.message}".strip())
        again = local_mechanism(hw.wall, result)
        if again is None:
            return WallMechanism(local, base, result, held, hw, rounds)
        left = again.description
        held = tuple(sorted(set(held) | set(hw.original_blocks(again.blocks))))
    return WallMechanism(local, base, result, hw.held, hw, max_rounds, LOCAL_LEFT,
                         f"the held wall's mechanism is still local after {max_rounds} rounds: {left}")
