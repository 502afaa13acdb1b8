"""The global search's types: its options, a contact pattern, the big-M bounds, the results.

A types module: it imports no module of the search (:mod:`~micro.global_search`
computes; this module only describes what goes in and comes out).
"""

from __future__ import annotations

import importlib.util
import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from micro.backends.base import check_integer, finite_real
from micro.columns import FlatRecord, Seconds, column, record_of
from micro.lp import LimitLP
from micro.mechanism import Mechanism

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Values of ``status``.
OPTIMAL, TIME_LIMIT, NODE_LIMIT = "optimal", "time_limit", "node_limit"
INFEASIBLE, SOLVER_ERROR = "infeasible", "solver_error"
STATUSES = (OPTIMAL, TIME_LIMIT, NODE_LIMIT, INFEASIBLE, SOLVER_ERROR)
#: Values of ``GlobalOptions.solver``.
SOLVERS = ("highs", "scip")

#: Big-M policies for the normal forces (:attr:`GlobalOptions.bounds`).
POLICIES = ("per_point", "uniform")

#: The default budget of the branch and bound, in nodes times binaries per direction: a node's LP grows
#: with the model (0.6 ms of CPU a node on a 10-block wall of 80 binaries, 6 ms on Set 12's 536), so that
#: nodes times binaries is about the work. 1.6 million: 20,000 nodes on ten blocks (about 13 s of CPU),
#: 2,985 on Set 12 (its root 2.4 s and 6 ms a node: about 20 s). A count of nodes, not seconds: the same
#: answer on every machine, busy or quiet (``docs/micro/global-search.md``).
NODE_WORK = 1_600_000
#: The default budget's bounds in nodes per direction: at least the root and a few branchings, at most
#: what the walls that close ever needed (a 9-block wall closed in 18,693 nodes) with room to spare.
MIN_NODES, MAX_NODES = 20, 100_000


