"""The proven global minimum of the non-associative collapse load (a mixed-integer search).

With non-associative (zero-dilatancy) friction the collapse load factor is
not unique: the iterated LP (:mod:`micro.nonassociative`) returns one exact
collapse state, a local answer. :func:`solve_global` writes the collapse
conditions with binary contact states (:mod:`.model`), minimises ``lambda``
by branch and bound (HiGHS, :mod:`.highs`, or SCIP, :mod:`.scip`), and
returns the proven lower bound, the best state and the gap; where the gap
closes, ``lambda`` is the global minimum of the non-associative problem (to
the MIP gap). Every big-M bound is provable (:mod:`.bounds`), and every
returned state is rebuilt by two LPs from its contact pattern and checked
against the collapse conditions (:mod:`.pattern`) before it is reported
(:mod:`.search`: one load direction). Options and results: :mod:`.global_types`.
Derivation and figures: ``docs/micro/global-search.md``. A reference tool
for small walls: the search closes on tens of blocks, not thousands.

The search is composed by its caller, not reached through the iterated LP's
options: ``solve_global(lp, start=result)`` starts from a finished
:class:`~micro.NonAssociativeResult` (its lowest certified states, else its
converged states). The iterated LP knows nothing of this package; this
package reads the iterated LP's result types only, and its patterns are
checked by :func:`micro.nonassociative.final_checks.state_residuals`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Literal

from micro.geometry import BlockWall
from micro.global_search.global_types import (
    INFEASIBLE,
    NODE_LIMIT,
    NODE_WORK,
    OPTIMAL,
    SOLVER_ERROR,
    SOLVERS,
    STATUSES,
    TIME_LIMIT,
    GlobalDirection,
    GlobalExtras,
    GlobalOptions,
    GlobalResult,
    StartState,
    default_node_limit,
    relative_gap,
)
from micro.global_search.search import Incumbent, search_direction
from micro.limit_result import direction_sign
from micro.lp import LimitLP, assemble
from micro.nonassociative.nonassociative_result import NonAssociativeResult

__all__ = [
    "INFEASIBLE",
    "NODE_LIMIT",
    "NODE_WORK",
    "OPTIMAL",
    "SOLVER_ERROR",
    "SOLVERS",
    "STATUSES",
    "TIME_LIMIT",
    "GlobalDirection",
    "GlobalExtras",
    "GlobalOptions",
    "GlobalResult",
    "StartState",
    "default_node_limit",
    "relative_gap",
    "solve_global",
    "starts_from",
]
_DIR_NAME = {1: "+x", -1: "-x"}


def solve_global(wall_or_lp: BlockWall | LimitLP, direction: Literal[1, -1, "both", "auto"] = "auto",
                 options: GlobalOptions | None = None,
                 start: StartState | Sequence[StartState] | NonAssociativeResult | None = None) -> GlobalResult:
    """Least collapse load factor with non-associative friction, with a proof.

    Args:
        wall_or_lp: the wall, or its assembled LP.
        direction: ``+1``, ``-1``, ``"both"`` or ``"auto"`` (both unless the
            wall is mirror-symmetric).
        options: :class:`GlobalOptions` (default: the defaults).
        start: a known collapse state of one direction (or one state per
            direction): its contact pattern is rebuilt into an exact state,
            handed to HiGHS as the first incumbent, and its load factor
            bounds the search. A :class:`~micro.NonAssociativeResult` of
            the same wall gives its states (:func:`starts_from`), and with
            ``direction="auto"`` its directions.

    Returns:
        The :class:`GlobalResult`.

    Raises:
        ValueError: a bad argument (the message names it).

    Examples:
        On a wall of five blocks a node limit stops the search the same way
        on every machine (a time limit would depend on the machine):

        >>> import micro
        >>> from micro.global_search import GlobalOptions, solve_global
        >>> wall = micro.build_wall(length=2.0, block_length=1.0, block_height=0.5, rows=(2,),
        ...                         thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=0.6)
        >>> result = solve_global(wall, options=GlobalOptions(node_limit=100))
        >>> result.status, round(result.load_factor, 4), result.lower_bound <= result.load_factor
        ('node_limit', 0.6, True)

        Composed after the iterated LP, started from its states:

        >>> iterated = micro.solve_nonassociative(wall)
        >>> started = solve_global(micro.assemble(wall), start=iterated, options=GlobalOptions(node_limit=100))
        >>> started.load_factor <= iterated.load_factor + 1e-9
        True
    """
    opts = GlobalOptions() if options is None else options
    if not isinstance(opts, GlobalOptions):
        raise ValueError(f"options must be a GlobalOptions, got {type(opts).__name__}")
    t0 = time.perf_counter()
    lp = wall_or_lp if isinstance(wall_or_lp, LimitLP) else assemble(wall_or_lp)
    if isinstance(start, NonAssociativeResult):
        if direction == "auto":
            direction = "both" if len(start.directions) > 1 else 1 if start.directions[0].direction == "+x" else -1
        start = starts_from(lp, start)
    if direction in (1, -1):
        dirs: tuple[int, ...] = (int(direction),)
    elif direction == "both" or (direction == "auto" and not lp.wall.mirror_symmetric):
        dirs = (1, -1)
    elif direction == "auto":
        dirs = (1,)
    else:
        raise ValueError(f"direction must be 1, -1, 'both' or 'auto', got {direction!r}")
    starts = () if start is None else (start,) if isinstance(start, StartState) else tuple(start)
    for st in starts:
        if st.direction not in (1, -1):
            raise ValueError(f"start.direction must be 1 or -1, got {st.direction!r}")
    by_dir = {st.direction: st for st in starts}
    results = tuple(_direction(lp, d, opts, by_dir.get(d)) for d in dirs)
    return _combine(results, opts, time.perf_counter() - t0)


def starts_from(lp: LimitLP, result: NonAssociativeResult) -> list[StartState]:
    """The start states a finished iterated LP gives: the lowest certified state
    of each direction, else the direction's converged state (none for a
    direction that did not converge).

    Args:
        lp: the LP of the wall ``result`` was solved on.
        result: :func:`micro.solve_nonassociative`'s result.
    """
    starts = [StartState.from_iterated(lp, low.state) for low in result.lowest if low.state is not None]
    have = {st.direction for st in starts}
    return starts + [StartState.from_iterated(lp, r) for r in result.directions
                     if r.converged and direction_sign(r.direction) not in have]


def _direction(lp: LimitLP, d: int, opts: GlobalOptions, start: StartState | None) -> GlobalDirection:
    """One load direction: search, then report in the result's shape."""
    t0 = time.perf_counter()
    inc = None
    if start is not None:
        inc = Incumbent.from_state(lp, d, start.velocities)
    out = search_direction(lp, d, opts, inc)
    st = out.state
    lam = st.load_factor if st is not None else math.nan
    return GlobalDirection(
        direction=_DIR_NAME[d], status=out.status, load_factor=lam, lower_bound=out.lower_bound,
        gap=relative_gap(lam, out.lower_bound), normal=None if st is None else st.n,
        shear=None if st is None else st.s, mechanism=None if st is None else st.mechanism(lp, d),
        pattern=None if st is None else st.pattern, pattern_band=out.band, residuals=out.residuals,
        bounds=out.bounds, binaries=out.binaries, node_limit=out.node_limit, nodes=out.nodes,
        mip_seconds=out.mip_seconds,
        seconds=time.perf_counter() - t0, start_load_factor=math.nan if inc is None else inc.load_factor,
        message=out.message)


def _combine(results: tuple[GlobalDirection, ...], opts: GlobalOptions, seconds: float) -> GlobalResult:
    """The summary over the directions."""
    found = [r for r in results if math.isfinite(r.load_factor)]
    best = min(found, key=lambda r: r.load_factor) if found else None
    bounds = [r.lower_bound for r in results]
    lb = math.nan if any(math.isnan(b) for b in bounds) else min(bounds)
    lam = best.load_factor if best is not None else math.nan
    failing = [r for r in results if r.status not in (OPTIMAL, INFEASIBLE)]
    # every direction closed: optimal unless no direction has a collapse state
    closed = OPTIMAL if best is not None else INFEASIBLE
    status = failing[0].status if failing else closed
    msg = "; ".join(f"{r.direction}: {r.message}" for r in results if r.message and r.status != OPTIMAL)
    return GlobalResult(status, lam, lb, relative_gap(lam, lb), best.direction if best else "", results, opts,
                        seconds, msg)

