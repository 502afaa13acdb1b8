"""Flat records of the micro results: frozen dataclasses that read as mappings, with a JSON form.

A record holds what a table, a cache or a report needs of one analysis:
numbers, strings, bools and tuples of numbers, no arrays (forces and
velocities stay on the result objects). It is a read-only mapping of its
fields (``rec["lowest_stop"]``, ``rec.lowest_stop``, ``dict(rec)``, ``list(rec)``
give the field names in order). ``NaN`` is allowed in memory (a failed
number); :meth:`MicroRecord.to_dict` gives the JSON form (``None`` for NaN,
lists for tuples) and :meth:`MicroRecord.from_dict` reads it back, so
``from_dict(to_dict(r))`` gives the record back.

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
from dataclasses import dataclass
from typing import Any, Self

__all__ = [
    "SUCCESS_STATUSES",
    "AssociativeRecord",
    "MicroRecord",
    "NonAssociativeRecord",
    "check_success",
    "json_number",
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


@dataclass(frozen=True)
class MicroRecord(Mapping[str, Any]):
    """What every micro analysis reports (governing direction first); a read-only mapping of its fields.

    Attributes:
        load_factor: the ``lambda`` to quote (NaN when the analysis failed): the associative LP's, or for
            the non-associative analysis its lowest certified state where the descent found one, else the
            iterated LP's (:class:`NonAssociativeRecord`).
        status: ``"optimal"`` (associative), ``"converged"`` (iterated LP)
            or the failing status.
        solver: the back end, or for the iterated LP which solver did what.
        direction: governing direction ``"+x"`` / ``"-x"`` (``""`` on failure).
        load_factor_plus, load_factor_minus: ``lambda`` of each direction, of the kind ``load_factor`` is
            (NaN when that direction was not solved, e.g. ``-x`` of a
            mirror-symmetric wall, or did not succeed).
        blocks, contacts, points: sizes of the wall.
        variables, rows, nnz: sizes of the assembled associative LP.
        iterations: the governing (or first failing) direction's count (module
            docstring).
        total_iterations: the sum over the directions solved.
        build_seconds: assembly of the LP.
        solve_seconds: every solve.
        mirror_symmetric: one direction solved (the wall is its own mirror image).
        closed_contacts, opening_contacts, sliding_contacts: contact states of
            the governing mechanism (0 when there is none).
        message: a one-line explanation when the analysis failed.
    """

    load_factor: float
    status: str
    solver: str
    direction: str
    load_factor_plus: float
    load_factor_minus: float
    blocks: int
    contacts: int
    points: int
    variables: int
    rows: int
    nnz: int
    iterations: int
    total_iterations: int
    build_seconds: float
    solve_seconds: float
    mirror_symmetric: bool
    closed_contacts: int
    opening_contacts: int
    sliding_contacts: int
    message: str

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


@dataclass(frozen=True)
class NonAssociativeRecord(MicroRecord):
    """Record of :func:`micro.solve_nonassociative`.

    ``load_factor`` is the value to quote (``quoted`` says which), the iterated LP's own value is
    ``iterated_load_factor`` with its mechanism's band ``mechanism_band``; ``load_factor_plus`` and
    ``load_factor_minus`` are each direction's lowest state when the lowest is quoted, else each
    direction's iterated LP value. The fields below describe the iterated LP's governing direction
    (the first direction that did not converge when the analysis failed), but for
    ``fallback_steps`` which is summed over the directions.

    Attributes:
        iterated_load_factor: the iterated LP's governing ``lambda`` (NaN unless every direction
            converged); ``load_factor`` when the descent did not run.
        scheme: rebuilt yield condition, ``"a"`` or ``"b"``.
        relaxation: ``beta``.
        converged: ``status == "converged"``.
        stop_reason: what stopped the sequence.
        lambda_band: ``(min, max)`` of ``lambda`` over the cycle or the last
            window (``None`` when converged).
        mechanism_band: ``(min, max)`` of ``lambda`` over the collapse states
            with the final mechanism (``None`` when not computed, and when the
            run did not converge: a failed run has no exact collapse state).
        last_load_factor: ``lambda`` of the last successful iterate.
        associative_load_factor: smallest associative ``lambda`` over the
            directions solved.
        cold_load_factor: the final iterate re-solved cold (NaN unless the
            sequence stopped exactly, not by the certificate).
        warm_cold_rel_diff: ``|warm - cold| / |cold|`` (NaN likewise).
        coulomb_residual: ``max(|s| - mu n, 0) / max n`` of the final forces.
        dilatancy_residual: largest opening rate at sliding points in
            contact, relative to the largest slip rate.
        history_load_factor: ``lambda`` of every LP, the associative one first.
        cold_algorithm: the algorithm of the cold re-solve.
        fallback_steps: scheme (b) LPs replaced by a scheme (a) step, over
            the directions solved.
        selection: how the governing sequence picked its forces
            (``"vertex"`` or ``"proximal"``).
        vertex_stop_reason, vertex_lambda_band: with ``"vertex+proximal"``, how
            the vertex sequence ended before the proximal one ran (``""`` and
            ``None`` when it did not run).
        quoted: which value ``load_factor`` is: ``"lowest certified"``, ``"iterated"``, or
            ``""`` on failure.
        lowest_load_factor: the lowest certified collapse state over the
            directions (:mod:`micro.nonassociative.descent.lowest`; NaN when not
            computed or not found in every direction).
        lowest_direction: its direction.
        lowest_band: ``(lambda, greatest lambda)`` of the collapse states
            with its mechanism.
        lowest_moves: moves between mechanisms that led to it.
        lowest_lps, lowest_seconds: cost of the descent over the directions.
        lowest_status: ``""`` (not run), ``"found"`` or ``"failed"``.
        lowest_stop: ``""`` (not run), ``"finished"`` (every direction's
            descent ended by its own rules) or ``"budget"`` (one spent its
            budget of LPs: the lowest state found so far).
        global_load_factor: best collapse state of the global search
            (:mod:`micro.global_search`; NaN when not run).
        global_lower_bound: its proven lower bound of every collapse load factor.
        global_gap: ``(global_load_factor - global_lower_bound) / global_load_factor``.
        global_status: ``""`` (not run), ``"optimal"`` (the gap closed),
            ``"time_limit"``, ``"node_limit"``, ``"infeasible"`` or ``"solver_error"``.
        fused_bodies, fused_points: moving bodies and contact points of the
            fused wall the sequence ran on (0 and 0: the wall itself;
            :mod:`micro.nonassociative.pipeline`).
        unfused_stop_reason: with ``fused_retry``, how the wall's own
            sequences ended before the fused wall with the continuation
            certified the governing direction (``""``: it did not run).
    """

    iterated_load_factor: float
    scheme: str
    relaxation: float
    converged: bool
    stop_reason: str
    lambda_band: Band | None
    mechanism_band: Band | None
    last_load_factor: float
    associative_load_factor: float
    cold_load_factor: float
    warm_cold_rel_diff: float
    coulomb_residual: float
    dilatancy_residual: float
    history_load_factor: tuple[float, ...]
    cold_algorithm: str
    fallback_steps: int
    selection: str = "vertex"
    vertex_stop_reason: str = ""
    vertex_lambda_band: Band | None = None
    quoted: str = ""
    lowest_load_factor: float = math.nan
    lowest_direction: str = ""
    lowest_band: Band | None = None
    lowest_moves: int = 0
    lowest_lps: int = 0
    lowest_seconds: float = 0.0
    lowest_status: str = ""
    lowest_stop: str = ""
    global_load_factor: float = math.nan
    global_lower_bound: float = math.nan
    global_gap: float = math.nan
    global_status: str = ""
    fused_bodies: int = 0
    fused_points: int = 0
    unfused_stop_reason: str = ""

    def __post_init__(self) -> None:
        """A success comes with a finite value to quote and a finite iterated LP value (:func:`check_success`)."""
        super().__post_init__()
        check_success(f"{type(self).__name__} (iterated_load_factor)", self.status, self.iterated_load_factor)
