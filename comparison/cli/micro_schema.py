"""The JSON schema of ``xcheck micro --json``, ``docs/schemas/micro.schema.json``, generated.

The record's keys come from their one declaration (:func:`micro.records.record_schema`: each field's type,
description and schema, :func:`micro.records.column`); the keys the command adds beside the record (the
wall, the figure and state files, the local mechanism, the directions, the iterated LP's history and
options) are written here. ``python -m comparison.cli.micro_schema`` rewrites the file; a test checks that
the committed file is what this module writes, so a field added to a record reaches the schema, and the
schema's tests, the day it is declared.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from comparison.utilities.outputs import write_text
from micro.backends.base import Status
from micro.nonassociative.nonassociative_result import STATUSES
from micro.records import MicroRecord, NonAssociativeRecord, record_schema

#: The schema's version: raised when a key changes meaning or goes (docs/schemas.md); a new key keeps it.
VERSION = 2
#: The file this module writes, from the repository's root.
PATH = Path("docs") / "schemas" / "micro.schema.json"

#: The head of the schema (its version is :data:`VERSION`).
_HEAD: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "$id": "xcheck-masonry/docs/schemas/micro.schema.json",
    "title": "xcheck micro --json",
    "version": 2,
    "description": "One object: rigid-block limit analysis of one wall, associative (--friction associative: one "
    "LP per load direction) or non-associative (--friction nonassociative: the iterated LP). "
    "Lengths in block heights, forces in block weights. A failed analysis has status other than "
    "optimal/converged and load_factor null; a number is never paired with a failure status. Keys "
    "are only added in a new release, with this schema. Version 2: load_factor is the value to "
    "quote with both friction laws (non-associative: the lowest certified state where the descent "
    "found one, else the iterated LP's value), the iterated LP's value is iterated_load_factor; "
    "version 1 had the iterated LP's value under load_factor and the value to quote under "
    "quoted_load_factor (docs/schemas.md).",
    "type": "object",
    "$ref": "#/$defs/common",
    "if": {"properties": {"friction": {"const": "nonassociative"}}, "required": ["friction"]},
    "then": {"$ref": "#/$defs/nonassociative"},
    "else": {"$ref": "#/$defs/associative"},
    "unevaluatedProperties": False,
}

#: The shared definitions: a load factor, a direction, a band.
_DEFS: dict[str, Any] = {
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

#: The keys ``xcheck micro --json`` adds to the record, with either friction law.
_COMMAND_KEYS: dict[str, Any] = {
    "wall": {
        "type": ["string", "null"],
        "description": "The wall's name (a scene's name), null when it has none (a wall given by --t, --m, "
        "...: see paper_parameters).",
    },
    "end_blocks_cut": {
        "type": "boolean",
        "description": "L is not a whole number of half blocks: the courses end in cut pieces, closers or "
        "slivers as ends says (docs/micro/walls.md).",
    },
    "ends": {
        "enum": ["closers", "cut"],
        "description": "How the courses end where L is not a whole number of half blocks: closers (no piece "
        "narrower than min(f b, l/4), a long last unit instead) or cut (whatever remains) (docs/micro/walls.md).",
    },
    "paper_parameters": {
        "type": "object",
        "description": "The paper's Table 4 parameters of the wall (ratios printed as the scene "
        "wrote them: m = 0.10/0.30 is 1/3; p storey by storey in p_storeys), as "
        "in xcheck macro --json.",
        "additionalProperties": False,
        "required": ["t", "m", "rows", "storeys", "p", "p_storeys", "f"],
        "properties": {
            "t": {"type": "number", "description": "H/L."},
            "m": {"type": "number", "description": "b/l."},
            "rows": {"type": "integer", "minimum": 1, "description": "o = H/b."},
            "storeys": {"type": "integer", "minimum": 1},
            "p": {
                "type": ["number", "null"],
                "minimum": 0,
                "description": "q/(gamma H b), the paper's p, the same on every "
                "floor; null when the storeys' differ (a scene's "
                "floor loads: see p_storeys).",
            },
            "p_storeys": {
                "type": "array",
                "minItems": 1,
                "items": {"type": "number", "minimum": 0},
                "description": "q_i/(gamma H b_i) of each storey, storey 1 (the top) first: a scene's floor loads.",
            },
            "f": {"type": "number", "description": "Friction coefficient."},
        },
    },
    "friction": {"enum": ["associative", "nonassociative"]},
    "first_course": {"enum": ["full", "half"]},
    "head_joints": {"enum": ["frictional", "frictionless"]},
    "plot": {"type": ["string", "null"], "description": "The figure written by --plot, or null."},
    "state": {
        "type": ["string", "null"],
        "description": "The collapse state file written by --state (docs/schemas/state.schema.json), or null.",
    },
    "held_load_factor": {
        "$ref": "#/$defs/lambda",
        "description": "Where a sliver's local mechanism governs the wall as built (local_mechanism), the "
        "same analysis with the slivers held to the blocks that carry them: another wall, reported beside "
        "load_factor (the wall as built's, the value to quote and compare), never in its place "
        "(docs/micro/walls.md). null when none governs, or the held analysis failed.",
    },
    "local_mechanism": {
        "type": ["object", "null"],
        "description": "The local mechanism that governs the wall as built: blocks at one of its top "
        "corners that a sliver (a piece narrower than a closer, ends = cut) lets collapse on their own, e.g. "
        "a cut end piece that tips over at lambda = width/height (micro.local_mechanisms); null when none.",
        "additionalProperties": False,
        "required": [
            "blocks",
            "slivers",
            "weight_share",
            "load_factor",
            "direction",
            "description",
            "held",
            "status",
            "message",
        ],
        "properties": {
            "blocks": {
                "type": "array",
                "items": {"type": "integer", "minimum": 0},
                "description": "The moving blocks (numbered course by course from the base, left to right).",
            },
            "slivers": {
                "type": "array",
                "items": {"type": "integer", "minimum": 0},
                "description": "The slivers it moves or rests on: the pieces held for the held wall.",
            },
            "weight_share": {
                "type": "number",
                "minimum": 0,
                "maximum": 1,
                "description": "Their share of the wall's dead load.",
            },
            "load_factor": {"$ref": "#/$defs/lambda", "description": "Its lambda: the wall as built's value to quote."},
            "direction": {"$ref": "#/$defs/direction"},
            "description": {"type": "string", "description": "What moves, in words."},
            "held": {
                "type": "array",
                "items": {"type": "integer", "minimum": 0},
                "description": "The slivers held to the blocks that carry them: every sliver of the wall.",
            },
            "status": {
                "enum": ["wall", "failed"],
                "description": "wall: held_load_factor is the held wall's (its mechanism is not local); "
                "otherwise held_load_factor is null and message says why.",
            },
            "message": {"type": "string"},
        },
    },
}

#: The keys the non-associative summary adds to its record (:meth:`micro.NonAssociativeResult.summary`).
_NONASSOCIATIVE_KEYS: dict[str, Any] = {
    "options": {
        "type": "object",
        "description": "What ran (micro.nonassociative.Resolved): the options and the tuning resolved for "
        "the wall: scheme, selection, relaxation, caps, tolerances, fusing.",
        "required": ["scheme", "relaxation", "max_iterations", "certify"],
    },
    "history": {
        "type": "array",
        "description": "Every LP of the governing direction.",
        "items": {
            "type": "object",
            "required": [
                "iteration",
                "load_factor",
                "max_dn",
                "simplex_iterations",
                "seconds",
                "algorithm",
                "status",
                "certificate",
            ],
            "properties": {
                "iteration": {"type": "integer", "minimum": 0},
                "load_factor": {"$ref": "#/$defs/lambda"},
                "lambda_change": {"type": ["number", "null"]},
                "max_dn": {"type": ["number", "null"]},
                "coulomb_residual": {"type": ["number", "null"]},
                "alpha": {"type": ["number", "null"]},
                "simplex_iterations": {"type": "integer", "minimum": 0},
                "ipm_iterations": {"type": "integer", "minimum": 0},
                "seconds": {"type": "number", "minimum": 0},
                "algorithm": {"type": "string"},
                "status": {"type": "string"},
                "certificate": {"type": "string", "description": "certified, not found, or empty when not attempted."},
                "certificate_seconds": {"type": "number", "minimum": 0},
                "certificate_iterations": {"type": "integer", "minimum": 0},
            },
        },
    },
    "directions": {
        "type": "object",
        "propertyNames": {"$ref": "#/$defs/direction"},
        "additionalProperties": {
            "type": "object",
            "additionalProperties": False,
            "required": [
                "status",
                "stop_reason",
                "load_factor",
                "iterated_load_factor",
                "last_load_factor",
                "associative_load_factor",
                "iterations",
                "seconds",
            ],
            "properties": {
                "status": {"type": "string"},
                "stop_reason": {"type": "string"},
                "load_factor": {
                    "$ref": "#/$defs/lambda",
                    "description": "This direction's "
                    "lambda of the kind the "
                    "wall's load_factor is: "
                    "its lowest certified "
                    "state when the wall's "
                    "is the lowest, else "
                    "its iterated LP's "
                    "value.",
                },
                "iterated_load_factor": {
                    "$ref": "#/$defs/lambda",
                    "description": "This direction's iterated LP value.",
                },
                "last_load_factor": {"$ref": "#/$defs/lambda"},
                "associative_load_factor": {"$ref": "#/$defs/lambda"},
                "iterations": {"type": "integer", "minimum": 0},
                "seconds": {"type": "number", "minimum": 0},
            },
        },
    },
    "lowest": {
        "type": "array",
        "description": "The descent per direction: load_factor, band, path, moves, lps, budget, stop, "
        "seconds, contact_states (closed, opening, sliding; null without a state), "
        "residuals.",
    },
    "global_direction": {"type": "string", "description": "--global: the direction of its best state."},
    "global_nodes": {
        "type": "integer",
        "minimum": 0,
        "description": "--global: branch-and-bound nodes over the directions.",
    },
    "global_seconds": {"type": "number", "minimum": 0},
}

_NONASSOCIATIVE_STATUS = (
    "converged: an exact collapse state (certified, or the LP's own forces satisfy Coulomb); cycling: lambda "
    "repeats or oscillates (lambda_band gives its range); max_iterations: the LP cap or the work budget of "
    "simplex iterations (stop_reason work_budget) was reached; time_limit: a user's wall-clock stop (max_seconds: "
    "stop_reason time_budget; an LP's time_limit), no final answer; solver_failure: an LP failed."
)

_NONASSOCIATIVE_SUCCESS: dict[str, Any] = {
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

_ASSOCIATIVE_STATUS = (
    "optimal, or the back end's failure mapped onto the shared statuses (inaccurate: an answer the back end "
    "called optimal failed the independent equilibrium/Coulomb re-check)."
)

_ASSOCIATIVE_DIRECTIONS: dict[str, Any] = {
    "type": "object",
    "propertyNames": {"$ref": "#/$defs/direction"},
    "additionalProperties": {
        "type": "object",
        "additionalProperties": False,
        "required": ["load_factor", "status", "native_status", "iterations", "solve_seconds"],
        "properties": {
            "load_factor": {"$ref": "#/$defs/lambda"},
            "status": {"type": "string"},
            "native_status": {"type": "string", "description": "The back end's own status."},
            "iterations": {"type": "integer", "minimum": 0},
            "solve_seconds": {"type": "number", "minimum": 0},
        },
    },
}

_ASSOCIATIVE_SUCCESS: dict[str, Any] = {
    "if": {"properties": {"status": {"const": "optimal"}}},
    "then": {"properties": {"load_factor": {"type": "number"}}},
    "else": {"properties": {"load_factor": {"type": "null"}}},
}


def micro_schema() -> dict[str, Any]:
    """The schema of ``xcheck micro --json``: the record's keys from their declarations, the command's beside."""
    common = record_schema(MicroRecord)
    own = record_schema(NonAssociativeRecord, inherited=False)
    optional = ("global_direction", "global_nodes", "global_seconds")
    return {
        **_HEAD,
        "version": VERSION,
        "$defs": {
            **_DEFS,
            "common": {
                "required": [*common, "directions", *_COMMAND_KEYS],
                "properties": {**common, **_COMMAND_KEYS},
            },
            "associative": {
                **_ASSOCIATIVE_SUCCESS,
                "properties": {
                    "status": {"enum": [s.value for s in Status], "description": _ASSOCIATIVE_STATUS},
                    "directions": _ASSOCIATIVE_DIRECTIONS,
                },
            },
            "nonassociative": {
                **_NONASSOCIATIVE_SUCCESS,
                "required": [*own, *(k for k in _NONASSOCIATIVE_KEYS if k not in optional)],
                "properties": {
                    "status": {"enum": list(STATUSES), "description": _NONASSOCIATIVE_STATUS},
                    **own,
                    **_NONASSOCIATIVE_KEYS,
                },
            },
        },
    }


def render() -> str:
    """The file's text: the schema as indented JSON, a newline at the end."""
    return json.dumps(micro_schema(), indent=2, ensure_ascii=False) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write :data:`PATH` under the repository root given (default: the current folder), whole or not at
    all; a root without ``docs/schemas/`` is one line on standard error and exit code 2."""
    root = Path((argv if argv is not None else sys.argv[1:] or ["."])[0])
    target = root / PATH
    if not target.parent.is_dir():
        print(f"micro_schema: error: {target.parent} is not a folder: give the repository's root", file=sys.stderr)
        return 2
    write_text(target, render())
    print(target)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
