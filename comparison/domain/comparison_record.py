"""The record of a comparison: what a table or a report keeps of :class:`~comparison.domain.verdict.Comparison`.

Declared field by field with the suite's one machinery (:func:`micro.columns.column`: a field's type,
description and source on the comparison; the JSON form and the schema from that declaration), as the
micro and macro records are. The comparison's nested parts (the local mechanism's detail, the seconds of
each stage, the models' own results) stay on it; the record keeps the numbers, the verdict and the bond, each
of the wall as built.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from micro.columns import Band, FlatRecord, LoadFactor, Seconds, column, record_of


@dataclass(frozen=True)
class ComparisonRecord(FlatRecord):
    """A comparison, flat: a read-only mapping of its fields (``rec["verdict"]``); :meth:`to_dict` is its JSON
    form. A field named as a key of ``xcheck compare --json`` (``docs/schemas/compare.schema.json``) holds the
    same value there; ``local_description`` and ``total_seconds`` flatten the JSON's nested parts."""

    verdict: str | None = column("unsafe, not refuted, safe, or null when nothing proves either way.",
                                 schema={"enum": ["unsafe", "not refuted", "safe", None]})
    proof: str | None = column("What proves the verdict: associative bound, certified state or global bound; null "
                               "with 'not refuted' and without a verdict.",
                               schema={"enum": ["associative bound", "certified state", "global bound", None]})
    status: str = column("ok: every method that ran gave its value; failed: one did not.",
                         schema={"enum": ["ok", "failed"]})
    macro_load_factor: LoadFactor = column("The macro model's lambda.")
    micro_load_factor: LoadFactor = column("The non-associative lambda compared: the lowest certified state, a "
                                           "certified state below the macro lambda where the search stopped, or the "
                                           "iterated LP's (micro_quoted says which).")
    difference_percent: float = column("(macro - micro) / micro in per cent.")
    associative_load_factor: LoadFactor = column("The associative LP's lambda, an upper bound of every "
                                                 "non-associative collapse load.")
    certified_load_factor: LoadFactor = column("The lowest lambda of a certified collapse state found.")
    micro_quoted: str = column("Which non-associative value micro_load_factor is (empty without one).")
    iterated_load_factor: LoadFactor = column("The iterated LP's own lambda.")
    mechanism_band: Band = column("The band of lambda over the collapse states of the iterated LP's mechanism.")
    macro_mechanism: str = column("The macro model's mechanism (empty when it failed).")
    global_status: str = column("The global search's status (empty when it did not run).")
    global_lower_bound: LoadFactor = column("The global search's lower bound (proven when global_status is "
                                            "optimal).")
    local_description: str = column("What a sliver lets collapse in the wall as built (empty: nothing local "
                                    "governs; ends = cut only); the JSON's local_mechanism gives its detail.")
    held_load_factor: LoadFactor = column("The held wall's lambda beside the wall as built's where a local "
                                          "mechanism governs (every sliver held; another wall, never compared).")
    blocks: int = column("Blocks of the micro wall as built.")
    first_course: str = column("The bottom course starts with a full or a half block.", source="options.first_course",
                               schema={"enum": ["full", "half"]})
    head_joints: str = column("Frictional or frictionless head joints.", source="options.head_joints",
                              schema={"enum": ["frictional", "frictionless"]})
    ends: str = column("How the courses end where L is not a whole number of half blocks.", source="wall.ends",
                       schema={"enum": ["closers", "cut"]})
    full: bool = column("Every number was computed (the non-associative search also where the bound settles the "
                        "verdict, on to the lowest state).", source="options.full")
    search_stopped: bool = column("The non-associative search stopped at the first certified state below the "
                                  "macro lambda.")
    total_seconds: Seconds = column("Wall time of the comparison, every stage (the JSON's seconds give each).",
                                    source="seconds.total")


def comparison_record(c: Any) -> ComparisonRecord:
    """The :class:`ComparisonRecord` of ``c``, a :class:`comparison.domain.verdict.Comparison` (named, not
    imported: that module imports this one)."""
    return record_of(ComparisonRecord, c)
