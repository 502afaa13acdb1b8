"""Result types of the iterated LP: one LP's record, a direction's diagnostics, the analysis (types
only: this module imports no module that computes them). The descent's own type, the lowest state of
a direction, is :mod:`micro.nonassociative.descent.lowest_direction`'s."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol

from micro.columns import FlatRecord, LoadFactor, Seconds, column, record_of
from micro.limit_result import DirectionResult, RecordSources
from micro.mechanism import Mechanism
from micro.nonassociative.config import Resolved
from micro.nonassociative.descent.lowest_direction import (
    DescentEntry,
    DescentSummary,
    LowestDirection,
    descent_summary,
)
from micro.records import IteratedDirection, NonAssociativeRecord, check_success


class ComposedSearch(Protocol):
    """What a record reads of a search composed after the run (:class:`micro.GlobalResult`; the method
    does not import the search: it is started from the result)."""

    @property
    def load_factor(self) -> float:
        """Its best verified lambda."""

    @property
    def lower_bound(self) -> float:
        """Its proven lower bound."""

    @property
    def gap(self) -> float:
        """``(load_factor - lower_bound) / load_factor``."""

    @property
    def status(self) -> str:
        """How it ended."""

    def extras(self) -> dict[str, Any]:
        """The keys the search adds to a summary."""
        ...

#: Values of ``status``. ``max_iterations``: the cap on LPs or the work budget
#: (simplex iterations) spent; ``time_limit``: stopped by a user's wall-clock
#: stop (``max_seconds``, ``time_limit``), so no final answer.
CONVERGED, CYCLING, MAX_ITERATIONS, SOLVER_FAILURE = "converged", "cycling", "max_iterations", "solver_failure"
TIME_LIMIT = "time_limit"
STATUSES = (CONVERGED, CYCLING, MAX_ITERATIONS, TIME_LIMIT, SOLVER_FAILURE)
#: Stop reasons that count as converged.
CONVERGED_STOPS = ("lambda_and_forces", "lambda_and_coulomb", "certified")
Band = tuple[float, float]


@dataclass(frozen=True)
class IterationRecord(FlatRecord):
    """One LP of the sequence, an entry of the summary's ``history`` (each field's meaning: its declaration)."""

    iteration: int = column("0 for the associative LP, then 1, 2, ...")
    load_factor: LoadFactor = column("lambda of this LP (null if it failed).")
    lambda_change: float = column("|lambda_k - lambda_(k-1)| / |lambda_k| (null for the first LP).")
    max_dn: float = column("max |n_k - n_(k-1)| relative to max n_k (null for the first LP).")
    coulomb_residual: float = column("max(|s_k| - mu n_k, 0) relative to max n_k.")
    alpha: float = column("The slope parameter of scheme (b) (0 for scheme (a) and the first LP).")
    simplex_iterations: int = column("Simplex iterations of this LP.")
    ipm_iterations: int = column("Interior-point iterations of this LP.")
    seconds: Seconds = column("Wall time of the solve (and of the model update before it).")
    algorithm: str = column(
        "clarabel, ipm, ipm+crossover+simplex, simplex-warm, simplex-warm-unrelaxed, fallback-a or ipm-restart "
        "(after a failed warm run).")
    status: str = column("The LP's status (a micro.Status value).")
    certificate: str = column(
        "certified, not found (no collapse state at this lambda with this LP's mechanism, or the try hit its "
        "time limit), or empty when not attempted; coulomb_residual is then that of the certified field.",
        default="")
    certificate_seconds: Seconds = column("The certificate's time.", default=0.0)
    certificate_iterations: int = column("The certificate's interior-point iterations.", default=0)
    proximal_step: float = column(
        "The proximal selection's |n - nbar|_1 / |nbar|_1 of the projection that gave this LP's nbar (its QP's "
        "time is in seconds); null for the other selections, the first LP and an unsolved QP.", default=math.nan)


@dataclass(frozen=True)
class FusionDiagnostics:
    """How a sequence ran on the fused wall (:mod:`micro.nonassociative.pipeline`).

    Attributes:
        bodies: moving bodies of the fused LP.
        single_bodies: of them, bodies of one block.
        blocks_at_rest: blocks fused into the ground.
        points: contact points of the fused LP.
        wall_points: contact points of the wall.
        rigid_tol: a contact was rigid below this fraction of the largest rate.
        seconds: the associative LP and the fusion.
        wall_certificate: ``"certified"`` (the state extends to the whole
            wall), ``"rejected"``, or ``""`` (not tried: the fused sequence
            did not converge).
        certificate_seconds: that certificate's LPs.
    """

    bodies: int
    single_bodies: int
    blocks_at_rest: int
    points: int
    wall_points: int
    rigid_tol: float
    seconds: float
    wall_certificate: str = ""
    certificate_seconds: float = 0.0


@dataclass(frozen=True)
class SequenceDiagnostics:
    """What the iterated LP adds to a :class:`~micro.limit_result.DirectionResult`.

    Attributes:
        stop_reason: what stopped the sequence (``"lambda_and_forces"``,
            ``"lambda_and_coulomb"``, ``"certified"``, ``"repeating"``,
            ``"oscillating"``, ``"stagnation"``, ``"max_iterations"``,
            ``"work_budget"``, ``"time_budget"`` (``max_seconds``),
            ``"time_limit"`` (an LP's ``time_limit``), ``"lp_failed"``, ``"cold_check_failed"``,
            ``"equilibrium_residual"``, ``"associative_failed"``,
            ``"fused_state_rejected"``).
        last_load_factor: ``lambda`` of the last successful iterate.
        lambda_band: ``(min, max)`` of ``lambda`` over the detected cycle or
            the last window (``None`` when converged).
        mechanism_band: ``(min, max)`` of ``lambda`` over ALL collapse
            states with the final mechanism (certified runs, and converged
            scheme (a) runs; ``None`` otherwise, also when a certified state
            then failed a final check): the non-associative problem
            has many solutions, and the same mechanism can form at any load
            factor in this band.
        associative_load_factor: ``lambda`` of the associative LP.
        history: every LP, the associative one first.
        cold_load_factor: ``lambda`` of the final iterate re-solved cold
            (NaN unless the sequence stopped exactly:
            :data:`~micro.nonassociative.final_checks.COLD_CHECKED_STOPS`).
        warm_cold_rel_diff: ``|warm - cold| / |cold|`` (NaN likewise).
        cold_algorithm: ``"ipm"``, ``"simplex"`` (when IPX gave up) or
            ``"ipm+crossover+simplex"`` (when IPX disagreed).
        coulomb_residual: ``max(|s| - mu n, 0)`` with the final forces,
            relative to ``max n``.
        dilatancy_residual: largest ``|opening rate|`` at sliding points in
            contact (``n > 0``) of the final mechanism, relative to the
            largest slip rate.
        equilibrium_residual: largest equilibrium violation (block weights).
        sliding_points: points of the final mechanism that slide while in contact.
        fallback_steps: scheme (b) LPs replaced by a scheme (a) step.
        selection: how this sequence's iterates picked their forces,
            ``"vertex"`` or ``"proximal"``.
        vertex_attempt: with ``selection="vertex+proximal"``, the vertex
            sequence that ended cycling (or at its cap) before this proximal
            one ran (``None`` otherwise); its LPs count in the direction's
            ``iterations`` and ``seconds``.
        fusion: how the sequence ran on the fused wall (``resolved.fuse``;
            ``None``: on the wall itself). Its history is then the fused
            LP's; forces, residuals, the mechanism band and
            ``associative_load_factor`` (whose mechanism gave the bodies)
            are the wall's.
        unfused_attempt: the wall's own sequences (vertex, then
            proximal) that ended cycling or at their caps before this run
            on the fused wall with the continuation certified the direction
            (``tuning.fused_retry``; ``None`` otherwise); their LPs count
            in the direction's ``iterations`` and ``seconds``.
        reduced: the state is the reduced wall's (:mod:`micro.nonassociative.reduced`): the lowest of the
            wall's states that its models' mechanisms lifted, at the lower end of its band; its history is
            that of the model whose mechanism gave it, ``fusion`` that model's.
    """

    stop_reason: str
    last_load_factor: float
    lambda_band: Band | None
    mechanism_band: Band | None
    associative_load_factor: float
    history: tuple[IterationRecord, ...] = field(repr=False)
    cold_load_factor: float = math.nan
    warm_cold_rel_diff: float = math.nan
    cold_algorithm: str = ""
    coulomb_residual: float = math.nan
    dilatancy_residual: float = math.nan
    equilibrium_residual: float = math.nan
    sliding_points: int = 0
    fallback_steps: int = 0
    selection: str = "vertex"
    vertex_attempt: SequenceDiagnostics | None = field(default=None, repr=False)
    fusion: FusionDiagnostics | None = None
    unfused_attempt: SequenceDiagnostics | None = field(default=None, repr=False)
    reduced: bool = False


def diagnostics(d: DirectionResult) -> SequenceDiagnostics:
    """The iterated LP's diagnostics of a direction.

    Raises:
        ValueError: ``d`` is not a result of the iterated LP.
    """
    if not isinstance(d.sequence, SequenceDiagnostics):
        raise ValueError(f"direction {d.direction} is not a result of the iterated LP")
    return d.sequence


#: Values of :attr:`NonAssociativeResult.quoted`: which load factor to quote.
QUOTED_LOWEST, QUOTED_ITERATED = "lowest certified", "iterated"


@dataclass(frozen=True, eq=False)
class NonAssociativeResult(RecordSources):
    """Result of the non-associative analysis. The value to quote is :attr:`load_factor` (the lowest
    certified collapse state where the descent found one in every direction, else the iterated LP's
    value; which one is :attr:`quoted`); the iterated LP's own value is :attr:`iterated_load_factor`,
    its mechanism's band :attr:`mechanism_band`. The other properties describe the governing
    direction (:attr:`governing`): the iterated LP's direction with the smallest load factor, or the
    first that did not converge.

    Attributes:
        iterated_load_factor: the iterated LP's governing ``lambda`` (NaN unless every direction
            converged).
        direction: the iterated LP's governing direction (``""`` unless converged; the lowest
            state's is ``lowest_direction`` of the record).
        status: :data:`CONVERGED` only if every direction converged, else the
            status of the first direction that did not.
        scheme: ``"a"`` or ``"b"``.
        relaxation: ``beta``.
        blocks, contacts, points: sizes of the wall.
        variables, rows, nnz: sizes of the assembled associative LP.
        build_seconds: assembly of the LP.
        solve_seconds: all sequences, incl. cold checks.
        mirror_symmetric: one direction solved.
        directions: per-direction results (each with its ``sequence``).
        resolved: what ran: the options and their tuning, resolved for the wall
            (:class:`~micro.nonassociative.config.Resolved`).
        message: explanation when not converged.
        lowest: the lowest certified state of every converged direction
            (``lowest``; :mod:`micro.nonassociative.descent.lowest`).
    """

    iterated_load_factor: float
    direction: str
    status: str
    scheme: str
    relaxation: float
    blocks: int
    contacts: int
    points: int
    variables: int
    rows: int
    nnz: int
    build_seconds: float
    solve_seconds: float
    mirror_symmetric: bool
    directions: tuple[DirectionResult, ...] = field(repr=False)
    resolved: Resolved = field(repr=False)
    message: str = ""
    lowest: tuple[LowestDirection, ...] = field(default=(), repr=False)

    def __post_init__(self) -> None:
        check_success("NonAssociativeResult", self.status, self.iterated_load_factor)

    @property
    def converged(self) -> bool:
        """``status == "converged"``."""
        return self.status == CONVERGED

    @property
    def ok(self) -> bool:
        """True when converged with a finite load factor (then :attr:`load_factor` is finite too)."""
        return self.converged and math.isfinite(self.iterated_load_factor)

    @property
    def governing(self) -> DirectionResult:
        """The direction the summary fields come from."""
        for d in self.directions:
            if d.direction == self.direction:
                return d
        for d in self.directions:
            if not d.converged:
                return d
        return self.directions[0]

    @property
    def sequence(self) -> SequenceDiagnostics:
        """The governing direction's diagnostics."""
        return diagnostics(self.governing)

    @property
    def iterations(self) -> int:
        """Non-associative LPs of the governing (or failing) direction."""
        return self.governing.iterations

    @property
    def total_iterations(self) -> int:
        """Non-associative LPs summed over the directions solved."""
        return sum(d.iterations for d in self.directions)

    @property
    def mechanism_band(self) -> Band | None:
        """``(min, max)`` of ``lambda`` over the collapse states with the
        governing direction's final mechanism (:class:`SequenceDiagnostics`)."""
        return self.sequence.mechanism_band

    @property
    def associative_load_factor(self) -> float:
        """Smallest associative ``lambda`` over the directions solved."""
        return min((diagnostics(d).associative_load_factor for d in self.directions), default=math.nan)

    @property
    def lowest_state(self) -> LowestDirection | None:
        """The lowest certified state over the directions (``None`` unless
        the run converged and every direction has one): the load factor a
        safety assessment should quote (docs/micro/nonassociative.md, "Which value to quote")."""
        found = [low for low in self.lowest if low.found]
        if not self.converged or not found or len(found) < len(self.directions):
            return None
        return min(found, key=lambda low: low.load_factor)

    @property
    def lowest_load_factor(self) -> float:
        """``lambda`` of :attr:`lowest_state` (NaN without one); never above :attr:`iterated_load_factor`."""
        low = self.lowest_state
        return low.load_factor if low is not None else math.nan

    @property
    def quoted(self) -> str:
        """Which value :attr:`load_factor` is: :data:`QUOTED_LOWEST`, else :data:`QUOTED_ITERATED`
        (``""``: failed)."""
        return "" if not self.ok else QUOTED_LOWEST if self.lowest_state is not None else QUOTED_ITERATED

    @property
    def load_factor(self) -> float:
        """The load factor to quote (:attr:`quoted`): :attr:`lowest_load_factor` where the descent found a
        certified state in every direction, else :attr:`iterated_load_factor`; NaN when the run failed."""
        return math.nan if not self.ok else self.lowest_load_factor if self.lowest_state is not None \
            else self.iterated_load_factor

    def direction_load_factors(self) -> dict[str, float]:
        """The load factor of each direction solved, of the kind :attr:`load_factor` is: each
        direction's lowest certified state when the quoted value is the lowest, else its iterated
        LP's value (NaN where it did not converge); their minimum is :attr:`load_factor` when the
        run converged."""
        lowest = {low.direction: low.load_factor for low in self.lowest}
        use_lowest = self.quoted == QUOTED_LOWEST
        return {d.direction: lowest[d.direction] if use_lowest else d.load_factor for d in self.directions}

    @property
    def governing_mechanism(self) -> Mechanism | None:
        """The mechanism of the governing direction's state (``None`` without one)."""
        return self.governing.mechanism if self.governing is not None else None

    @property
    def solver(self) -> str:
        """Which solver did what in the iterated LP (:meth:`Resolved.solver_description`)."""
        return self.resolved.solver_description()

    @property
    def history_load_factor(self) -> tuple[float, ...]:
        """``lambda`` of every LP of the governing sequence, the associative one first."""
        return tuple(r.load_factor for r in self.sequence.history)

    @property
    def fallback_steps(self) -> int:
        """Scheme (b) LPs replaced by a scheme (a) step, over the directions solved."""
        return sum(diagnostics(d).fallback_steps for d in self.directions)

    @property
    def descent(self) -> DescentSummary:
        """The descent over the directions, as the record reads it (:class:`DescentSummary`)."""
        return descent_summary(self.lowest_state, self.lowest)

    def to_record(self, search: ComposedSearch | None = None) -> NonAssociativeRecord:
        """The flat record of this result: a read-only mapping of its fields; ``.to_dict()`` is its JSON form.
        Each field is read along its declared source (:mod:`micro.records`); ``search``: a global search
        composed after the run (:func:`micro.solve_global`), whose ``global_*`` fields it fills."""
        return record_of(NonAssociativeRecord, self, search=search)


    def summary(self, search: ComposedSearch | None = None) -> dict[str, Any]:
        """JSON-ready summary: the record (:meth:`to_record`) with the descent, options, history and
        directions as nested objects, each a record of its own (their schemas: :mod:`micro.schema`); a global
        search composed after the run (``search``) fills the record's ``global_*`` keys and adds its own
        (:class:`micro.global_search.GlobalExtras`) before ``options``. The contact states of the mechanism
        are the record's ``*_contacts`` keys (0 without one). Each entry of ``directions`` gives
        ``load_factor`` of the kind the wall's is (:meth:`direction_load_factors`) and the iterated LP's value
        beside it."""
        record = self.to_record(search).to_dict()
        by_direction = self.direction_load_factors()
        first = ("load_factor", "quoted", "iterated_load_factor", "mechanism_band", "lowest_load_factor",
                 "lowest_band", "lowest_stop")
        return {
            **{k: record[k] for k in first}, **record,
            "lowest": [record_of(DescentEntry, low).to_dict() for low in self.lowest],
            **({} if search is None else search.extras()),
            "options": self.resolved.as_dict(),
            "history": [r.to_dict() for r in self.sequence.history],
            "directions": {d.direction: record_of(IteratedDirection, d,
                                                  quoted_value=by_direction[d.direction]).to_dict()
                           for d in self.directions},
        }
