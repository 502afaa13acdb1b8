"""The records of the micro results: what a table, a cache or a report keeps of one analysis.

A record holds numbers, strings, bools and tuples of numbers, no arrays (forces and velocities stay on the
result objects). Each field is declared once, here, by :func:`~micro.columns.column` (:mod:`micro.columns`:
the record made from the result, its JSON form and its JSON schema all come from that declaration): its
type, its description, where the result holds its value (an attribute path, by default the field's own
name; every value a record holds is an attribute of the result, or of the global search composed after
it: ``result.to_record(search=g)``) and, where its type does not say enough, its schema. ``NaN`` is
allowed in memory (a failed number); the JSON form has ``null``, and ``from_dict(to_dict(r))`` gives the
record back. A diagnostic that a result already holds becomes a column with one line (docs/api.md,
"Records").

``iterations`` and ``total_iterations`` (both records):

* ``iterations``: the governing direction's count, or the first failing
  direction's when the analysis failed (solver iterations for the
  associative LP, non-associative LPs for the iterated scheme);
* ``total_iterations``: the sum over the directions solved.

Made by :meth:`micro.LimitResult.to_record` and
:meth:`micro.NonAssociativeResult.to_record`; the nested parts of a summary (the directions) are records
too (:class:`AssociativeDirection`, :class:`IteratedDirection`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from micro.columns import Band, FlatRecord, LoadFactor, Seconds, column

__all__ = [
    "SUCCESS_STATUSES",
    "AssociativeDirection",
    "AssociativeRecord",
    "IteratedDirection",
    "MicroRecord",
    "NonAssociativeRecord",
    "check_success",
]

#: The statuses of a micro analysis that report a load factor: the associative
#: LP's and the iterated LP's success. Every other status comes with NaN.
SUCCESS_STATUSES = ("optimal", "converged")


def check_success(owner: str, status: str, load_factor: float) -> None:
    """A success status must come with a finite load factor ``>= 0`` (the invariant of every micro result).

    Raises:
        ValueError: ``status`` is in :data:`SUCCESS_STATUSES` and ``load_factor``
            is NaN, infinite or negative (a bug of the analysis, never an answer).
    """
    if status in SUCCESS_STATUSES and not (math.isfinite(load_factor) and load_factor >= 0.0):
        raise ValueError(f"{owner}: status {status!r} needs a finite load factor >= 0, got {load_factor!r}")


@dataclass(frozen=True)
class MicroRecord(FlatRecord):
    """What every micro analysis reports (governing direction first); a read-only mapping of its fields.

    Each field's meaning is its :func:`column` declaration (``docs/schemas/micro.schema.json`` prints them).
    """

    load_factor: LoadFactor = column(
        "The lambda to quote, the smallest over the load directions: the associative LP's, or the "
        "non-associative lowest certified state where the descent found one in every direction, else the "
        "iterated LP's (quoted says which); null on failure.")
    status: str = column(
        "optimal (associative LP), converged (iterated LP), or the failing status; every other status comes "
        "with load_factor null.")
    solver: str = column("The back end, or which solver did what in the iterated LP.")
    direction: str = column(
        "The governing direction of the live load (non-associative: the iterated LP's; lowest_direction is the "
        "lowest state's); empty on failure.", schema={"enum": ["+x", "-x", ""]})
    load_factor_plus: LoadFactor = column(
        "lambda of the +x direction, of the kind load_factor is (non-associative: that direction's lowest "
        "certified state when load_factor is the lowest, else its iterated LP's value).")
    load_factor_minus: LoadFactor = column(
        "lambda of the -x direction, of the kind load_factor is (null when not solved, e.g. a "
        "mirror-symmetric wall).")
    blocks: int = column("Blocks of the wall.", schema={"minimum": 1})
    contacts: int = column("Interfaces between blocks, and between blocks and the ground.")
    points: int = column("Contact points (two per interface).")
    variables: int = column("Columns of the assembled associative LP.")
    rows: int = column("Rows of the assembled associative LP (three per block).")
    nnz: int = column("Nonzeros of the assembled associative LP.")
    iterations: int = column(
        "The governing (or first failing) direction's count: solver iterations (associative) or LPs "
        "(iterated LP).")
    total_iterations: int = column("The sum of iterations over the directions solved.")
    build_seconds: Seconds = column("Assembly of the LP (and the back end's setup).")
    solve_seconds: Seconds = column("Every solve.")
    mirror_symmetric: bool = column("One direction solved: the wall is its own mirror image.")
    closed_contacts: int = column(
        "Contacts of the governing mechanism that stay closed (0 without a mechanism, e.g. on failure).",
        source="mechanism_contacts.closed")
    opening_contacts: int = column("Contacts of the governing mechanism that open (0 without a mechanism).",
                                   source="mechanism_contacts.opening")
    sliding_contacts: int = column("Contacts of the governing mechanism that slide (0 without a mechanism).",
                                   source="mechanism_contacts.sliding")
    message: str = column("Why the analysis failed (empty on success).")

    def __post_init__(self) -> None:
        check_success(type(self).__name__, self.status, self.load_factor)

    @property
    def contact_states(self) -> dict[str, int]:
        """``{"closed": .., "opening": .., "sliding": ..}``."""
        return {"closed": self.closed_contacts, "opening": self.opening_contacts, "sliding": self.sliding_contacts}


@dataclass(frozen=True)
class AssociativeRecord(MicroRecord):
    """Record of :func:`micro.solve_associative` (fields: :class:`MicroRecord`)."""


_SEQ = "sequence."


@dataclass(frozen=True)
class NonAssociativeRecord(MicroRecord):
    """Record of :func:`micro.solve_nonassociative`.

    ``load_factor`` is the value to quote (``quoted`` says which), the iterated LP's own value is
    ``iterated_load_factor`` with its mechanism's band ``mechanism_band``. The iterated LP's fields
    describe its governing direction (the first direction that did not converge when the analysis
    failed), but ``fallback_steps``, summed over the directions. Each field's meaning is its
    :func:`column` declaration.
    """

    iterated_load_factor: LoadFactor = column(
        "The iterated LP's own lambda (its fixed point, the smallest over the directions), with its "
        "mechanism's band in mechanism_band; equal to load_factor when quoted is iterated; null on failure.")
    scheme: str = column("The rebuilt yield condition: scheme a or b.", schema={"enum": ["a", "b"]})
    relaxation: float = column("beta: nbar = beta n_k + (1 - beta) n_(k-1).",
                               schema={"type": "number", "exclusiveMinimum": 0, "maximum": 1})
    converged: bool = column("status is converged.")
    stop_reason: str = column(
        "What stopped the sequence: certified, lambda_and_forces, lambda_and_coulomb, repeating, oscillating, "
        "stagnation, max_iterations, work_budget, time_budget, time_limit, associative_failed, lp_failed, ...",
        source=_SEQ + "stop_reason")
    lambda_band: Band = column(
        "[min, max] of lambda over the cycle or the last window (null when converged).",
        source=_SEQ + "lambda_band")
    mechanism_band: Band = column(
        "[min, max] of lambda over the exact collapse states with the final mechanism (null when not computed, "
        "and whenever the status is not converged: a failed run has no exact collapse state).",
        source=_SEQ + "mechanism_band")
    last_load_factor: LoadFactor = column("lambda of the last successful LP.", source=_SEQ + "last_load_factor")
    associative_load_factor: LoadFactor = column(
        "The smallest associative lambda over the directions (an upper bound of every non-associative "
        "collapse state).")
    cold_load_factor: LoadFactor = column(
        "The final LP re-solved cold (null unless the sequence stopped exactly, not by the certificate).",
        source=_SEQ + "cold_load_factor")
    warm_cold_rel_diff: float = column("|warm - cold| / |cold| of the final LP (null likewise).",
                                       source=_SEQ + "warm_cold_rel_diff")
    coulomb_residual: float = column(
        "Of the final state: how far the forces are from Coulomb with their own normal forces, "
        "max(|s| - mu n, 0) / max n.", source=_SEQ + "coulomb_residual")
    dilatancy_residual: float = column(
        "Of the final state: the largest opening rate at sliding points in contact, relative to the largest "
        "slip rate.", source=_SEQ + "dilatancy_residual")
    history_load_factor: tuple[LoadFactor, ...] = column("lambda of every LP, the associative one first.")
    cold_algorithm: str = column("The algorithm of the cold re-solve (ipm, simplex, ipm+crossover+simplex).",
                                 source=_SEQ + "cold_algorithm")
    fallback_steps: int = column("Scheme (b) LPs replaced by a scheme (a) step, over the directions solved.")
    selection: str = column(
        "How the governing sequence's iterates picked their forces: the simplex's vertex, or nbar moved "
        "towards the closest field that carries the LP's load (proximal; by default after a vertex sequence "
        "that ended without a state).", source=_SEQ + "selection", schema={"enum": ["vertex", "proximal"]},
        default="vertex")
    vertex_stop_reason: str = column(
        "selection vertex+proximal: how the vertex sequence ended before the proximal one ran (empty when it "
        "did not run).", source=_SEQ + "vertex_attempt.stop_reason", default="")
    vertex_lambda_band: Band = column(
        "selection vertex+proximal: the vertex sequence's band of its last lambda values (null when the "
        "proximal sequence did not run).", source=_SEQ + "vertex_attempt.lambda_band", default=None)
    quoted: str = column("Which value load_factor is (empty on failure).",
                         schema={"enum": ["lowest certified", "iterated", ""]}, default="")
    lowest_load_factor: LoadFactor = column(
        "The lowest certified collapse state over the directions (the descent from the iterated LP's fixed "
        "point, on by default on every wall; every state verified exact); null when not run (--lowest off) or "
        "not found. The value a safety assessment should quote when the global search has not closed.",
        source="descent.load_factor", default=math.nan)
    lowest_direction: str = column("The direction of the lowest certified state (empty without one).",
                                   source="descent.direction", default="")
    lowest_band: Band = column(
        "[lowest_load_factor, greatest lambda] of the collapse states with its mechanism.",
        source="descent.band", default=None)
    lowest_moves: int = column("Moves between mechanisms that led to it.", source="descent.moves", default=0)
    lowest_lps: int = column("LPs of the descent, over the directions.", source="descent.lps", default=0)
    lowest_seconds: Seconds = column("Seconds of the descent, over the directions.", source="descent.seconds",
                                    default=0.0)
    lowest_status: str = column("found or failed (failed: some direction has no state); empty when the descent "
                                "did not run.", source="descent.status", default="",
                                schema={"enum": ["", "found", "failed"]})
    lowest_stop: str = column(
        "finished: every direction's descent ended by its own rules; budget: one spent its budget of LPs "
        "(--lowest-budget, LPs per direction) and gave the lowest certified state found so far; target: the "
        "search stopped at the first certified state below the options' stop_below (a compare whose macro "
        "lambda it refutes); empty when the descent did not run.", source="descent.stop", default="",
        schema={"enum": ["", "finished", "budget", "target"]})
    global_load_factor: LoadFactor = column(
        "--global: the best verified collapse state of the branch and bound (null when not run).",
        source="search.load_factor", default=math.nan)
    global_lower_bound: float = column("--global: its proven lower bound of every collapse load factor.",
                                       source="search.lower_bound", default=math.nan)
    global_gap: float = column("(global_load_factor - global_lower_bound) / global_load_factor.",
                               source="search.gap", default=math.nan)
    global_status: str = column(
        "empty (not run), optimal (the gap closed: global_load_factor is the global minimum), time_limit "
        "(stopped by --time-limit: depends on the machine), node_limit (stopped at its budget of nodes: the "
        "same on every machine), infeasible or solver_error.",
        source="search.status", default="")
    fused_bodies: int = column(
        "--fuse: moving bodies of the fused wall the iterated LP ran on (0: the wall itself).",
        source=_SEQ + "fusion.bodies", default=0)
    fused_points: int = column("--fuse: contact points of the fused wall (0: the wall itself).",
                               source=_SEQ + "fusion.points", default=0)
    reduced: bool = column(
        "The state is the reduced wall's: its sequences ran on models of the associative mechanism's rigid "
        "parts (fused_bodies: the model whose mechanism gave it) and its mechanism was lifted onto the wall "
        "(false: the wall's own sequences, or the fused wall with the continuation).",
        source=_SEQ + "reduced", default=False)
    unfused_stop_reason: str = column(
        "How the wall's own sequences ended before the fused wall with the continuation certified the "
        "governing direction (options.fused_retry; empty: it did not run).",
        source=_SEQ + "unfused_attempt.stop_reason", default="")

    def __post_init__(self) -> None:
        """A success comes with a finite value to quote and a finite iterated LP value (:func:`check_success`)."""
        super().__post_init__()
        check_success(f"{type(self).__name__} (iterated_load_factor)", self.status, self.iterated_load_factor)


@dataclass(frozen=True)
class AssociativeDirection(FlatRecord):
    """One load direction of an associative analysis, an entry of its summary's ``directions``."""

    load_factor: LoadFactor = column("This direction's lambda.")
    status: str = column("This direction's status (optimal, or the back end's failure in the shared terms).")
    native_status: str = column("The back end's own status.")
    iterations: int = column("The back end's iterations.")
    solve_seconds: Seconds = column("The solve.", source="seconds")


@dataclass(frozen=True)
class IteratedDirection(FlatRecord):
    """One load direction of the iterated LP, an entry of its summary's ``directions``; ``load_factor`` is of
    the kind the wall's is (:meth:`micro.NonAssociativeResult.direction_load_factors`, given as the root
    ``quoted_value``)."""

    status: str = column("This direction's status.")
    stop_reason: str = column("What stopped its sequence.", source="sequence.stop_reason")
    load_factor: LoadFactor = column(
        "This direction's lambda of the kind the wall's load_factor is: its lowest certified state when the "
        "wall's is the lowest, else its iterated LP's value.", source="quoted_value")
    iterated_load_factor: LoadFactor = column("This direction's iterated LP value.", source="load_factor")
    last_load_factor: LoadFactor = column("lambda of its last successful LP.", source="sequence.last_load_factor")
    associative_load_factor: LoadFactor = column("Its associative lambda.",
                                                 source="sequence.associative_load_factor")
    iterations: int = column("Its LPs.")
    seconds: Seconds = column("Its sequences' time.")
