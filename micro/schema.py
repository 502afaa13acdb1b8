"""The JSON schema of a micro result's summary (``result.summary()``), generated where its records live.

Every key of a summary is a field of a record (:mod:`micro.records`, :mod:`micro.columns`): the flat record
of the analysis, and the records of its nested parts (each load direction, each LP of the iterated LP's
history, each direction's descent, the global search's extra keys). Their schemas are made here from
those declarations, never written by hand; only the options of the iterated LP, a configuration rather
than a record, are described from their types (:class:`micro.NonAssociativeOptions`,
:class:`micro.Tuning`). ``xcheck micro --json`` adds the keys of the command beside them
(:mod:`comparison.cli.micro_schema`, which writes ``docs/schemas/micro.schema.json``).
"""

from __future__ import annotations

import dataclasses
import typing
from typing import Any, Literal

from micro.backends.base import Status
from micro.columns import FlatRecord, record_schema
from micro.global_search.global_types import GlobalExtras
from micro.nonassociative.config import NonAssociativeOptions, Tuning
from micro.nonassociative.descent.lowest_direction import DescentEntry
from micro.nonassociative.nonassociative_result import STATUSES, IterationRecord
from micro.records import AssociativeDirection, IteratedDirection, MicroRecord, NonAssociativeRecord

#: The shared definitions: a load factor, a direction, a band.
DEFS: dict[str, Any] = {
    "lambda": {"type": ["number", "null"], "description": "A load factor; null when not computed or failed."},
    "direction": {"enum": ["+x", "-x"]},
    "band": {
        "type": ["array", "null"],
        "prefixItems": [{"$ref": "#/$defs/lambda"}, {"$ref": "#/$defs/lambda"}],
        "minItems": 2,
        "maxItems": 2,
        "description": "[min, max] of lambda, or null.",
    },
}

NONASSOCIATIVE_STATUS = (
    "converged: an exact collapse state (certified, or the LP's own forces satisfy Coulomb); cycling: lambda "
    "repeats or oscillates (lambda_band gives its range); max_iterations: the LP cap or the work budget of "
    "simplex iterations (stop_reason work_budget) was reached; time_limit: a user's wall-clock stop (max_seconds: "
    "stop_reason time_budget; an LP's time_limit), no final answer; solver_failure: an LP failed."
)
ASSOCIATIVE_STATUS = (
    "optimal, or the back end's failure mapped onto the shared statuses (inaccurate: an answer the back end "
    "called optimal failed the independent equilibrium/Coulomb re-check)."
)
#: A success comes with numbers, a failure with none.
NONASSOCIATIVE_SUCCESS: dict[str, Any] = {
    "if": {"properties": {"status": {"const": "converged"}}},
    "then": {"properties": {"load_factor": {"type": "number"}, "iterated_load_factor": {"type": "number"}}},
    "else": {
        "properties": {
            "load_factor": {"type": "null"},
            "mechanism_band": {"type": "null"},
            "iterated_load_factor": {"type": "null"},
        }
    },
}
ASSOCIATIVE_SUCCESS: dict[str, Any] = {
    "if": {"properties": {"status": {"const": "optimal"}}},
    "then": {"properties": {"load_factor": {"type": "number"}}},
    "else": {"properties": {"load_factor": {"type": "null"}}},
}


def entry_schema(cls: type[FlatRecord], description: str = "") -> dict[str, Any]:
    """The schema of one record ``cls`` as a nested object: every field a property, those without a default
    required, no other key."""
    props = record_schema(cls)
    required = [f.name for f in dataclasses.fields(cls)
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    out: dict[str, Any] = {"type": "object"}
    if description:
        out["description"] = description
    return {**out, "additionalProperties": False, "required": required, "properties": props}


def by_direction(cls: type[FlatRecord]) -> dict[str, Any]:
    """The schema of a summary's ``directions``: one record ``cls`` per load direction solved."""
    return {"type": "object", "propertyNames": {"$ref": "#/$defs/direction"},
            "additionalProperties": entry_schema(cls)}


def _option_type(hint: Any) -> dict[str, Any]:
    """The JSON type of an option or knob of type ``hint`` (a resolved one is never null but where the
    option itself may be)."""
    args = typing.get_args(hint)
    if typing.get_origin(hint) is Literal:
        return {"enum": list(args)}
    if type(None) in args:
        inner = _option_type(next(a for a in args if a is not type(None)))
        if "enum" in inner:
            return {"enum": [*inner["enum"], None]}
        return {"type": [inner["type"], "null"]}
    names = {bool: "boolean", int: "integer", float: "number", str: "string"}
    return {"type": names[hint]}


def options_schema() -> dict[str, Any]:
    """The schema of a summary's ``options``: every option (:class:`micro.NonAssociativeOptions`) and knob
    (:class:`micro.Tuning`) by its type, the resolved values in place (``selection``, ``relaxation``,
    ``fuse``, ``continuation`` resolved for the wall, ``beta`` the relaxation used)."""
    props: dict[str, Any] = {}
    for cls in (NonAssociativeOptions, Tuning):
        hints = typing.get_type_hints(cls)
        props |= {f.name: _option_type(hints[f.name]) for f in dataclasses.fields(cls) if f.name != "tuning"}
    props |= {"selection": {"type": "string"}, "relaxation": {"type": "number"}, "fuse": {"type": "boolean"},
              "continuation": {"type": "boolean"}, "beta": {"type": "number"}}
    return {"type": "object", "description": "What ran (micro.nonassociative.Resolved): the options and the tuning "
            "resolved for the wall: scheme, selection, relaxation, caps, tolerances, fusing.",
            "additionalProperties": False, "required": list(props), "properties": props}


#: The keys of a non-associative summary only with a global search composed after the run.
GLOBAL_KEYS = tuple(record_schema(GlobalExtras))


def summary_definitions() -> dict[str, Any]:
    """The schema's definitions of a micro summary: ``common`` (every analysis's record, and its
    ``directions``), ``associative`` and ``nonassociative`` (what each adds)."""
    common = record_schema(MicroRecord)
    base = set(common)
    own = {k: v for k, v in record_schema(NonAssociativeRecord).items() if k not in base}
    nested = {
        "lowest": {"type": "array", "description": "The descent per direction.",
                   "items": entry_schema(DescentEntry)},
        **record_schema(GlobalExtras),
        "options": options_schema(),
        "history": {"type": "array", "description": "Every LP of the governing direction.",
                    "items": entry_schema(IterationRecord)},
        "directions": by_direction(IteratedDirection),
    }
    return {
        **DEFS,
        "common": {"required": [*common, "directions"], "properties": common},
        "associative": {
            **ASSOCIATIVE_SUCCESS,
            "properties": {"status": {"enum": [s.value for s in Status], "description": ASSOCIATIVE_STATUS},
                           "directions": by_direction(AssociativeDirection)},
        },
        "nonassociative": {
            **NONASSOCIATIVE_SUCCESS,
            "required": [*own, *(k for k in nested if k not in GLOBAL_KEYS)],
            "properties": {"status": {"enum": list(STATUSES), "description": NONASSOCIATIVE_STATUS}, **own, **nested},
        },
    }
