"""Rigid-block limit analysis of running-bond walls by linear programming.

Build a wall block by block with :func:`build_wall` and compute its collapse
load factor under a horizontal (seismic) live load with associative friction
with :func:`solve_associative`::

    import micro
    wall = micro.build_wall(length=12, block_length=3, block_height=1, rows=(12,),
                            thickness=(1,), overload=(0,), unit_weight=1, friction=0.75)
    result = micro.solve_associative(wall, solver="highs")
    result.load_factor, result.direction, result.status

and with non-associative (zero-dilatancy) friction by the iterated LP of
Gilbert, Casapulla & Ahmed (2006) with :func:`solve_nonassociative`::

    result = micro.solve_nonassociative(wall, scheme="a")
    result.load_factor, result.status, result.iterations, result.history
"""

from micro.analysis import DirectionResult, LimitResult, solve_associative
from micro.geometry import BlockWall, build_wall, estimate_bytes
from micro.lp import LimitLP, assemble
from micro.mechanism import Mechanism, mechanism_from_duals
from micro.nonassociative import (
    IterationRecord,
    NonAssocDirection,
    NonAssociativeResult,
    solve_nonassociative,
    verify_collapse_state,
)
from micro.records import AssociativeRecord, MicroRecord, NonAssociativeRecord
from micro.solvers import SOLVERS, Status, make_backend

__all__ = [
    "SOLVERS",
    "BlockWall",
    "DirectionResult",
    "LimitLP",
    "LimitResult",
    "Mechanism",
    "Status",
    "assemble",
    "build_wall",
    "estimate_bytes",
    "make_backend",
    "mechanism_from_duals",
    "solve_associative",
    # non-associative friction (issue 4)
    "IterationRecord",
    "NonAssocDirection",
    "NonAssociativeResult",
    "solve_nonassociative",
    "verify_collapse_state",
    # flat JSON-ready records
    "AssociativeRecord",
    "MicroRecord",
    "NonAssociativeRecord",
]