def default_node_limit(binaries: int) -> int:
    """The default node budget of one direction of a model of ``binaries`` binary columns:
    :data:`NODE_WORK` over ``binaries``, within [:data:`MIN_NODES`, :data:`MAX_NODES`]."""
    return int(min(MAX_NODES, max(MIN_NODES, NODE_WORK // max(int(binaries), 1))))


def scip_available() -> bool:
    """True when ``pyscipopt`` is installed (the optional extra ``global``)."""
    return importlib.util.find_spec("pyscipopt") is not None


@dataclass(frozen=True)
class GlobalOptions:
    """Options of the global search.

    Attributes:
        direction_time_limit: seconds of branch and bound per load direction, a limit the user gives
            (``None``, the default: none, the clock decides nothing). A search stopped by it reports
            ``time_limit`` with its bound and best state, and says that they depend on the machine.
            Named apart from the iterated LP's ``time_limit`` (seconds per LP): one meaning per name.
        node_limit: branch-and-bound nodes per direction: the budget that decides where the search
            stops (``None``, the default: :func:`default_node_limit` of the model, :data:`NODE_WORK`
            over its binaries). A count, so that the same command gives the same status, bound and
            state on a busy machine and on a quiet one.
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

    direction_time_limit: float | None = None
    node_limit: int | None = None
    mip_gap: float = 1e-7
    bounds: Literal["per_point", "uniform"] = "per_point"
    energy_cut: bool = True
    seed: int = 0
    log: bool = False
    solver: Literal["highs", "scip"] = "highs"

    def __post_init__(self) -> None:
        t = self.direction_time_limit
        if t is not None and ((x := finite_real(t)) is None or x <= 0):
            raise ValueError(f"direction_time_limit must be a positive number, got {t!r}")
        if self.node_limit is not None:
            check_integer("node_limit", self.node_limit, 1)
        g = self.mip_gap
        if (x := finite_real(g)) is None or not (0.0 <= x < 1.0):
            raise ValueError(f"mip_gap must be in [0, 1), got {g!r}")
        if self.bounds not in POLICIES:
            raise ValueError(f"bounds must be one of {', '.join(POLICIES)}, got {self.bounds!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"seed must be zero or a positive integer, got {self.seed!r}")
        if self.solver not in SOLVERS:
            raise ValueError(f"solver must be one of {', '.join(SOLVERS)}, got {self.solver!r}")
        if self.solver == "scip" and not scip_available():
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
class BigM:
    """The bounds used by one global search (scaled units).

    Attributes:
        normal: ``N_p``, the bound on the normal force of every point.
        lambda_lower: lower bound of the load factor (column bound).
        lambda_upper: upper bound of the load factor (a known collapse
            state's, else the associative load factor).
        associative: largest statically admissible load factor (the
            associative limit load) in this direction.
        lift_nonnegative: no admissible mechanism lowers the dead load (so
            ``lambda >= 0`` and ``lift <= lambda_upper * live work`` hold).
        policy: ``"per_point"`` or ``"uniform"``.
        lps: LPs solved for the bounds.
        seconds: their time.
    """

    normal: FloatArray = field(repr=False)
    lambda_lower: float
    lambda_upper: float
    associative: float
    lift_nonnegative: bool
    policy: str
    lps: int
    seconds: float


@dataclass(frozen=True, eq=False)
class Pattern:
    """Which points may open and in which sense each interface may slip.

    Attributes:
        opening: ``(P,)`` True where the point may open (its ``n`` is 0).
        slip: ``(C,)`` ``0`` (sticks), ``+1`` or ``-1`` per interface.
    """

    opening: BoolArray = field(repr=False)
    slip: IntArray = field(repr=False)

    @classmethod
    def from_rates(cls, opening_rate: FloatArray, slip_rate: FloatArray, tol: float) -> Pattern:
        """The pattern a mechanism follows: rates above ``tol`` count.

        Args:
            opening_rate: ``(P,)`` ``B_n^T v``.
            slip_rate: ``(P,)`` ``B_s^T v`` (one value per interface is read,
                the larger in magnitude of its two points).
            tol: rates at most ``tol`` in magnitude count as zero.
        """
        s2 = np.asarray(slip_rate).reshape(-1, 2)
        pick = np.where(np.abs(s2[:, 0]) >= np.abs(s2[:, 1]), s2[:, 0], s2[:, 1])
        slip = np.where(pick > tol, 1, np.where(pick < -tol, -1, 0)).astype(np.int64)
        return cls(np.asarray(opening_rate) > tol, slip)


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
        residuals: its check (:func:`micro.global_search.pattern.collapse_residuals`).
        bounds: the big-M bounds used, or ``None``.
        binaries: binary columns of the model.
        node_limit: the node budget it ran under (:attr:`GlobalOptions.node_limit`, or the default of
            the model's size).
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
    node_limit: int
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

    @property
    def nodes(self) -> int:
        """Branch-and-bound nodes over the directions."""
        return sum(d.nodes for d in self.directions)

    def extras(self) -> dict[str, Any]:
        """The JSON keys the search adds to a summary beside the record's ``global_*`` (:class:`GlobalExtras`)."""
        return record_of(GlobalExtras, self).to_dict()


def relative_gap(value: float, bound: float) -> float:
    """``max(value - bound, 0) / |value|`` (NaN when either is not finite)."""
    if not (math.isfinite(value) and math.isfinite(bound)):
        return math.nan
    return max(value - bound, 0.0) / max(abs(value), 1e-12)


@dataclass(frozen=True)
class GlobalExtras(FlatRecord):
    """The keys a global search adds to a summary beside the record's ``global_*`` fields
    (:class:`micro.NonAssociativeRecord`, read from the search by ``result.to_record(search=g)``)."""

    global_direction: str = column("--global: the direction of its best state.", source="direction")
    global_nodes: int = column("--global: branch-and-bound nodes over the directions.", source="nodes")
    global_seconds: Seconds = column("--global: the search's time.", source="seconds")


