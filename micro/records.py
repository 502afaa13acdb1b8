"""Flat records of the micro results: frozen dataclasses that read as mappings, with a JSON form.

A record holds what a table, a cache or a report needs of one analysis:
numbers, strings, bools and tuples of numbers, no arrays (forces and
velocities stay on the result objects). It is a read-only mapping of its
fields (``rec["lowest_stop"]``, ``rec.lowest_stop``, ``dict(rec)``, ``list(rec)``
give the field names in order). ``NaN`` is allowed in memory (a failed
number); :meth:`MicroRecord.to_dict` gives the JSON form (``None`` for NaN,
lists for tuples) and :meth:`MicroRecord.from_dict` reads it back, so
``from_dict(to_dict(r))`` gives the record back.

**One declaration per field.** Each field is declared once, here, by :func:`column`: its type, its
description, where the result holds its value (a dotted path from the result object, by default the
field's own name) and, where its type does not say enough, its JSON schema. From that one declaration
come the record a result makes (:func:`record_of`), its JSON form (the result cache stores it), the
summary printed by ``xcheck micro --json`` and the JSON schema that documents it
(:func:`record_schema`, written into ``docs/schemas/micro.schema.json``). A diagnostic that a result
already holds becomes a column with one :func:`column` line (docs/api.md, "Records").

``iterations`` and ``total_iterations`` (both records):

* ``iterations``: the governing direction's count, or the first failing
  direction's when the analysis failed (solver iterations for the
  associative LP, non-associative LPs for the iterated scheme);
* ``total_iterations``: the sum over the directions solved.

Made by :meth:`micro.LimitResult.to_record` and
:meth:`micro.NonAssociativeResult.to_record`.
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from collections.abc import Iterator, Mapping
from dataclasses import MISSING, dataclass
from typing import Any, Self

__all__ = [
    "GIVEN",
    "SUCCESS_STATUSES",
    "AssociativeRecord",
    "MicroRecord",
    "NonAssociativeRecord",
    "check_success",
    "column",
    "json_number",
    "record_of",
    "record_schema",
]

Band = tuple[float, float]

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


def json_number(value: float) -> float | None:
    """``value`` as a strict JSON number: a float, or ``None`` for NaN and the infinities (JSON has neither).

    The one NaN-to-null conversion of every micro summary and record.
    """
    value = float(value)
    return value if math.isfinite(value) else None


def _out(value: Any) -> Any:
    """JSON-ready: NaN and infinities -> None, tuples -> lists."""
    if isinstance(value, float):
        return json_number(value)
    if isinstance(value, tuple):
        return [_out(v) for v in value]
    return value


def _in(hint: Any, value: Any) -> Any:
    """The inverse of :func:`_out` for a field of type ``hint``."""
    args = typing.get_args(hint)
    optional = isinstance(hint, types.UnionType) and type(None) in args
    if value is None:
        return None if optional else (math.nan if hint is float else value)
    if optional:
        hint = next(a for a in args if a is not type(None))
        args = typing.get_args(hint)
    if typing.get_origin(hint) is tuple:
        return tuple(math.nan if v is None else float(v) for v in value)
    return float(value) if hint is float else value


#: :func:`column`'s ``source`` for a field the result does not hold under a path: its ``to_record``
#: passes the value (computed there), or the field keeps its default.
GIVEN = ""


def column(doc: str, *, source: str | None = None, schema: Mapping[str, Any] | None = None,
           default: Any = MISSING) -> Any:
    """Declare a record field: the one place its description, its source and its schema are written.

    Args:
        doc: what the field means, in a user's words: the JSON schema's description and the docs' line.
        source: where the result holds the value, a dotted path of attributes from the result object
            (``"sequence.stop_reason"``; a ``None`` met on the way gives the field's default); ``None``:
            the field's own name; :data:`GIVEN`: the result's ``to_record`` passes it.
        schema: JSON schema keys beyond what the field's type gives (an ``enum``, a ``minimum``).
        default: the value when the result has none (a ``None`` on the path, or not given).
    """
    metadata = {"doc": doc, "source": source, "schema": dict(schema or {})}
    return dataclasses.field(default=default, metadata=metadata)


def _follow(result: Any, f: dataclasses.Field[Any]) -> Any:
    """The value of field ``f`` on ``result``: its source path followed, its default where it breaks off."""
    source = f.metadata.get("source")
    if source == GIVEN:
        if f.default is MISSING:
            raise TypeError(f"record field {f.name!r} has no default: the result's to_record must give it")
        return f.default
    value = result
    for name in (source or f.name).split("."):
        if value is None:
            if f.default is MISSING:
                raise TypeError(f"record field {f.name!r}: {source!r} breaks off at None and there is no default")
            return f.default
        value = getattr(value, name)
    return value


R = typing.TypeVar("R", bound="MicroRecord")


def record_of(cls: type[R], result: Any, **given: Any) -> R:
    """The record ``cls`` of ``result``: every field read from the result along its :func:`column` source,
    but those in ``given`` (values the result computes for its record).

    Raises:
        TypeError: ``given`` names a field ``cls`` does not have, or a field has no value.
    """
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(set(given) - names)
    if unknown:
        raise TypeError(f"{cls.__name__} has no field {unknown[0]!r}")
    return cls(**{f.name: given[f.name] if f.name in given else _follow(result, f) for f in dataclasses.fields(cls)})


def _json_type(name: str, hint: Any) -> dict[str, Any]:
    """The JSON schema a field's type gives (a ``*load_factor*`` float is a load factor: a number or null)."""
    if hint is float:
        return {"$ref": "#/$defs/lambda"} if "load_factor" in name else {"type": ["number", "null"]}
    if hint is bool:
        return {"type": "boolean"}
    if hint is int:
        return {"type": "integer", "minimum": 0}
    if hint is str:
        return {"type": "string"}
    if typing.get_origin(hint) is tuple or isinstance(hint, types.UnionType):
        args = [a for a in typing.get_args(hint) if a is not type(None)]
        inner = args[0] if isinstance(hint, types.UnionType) else hint
        if typing.get_args(inner) == (float, float):
            return {"$ref": "#/$defs/band"}
        return {"type": "array", "items": {"$ref": "#/$defs/lambda"}}
    raise TypeError(f"record field {name!r}: no JSON type for {hint!r}")


def record_schema(cls: type[MicroRecord], *, inherited: bool = True) -> dict[str, dict[str, Any]]:
    """The JSON schema of each field of record ``cls`` (``inherited=False``: the fields ``cls`` adds to its
    base), from its type and its :func:`column` declaration: the ``properties`` of
    ``docs/schemas/micro.schema.json``."""
    hints = typing.get_type_hints(cls)
    base = set() if inherited else {f.name for c in cls.__mro__[1:] if dataclasses.is_dataclass(c)
                                    for f in dataclasses.fields(c)}
    return {f.name: {**_json_type(f.name, hints[f.name]), **f.metadata["schema"], "description": f.metadata["doc"]}
            for f in dataclasses.fields(cls) if f.name not in base}


_SECONDS = {"type": "number", "minimum": 0}


@dataclass(frozen=True)
class MicroRecord(Mapping[str, Any]):
    """What every micro analysis reports (governing direction first); a read-only mapping of its fields.

    Each field's meaning is its :func:`column` declaration (``docs/schemas/micro.schema.json`` prints them).
    """

    load_factor: float = column(
        "The lambda to quote, the smallest over the load directions: the associative LP's, or the "
        "non-associative lowest certified state where the descent found one in every direction, else the "
        "iterated LP's (quoted says which); null on failure.")
    status: str = column(
        "optimal (associative LP), converged (iterated LP), or the failing status; every other status comes "
        "with load_factor null.")
    solver: str = column("The back end, or which solver did what in the iterated LP.", source=GIVEN)
    direction: str = column(
        "The governing direction of the live load (non-associative: the iterated LP's; lowest_direction is the "
        "lowest state's); empty on failure.", schema={"enum": ["+x", "-x", ""]})
    load_factor_plus: float = column(
        "lambda of the +x direction, of the kind load_factor is (non-associative: that direction's lowest "
        "certified state when load_factor is the lowest, else its iterated LP's value).", source=GIVEN)
    load_factor_minus: float = column(
        "lambda of the -x direction, of the kind load_factor is (null when not solved, e.g. a "
        "mirror-symmetric wall).", source=GIVEN)
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
    build_seconds: float = column("Assembly of the LP (and the back end's setup).", schema=_SECONDS)
    solve_seconds: float = column("Every solve.", schema=_SECONDS)
    mirror_symmetric: bool = column("One direction solved: the wall is its own mirror image.")
    closed_contacts: int = column(
        "Contacts of the governing mechanism that stay closed (0 without a mechanism, e.g. on failure).",
        source=GIVEN)
    opening_contacts: int = column("Contacts of the governing mechanism that open (0 without a mechanism).",
                                   source=GIVEN)
    sliding_contacts: int = column("Contacts of the governing mechanism that slide (0 without a mechanism).",
                                   source=GIVEN)
    message: str = column("Why the analysis failed (empty on success).")

    def __post_init__(self) -> None:
        check_success(type(self).__name__, self.status, self.load_factor)

    def __getitem__(self, key: str) -> Any:
        """``rec[name]``: the field ``name`` (as in memory: NaN, tuples).

        Raises:
            KeyError: ``name`` is not a field.
        """
        if key not in self.__dataclass_fields__:
            raise KeyError(key)
        return getattr(self, key)

    def __iter__(self) -> Iterator[str]:
        """The field names, in order."""
        return (f.name for f in dataclasses.fields(self))

    def __len__(self) -> int:
        return len(dataclasses.fields(self))

    def to_dict(self) -> dict[str, Any]:
        """The JSON form: a dictionary of plain values (NaN -> ``None``, tuples -> lists)."""
        return {f.name: _out(getattr(self, f.name)) for f in dataclasses.fields(self)}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Self:
        """The record written by :meth:`to_dict` (``None`` -> NaN for numbers).

        Raises:
            KeyError: a field is missing from ``data``.
        """
        hints = typing.get_type_hints(cls)
        return cls(**{f.name: _in(hints[f.name], data[f.name]) for f in dataclasses.fields(cls)})

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

    iterated_load_factor: float = column(
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
    lambda_band: Band | None = column(
        "[min, max] of lambda over the cycle or the last window (null when converged).",
        source=_SEQ + "lambda_band")
    mechanism_band: Band | None = column(
        "[min, max] of lambda over the exact collapse states with the final mechanism (null when not computed, "
        "and whenever the status is not converged: a failed run has no exact collapse state).",
        source=_SEQ + "mechanism_band")
    last_load_factor: float = column("lambda of the last successful LP.", source=_SEQ + "last_load_factor")
    associative_load_factor: float = column(
        "The smallest associative lambda over the directions (an upper bound of every non-associative "
        "collapse state).")
    cold_load_factor: float = column(
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
    history_load_factor: tuple[float, ...] = column("lambda of every LP, the associative one first.",
                                                    source=GIVEN)
    cold_algorithm: str = column("The algorithm of the cold re-solve (ipm, simplex, ipm+crossover+simplex).",
                                 source=_SEQ + "cold_algorithm")
    fallback_steps: int = column("Scheme (b) LPs replaced by a scheme (a) step, over the directions solved.",
                                 source=GIVEN)
    selection: str = column(
        "How the governing sequence's iterates picked their forces: the simplex's vertex, or nbar moved "
        "towards the closest field that carries the LP's load (proximal; by default after a vertex sequence "
        "that ended without a state).", source=_SEQ + "selection", schema={"enum": ["vertex", "proximal"]},
        default="vertex")
    vertex_stop_reason: str = column(
        "selection vertex+proximal: how the vertex sequence ended before the proximal one ran (empty when it "
        "did not run).", source=_SEQ + "vertex_attempt.stop_reason", default="")
    vertex_lambda_band: Band | None = column(
        "selection vertex+proximal: the vertex sequence's band of its last lambda values (null when the "
        "proximal sequence did not run).", source=_SEQ + "vertex_attempt.lambda_band", default=None)
    quoted: str = column("Which value load_factor is (empty on failure).",
                         schema={"enum": ["lowest certified", "iterated", ""]}, default="")
    lowest_load_factor: float = column(
        "The lowest certified collapse state over the directions (the descent from the iterated LP's fixed "
        "point, on by default on every wall; every state verified exact); null when not run (--lowest off) or "
        "not found. The value a safety assessment should quote when the global search has not closed.",
        source=GIVEN, default=math.nan)
    lowest_direction: str = column("The direction of the lowest certified state (empty without one).",
                                   source=GIVEN, default="")
    lowest_band: Band | None = column(
        "[lowest_load_factor, greatest lambda] of the collapse states with its mechanism.", source=GIVEN,
        default=None)
    lowest_moves: int = column("Moves between mechanisms that led to it.", source=GIVEN, default=0)
    lowest_lps: int = column("LPs of the descent, over the directions.", source=GIVEN, default=0)
    lowest_seconds: float = column("Seconds of the descent, over the directions.", source=GIVEN, default=0.0,
                                   schema=_SECONDS)
    lowest_status: str = column("found or failed (failed: some direction has no state); empty when the descent "
                                "did not run.", source=GIVEN, default="", schema={"enum": ["", "found", "failed"]})
    lowest_stop: str = column(
        "finished: every direction's descent ended by its own rules; budget: one spent its budget of LPs "
        "(--lowest-budget, LPs per direction) and gave the lowest certified state found so far; target: the "
        "search stopped at the first certified state below the options' stop_below (a compare whose macro "
        "lambda it refutes); empty when the descent did not run.", source=GIVEN, default="",
        schema={"enum": ["", "finished", "budget", "target"]})
    global_load_factor: float = column(
        "--global: the best verified collapse state of the branch and bound (null when not run).", source=GIVEN,
        default=math.nan)
    global_lower_bound: float = column("--global: its proven lower bound of every collapse load factor.",
                                       source=GIVEN, default=math.nan)
    global_gap: float = column("(global_load_factor - global_lower_bound) / global_load_factor.", source=GIVEN,
                               default=math.nan)
    global_status: str = column(
        "empty (not run), optimal (the gap closed: global_load_factor is the global minimum), time_limit "
        "(stopped by --time-limit: depends on the machine), node_limit (stopped at its budget of nodes: the "
        "same on every machine), infeasible or solver_error.",
        source=GIVEN, default="")
    fused_bodies: int = column(
        "--fuse: moving bodies of the fused wall the iterated LP ran on (0: the wall itself).",
        source=_SEQ + "fusion.bodies", default=0)
    fused_points: int = column("--fuse: contact points of the fused wall (0: the wall itself).",
                               source=_SEQ + "fusion.points", default=0)
    unfused_stop_reason: str = column(
        "How the wall's own sequences ended before the fused wall with the continuation certified the "
        "governing direction (options.fused_retry; empty: it did not run).",
        source=_SEQ + "unfused_attempt.stop_reason", default="")

    def __post_init__(self) -> None:
        """A success comes with a finite value to quote and a finite iterated LP value (:func:`check_success`)."""
        super().__post_init__()
        check_success(f"{type(self).__name__} (iterated_load_factor)", self.status, self.iterated_load_factor)
