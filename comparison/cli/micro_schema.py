"""The JSON schema of ``xcheck micro --json``, ``docs/schemas/micro.schema.json``, generated.

Every key of the micro result's summary comes from a record's declaration (:mod:`micro.schema`, where the
records live: the flat record, each direction, each LP of the history, each direction's descent); the keys
the command adds beside them (the wall and its paper parameters, the friction law and bond, the files
written, the held wall's value and the local mechanism, a record of its own:
:class:`comparison.domain.wall_mechanism.LocalRecord`) are described here. ``python -m
comparison.cli.micro_schema`` rewrites the file; a test checks that the committed file is what this module
writes, so a field added to a record reaches the schema, and the schema's tests, the day it is declared.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from comparison.domain.wall_mechanism import LocalRecord
from comparison.utilities.outputs import write_text
from micro.schema import entry_schema, summary_definitions

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
        **entry_schema(LocalRecord),
        "type": ["object", "null"],
        "description": "The local mechanism that governs the wall as built: blocks at one of its top "
        "corners that a sliver (a piece narrower than a closer, ends = cut) lets collapse on their own, e.g. "
        "a cut end piece that tips over at lambda = width/height (micro.local_mechanisms), with the held "
        "wall's value beside it; null when none.",
    },
}


def micro_schema() -> dict[str, Any]:
    """The schema of ``xcheck micro --json``: the summary's keys from their records' declarations
    (:func:`micro.schema.summary_definitions`), the command's beside them."""
    defs = summary_definitions()
    common = defs["common"]
    return {
        **_HEAD,
        "version": VERSION,
        "$defs": {
            **defs,
            "common": {"required": [*common["required"], *_COMMAND_KEYS],
                       "properties": {**common["properties"], **_COMMAND_KEYS}},
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
