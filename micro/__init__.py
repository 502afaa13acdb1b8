"""Rigid-block limit analysis of running-bond walls by linear programming.

Build a wall block by block with :func:`build_wall` and compute its collapse
load factor under a horizontal (seismic) live load with associative friction
with :func:`solve_associative`::

    import micro
    wall = micro.build_wall(length=12, block_length=3, block_height=1, rows=(12,),
                            thickness=(1,), overload=(0,), unit_weight=1, friction=0.75)
    result = micro.solve_associative(wall)
    result.load_factor, result.direction, result.status

and with non-associative (zero-dilatancy) friction by the iterated LP of
Gilbert, Casapulla & Ahmed (2006) with :func:`solve_nonassociative`::

    result = micro.solve_nonassociative(wall)   # the report's method
    result.load_factor, result.status, result.iterated_load_factor, result.mechanism_band  # quote the first

The collapse state behind a result, as a file that another program can check and write
(:mod:`micro.state`)::

    micro.write_state(result, "state.json", wall=wall)
    micro.verify_state("state.json").passed     # True: a genuine collapse state

Every result has a flat record (``result.to_record()``: a read-only mapping of its fields,
``record["load_factor"]``; ``record.to_dict()`` is its JSON form).

Layout: ``geometry`` (the wall), ``lp`` (the LP), ``backends`` (the solvers),
``mechanism``, ``results`` and ``records`` (what comes out), ``local`` (is the governing
mechanism a loose piece's, not the wall's?) and ``hold`` (blocks held to their hosts), ``state`` (a
collapse state as data), ``files`` (reading and writing files safely), ``associative``
and ``nonassociative`` (the two analyses), ``global_search`` (the proven global
minimum, composed after a non-associative run: ``solve_global(lp, start=result)``),
``plot``, ``exact`` (dot products whose last bits do not depend on the BLAS kernel). The method, its
options and which
value to quote: ``docs/micro/`` (walls, associative, nonassociative, tuning, global-search).
"""

from micro.associative import solve_associative
from micro.backends import DEFAULT_SOLVER, SOLVERS, Outcome, Status, make_backend
from micro.courses import closer_width
from micro.geometry import ENDS, BlockWall, build_wall
from micro.global_search import GlobalOptions, GlobalResult, solve_global
from micro.hold import HeldWall, hold_blocks
from micro.limit_result import DirectionResult, LimitResult
from micro.local_mechanisms import LocalMechanism, find_local, local_mechanism
from micro.lp import LimitLP, assemble
from micro.mechanism import Mechanism, mechanism_from_duals
from micro.memory import estimate_bytes
from micro.nonassociative import (
    SCHEMES,
    IterationRecord,
    NonAssociativeOptions,
    NonAssociativeResult,
    SequenceDiagnostics,
    Tuning,
    solve_nonassociative,
    verify_collapse_state,
)
from micro.records import AssociativeRecord, MicroRecord, NonAssociativeRecord
from micro.state import (
    CollapseStateData,
    StateCheck,
    StateFileError,
    collapse_state,
    read_state,
    verify_state,
    write_state,
)

__all__ = [
    "DEFAULT_SOLVER",
    "ENDS",
    "SCHEMES",
    "SOLVERS",
    "AssociativeRecord",
    "BlockWall",
    "CollapseStateData",
    "DirectionResult",
    "GlobalOptions",
    "GlobalResult",
    "HeldWall",
    "IterationRecord",
    "LimitLP",
    "LimitResult",
    "LocalMechanism",
    "Mechanism",
    "MicroRecord",
    "NonAssociativeOptions",
    "NonAssociativeRecord",
    "NonAssociativeResult",
    "Outcome",
    "SequenceDiagnostics",
    "StateCheck",
    "StateFileError",
    "Status",
    "Tuning",
    "assemble",
    "build_wall",
    "closer_width",
    "collapse_state",
    "estimate_bytes",
    "find_local",
    "hold_blocks",
    "local_mechanism",
    "make_backend",
    "mechanism_from_duals",
    "read_state",
    "solve_associative",
    "solve_global",
    "solve_nonassociative",
    "verify_collapse_state",
    "verify_state",
    "write_state",
]
