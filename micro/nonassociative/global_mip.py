"""Proven global minimum of the non-associative collapse load (mixed-integer search).

With non-associative (zero-dilatancy) friction the collapse load factor is
not unique: the iterated LP (:mod:`micro.nonassociative`) returns one exact
collapse state, a local answer. :func:`solve_global` writes the collapse
conditions with binary contact states (:mod:`micro.nonassociative.global_model`), minimises
``lambda`` with HiGHS' branch and bound, and returns the proven lower bound,
the best state and the gap; where the gap closes, ``lambda`` is the global
minimum of the non-associative problem (to the MIP gap). Every big-M bound is
provable (:mod:`micro.nonassociative.global_bounds`), and every returned state is rebuilt by
two LPs from its contact pattern and checked against the collapse conditions
(:mod:`micro.nonassociative.global_pattern`) before it is reported. Derivation and figures:
``docs/micro/global-search.md``. A reference tool for small walls: the search
closes on tens of blocks, not thousands.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall
from micro.lp import LimitLP, assemble
from micro.mechanism import Mechanism
from micro.nonassociative import global_scip
from micro.nonassociative.global_bounds import POLICIES, BigM
from micro.nonassociative.global_pattern import Pattern
from micro.nonassociative.global_search import Incumbent, search_direction
from micro.records import json_number

FloatArray = NDArray[np.float64]

#: Values of ``status``.
OPTIMAL, TIME_LIMIT, NODE_LIMIT = "optimal", "time_limit", "node_limit"
INFEASIBLE, SOLVER_ERROR = "infeasible", "solver_error"
STATUSES = (OPTIMAL, TIME_LIMIT, NODE_LIMIT, INFEASIBLE, SOLVER_ERROR)
_DIR_NAME = {1: "+x", -1: "-x"}
#: Values of ``GlobalOptions.solver``.
SOLVERS = ("highs", "scip")


@dataclass(frozen=True)
class GlobalOptions:
    """Options of the global search.

    Attributes:
        time_limit: seconds of branch and bound per load direction (``None``:
            none). A search stopped by it reports ``time_limit`` with its
            bound and best state; such numbers depend on the machine.
        node_limit: branch-and-bound nodes per direction (``None``: none);
            unlike the time limit it gives the same answer on every machine.
        mip_gap: relative gap ``(lambda - bound) / lambda`` at which the
            search stops as ``optimal``.
        bounds: big-M policy for the normal forces: ``"per_point"`` (an LP
            per contact point) or ``"uniform"`` (one LP for all points).
        energy_cut: add the valid inequality ``lift <= lambda_up * live work``.
        seed: the solver's random seed (the search is deterministic for a seed).
        log: print the solver's log.
        solver: ``"highs"`` (default) or ``"scip"`` (the same model, solved by
            SCIP; needs ``pyscipopt``, the optional extra ``global``).
    """

    time_limit: float | None = 300.0
    node_limit: int | None = None
    mip_gap: float = 1e-7
    bounds: Literal["per_point", "uniform"] = "per_point"
    energy_cut: bool = True
    seed: int = 0
    log: bool = False
    solver: Literal["highs", "scip"] = "highs"

    def __post_init__(self) -> None:
        t = self.time_limit
        if t is not None and (isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t) or t <= 0):
            raise ValueError(f"time_limit must be a positive number, got {t!r}")
        n = self.node_limit
        if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n <= 0):
            raise ValueError(f"node_limit must be a positive integer, got {n!r}")
        g = self.mip_gap
        if isinstance(g, bool) or not isinstance(g, (int, float)) or not (0.0 <= g < 1.0):
            raise ValueError(f"mip_gap must be in [0, 1), got {g!r}")
        if self.bounds not in POLICIES:
            raise ValueError(f"bounds must be one of {', '.join(POLICIES)}, got {self.bounds!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"seed must be zero or a positive integer, got {self.seed!r}")
        if self.solver not in SOLVERS:
            raise ValueError(f"solver must be one of {', '.join(SOLVERS)}, got {self.solver!r}")
        if self.solver == "scip" and not global_scip.available():
            raise ValueError("solver 'scip' needs pyscipopt: pip install 'xcheck-masonry[global]'")


@dataclass(frozen=True, eq=False)
class StartState:
    """A known collapse state, given to the search as its first incumbent.

    Attributes:
        direction: ``+1`` or ``-1``.
        normal, shear: point forces in the LP's scaled units
            (dimensional forces divided by :attr:`micro.LimitLP.force_scale`).
        load_factor: its ``lambda``.
        velocities: ``(3 n_blocks,)`` or ``(n_blocks, 3)`` block velocities.
    """

    direction: int
    normal: FloatArray = field(repr=False)
    shear: FloatArray = field(repr=False)
    load_factor: float
    velocities: FloatArray = field(repr=False)

    @classmethod
    def from_iterated(cls, lp: LimitLP, result: Any) -> StartState:
        """The final state of one direction of the iterated LP.

        Args:
            lp: the LP of the wall.
            result: a converged direction of ``micro.solve_nonassociative``
                (a ``micro.DirectionResult``, read through its public fields
                ``direction``, ``normal``, ``shear``, ``mechanism`` and
                ``sequence.last_load_factor``).

        Raises:
            ValueError: the direction has no final state.
        """
        if result.normal is None or result.shear is None or result.mechanism is None:
            raise ValueError(f"direction {result.direction} has no final state ({result.status})")
        seq = getattr(result, "sequence", None)
        lam = float(seq.last_load_factor if seq is not None else result.load_factor)
        return cls(1 if result.direction == "+x" else -1, np.asarray(result.normal) / lp.force_scale,
                   np.asarray(result.shear) / lp.force_scale, lam,
                   np.asarray(result.mechanism.velocities, dtype=float).ravel())


@dataclass(frozen=True, eq=False)
class GlobalDirection:
    """The global search in one load direction (scaled units).

    Attributes:
        direction: ``"+x"`` or ``"-x"``.
        status: one of :data:`STATUSES`.
        load_factor: ``lambda`` of the best verified collapse state (NaN if none).
        lower_bound: proven lower bound of every collapse load factor
            (``inf`` when no collapse state exists below the associative load).
        gap: ``(load_factor - lower_bound) / |load_factor|`` (NaN without a state).
        normal, shear: forces of the best state, or ``None``.
        mechanism: its mechanism (unit live-load work), or ``None``.
        pattern: its contact pattern, or ``None``.
        pattern_band: least and greatest ``lambda`` over the force fields of
            that pattern (any of them forms a collapse state with the mechanism).
        residuals: its check (:func:`micro.nonassociative.global_pattern.collapse_residuals`).
        bounds: the big-M bounds used, or ``None``.
        binaries: binary columns of the model.
        nodes: branch-and-bound nodes.
        mip_seconds: time of the branch and bound.
        seconds: time of the whole direction (bounds, model, search, checks).
        start_load_factor: ``lambda`` of the start state rebuilt from its
            pattern (NaN without a usable start).
        message: a one-line explanation.
    """

    direction: str
    status: str
    load_factor: float
    lower_bound: float
    gap: float
    normal: FloatArray | None = field(repr=False)
    shear: FloatArray | None = field(repr=False)
    mechanism: Mechanism | None = field(repr=False)
    pattern: Pattern | None = field(repr=False)
    pattern_band: tuple[float, float] | None
    residuals: dict[str, float] = field(repr=False)
    bounds: BigM | None = field(repr=False)
    binaries: int
    nodes: int
    mip_seconds: float
    seconds: float
    start_load_factor: float
    message: str = ""


@dataclass(frozen=True, eq=False)
class GlobalResult:
    """The global search over the load directions solved.

    Attributes:
        status: :data:`OPTIMAL` when every direction closed, else the status
            of the first that did not.
        load_factor: least verified ``lambda`` over the directions (NaN if none).
        lower_bound: least lower bound over the directions.
        gap: ``(load_factor - lower_bound) / |load_factor|``.
        direction: the direction of ``load_factor`` (``""`` if none).
        directions: per-direction results.
        options: the options used.
        seconds: total time.
        message: explanation when not optimal.
    """

    status: str
    load_factor: float
    lower_bound: float
    gap: float
    direction: str
    directions: tuple[GlobalDirection, ...] = field(repr=False)
    options: GlobalOptions
    seconds: float
    message: str = ""


def relative_gap(value: float, bound: float) -> float:
    """``max(value - bound, 0) / |value|`` (NaN when either is not finite)."""
    if not (math.isfinite(value) and math.isfinite(bound)):
        return math.nan
    return max(value - bound, 0.0) / max(abs(value), 1e-12)


def solve_global(wall_or_lp: BlockWall | LimitLP, direction: Literal[1, -1, "both", "auto"] = "auto",
                 options: GlobalOptions | None = None,
                 start: StartState | Sequence[StartState] | None = None) -> GlobalResult:
    """Least collapse load factor with non-associative friction, with a proof.

    Args:
        wall_or_lp: the wall, or its assembled LP.
        direction: ``+1``, ``-1``, ``"both"`` or ``"auto"`` (both unless the
            wall is mirror-symmetric).
        options: :class:`GlobalOptions` (default: the defaults).
        start: a known collapse state of one direction (or one state per
            direction): its contact pattern is rebuilt into an exact state,
            handed to HiGHS as the first incumbent, and its load factor
            bounds the search.

    Returns:
        The :class:`GlobalResult`.

    Raises:
        ValueError: a bad argument (the message names it).
    """
    opts = GlobalOptions() if options is None else options
    if not isinstance(opts, GlobalOptions):
        raise ValueError(f"options must be a GlobalOptions, got {type(opts).__name__}")
    t0 = time.perf_counter()
    lp = wall_or_lp if isinstance(wall_or_lp, LimitLP) else assemble(wall_or_lp)
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
        bounds=out.bounds, binaries=out.binaries, nodes=out.nodes, mip_seconds=out.mip_seconds,
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


def global_summary(result: GlobalResult) -> dict[str, Any]:
    """The JSON keys of the global search (NaN and infinities as ``None``).

    Returns:
        ``global_load_factor``, ``global_lower_bound``, ``global_gap``,
        ``global_status``, and beside them ``global_direction``,
        ``global_nodes`` and ``global_seconds``.
    """
    return {
        "global_load_factor": json_number(result.load_factor),
        "global_lower_bound": json_number(result.lower_bound),
        "global_gap": json_number(result.gap),
        "global_status": result.status,
        "global_direction": result.direction,
        "global_nodes": sum(r.nodes for r in result.directions),
        "global_seconds": result.seconds,
    }


def global_fields(result: GlobalResult | None) -> dict[str, Any]:
    """The record fields of the global search (:class:`micro.NonAssociativeRecord`):
    ``global_load_factor``, ``global_lower_bound``, ``global_gap`` and
    ``global_status`` (NaN and ``""`` when there was no search)."""
    if result is None:
        return {"global_load_factor": math.nan, "global_lower_bound": math.nan, "global_gap": math.nan,
                "global_status": ""}
    return {"global_load_factor": result.load_factor, "global_lower_bound": result.lower_bound,
            "global_gap": result.gap, "global_status": result.status}
