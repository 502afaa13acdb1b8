"""Records: flat, read-only mappings with a JSON form, round trip, and consistent with the results they come from."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest
from micro_walls import table7_wall, three_storey_wall

import micro


def _eq(u: object, v: object) -> bool:
    return u == v or (isinstance(u, float) and isinstance(v, float) and math.isnan(u) and math.isnan(v))


def _same(a: micro.MicroRecord, b: micro.MicroRecord) -> bool:
    """Equal field by field, NaN equal to NaN."""
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        xs, ys = (x, y) if isinstance(x, tuple) else ((x,), (y,))
        if len(xs) != len(ys) or not all(_eq(u, v) for u, v in zip(xs, ys, strict=True)):
            return False
    return type(a) is type(b)


def _flat(d: dict) -> None:
    for k, v in d.items():
        assert v is None or isinstance(v, (int, float, str, bool, list)), k
        if isinstance(v, list):
            assert all(x is None or isinstance(x, (int, float)) for x in v), k


def test_associative_record() -> None:
    w = three_storey_wall()
    r = micro.solve_associative(w)
    rec = r.to_record()
    assert isinstance(rec, micro.AssociativeRecord)
    assert rec.load_factor == r.load_factor and rec.status == "optimal" and rec.direction == r.direction
    assert {rec.load_factor_plus, rec.load_factor_minus} == {d.load_factor for d in r.directions}
    assert rec.blocks == w.n_blocks and rec.variables == r.variables and rec.nnz == r.nnz
    gov = r.by_direction(r.direction)
    assert rec.iterations == gov.iterations
    assert rec.total_iterations == sum(d.iterations for d in r.directions) > rec.iterations
    assert rec.closed_contacts + rec.opening_contacts + rec.sliding_contacts == rec.contacts
    d = rec.to_dict()
    _flat(d)
    assert _same(micro.AssociativeRecord.from_dict(json.loads(json.dumps(d))), rec)
    # the summary (--json) is built from the record
    s = r.summary()
    assert {k: s[k] for k in d} == d
    # the contact states once, as the record's keys (no nested copy that could disagree, {} on failure)
    assert "contact_states" not in s and rec.contact_states == {
        "closed": s["closed_contacts"], "opening": s["opening_contacts"], "sliding": s["sliding_contacts"]}


def test_failed_associative_record_round_trips_nan() -> None:
    w = table7_wall("set12")
    import numpy as np

    r = micro.solve_associative(dataclasses.replace(w, live=np.zeros_like(w.live)))
    rec = r.to_record()
    assert rec.status == "unbounded" and math.isnan(rec.load_factor) and rec.direction == ""
    d = rec.to_dict()
    assert d["load_factor"] is None and d["load_factor_minus"] is None
    back = micro.AssociativeRecord.from_dict(json.loads(json.dumps(d)))
    assert math.isnan(back.load_factor) and _same(back, rec)


@pytest.mark.parametrize("kw", [{}, {"relaxation": 1.0, "certify": False, "selection": "vertex"}])
def test_nonassociative_record(kw: dict) -> None:
    r = micro.solve_nonassociative(table7_wall("set14"), tuning=micro.Tuning(**kw))
    rec = r.to_record()
    assert isinstance(rec, micro.NonAssociativeRecord)
    assert rec.status == r.status and rec.converged == r.converged and rec.scheme == "a"
    assert rec.stop_reason == r.sequence.stop_reason
    # load_factor is the value to quote, the iterated LP's value beside it; NaN both when the run failed
    assert _same_number(rec.load_factor, r.load_factor) and _same_number(rec.iterated_load_factor,
                                                                          r.iterated_load_factor)
    assert rec.quoted == r.quoted and "quoted_load_factor" not in rec
    if r.converged:
        assert rec.load_factor == (r.lowest_load_factor if r.quoted == "lowest certified" else r.iterated_load_factor)
        assert rec.load_factor <= rec.iterated_load_factor
        assert min(x for x in (rec.load_factor_plus, rec.load_factor_minus) if not math.isnan(x)) == rec.load_factor
    else:
        assert math.isnan(rec.load_factor) and math.isnan(rec.iterated_load_factor) and rec.quoted == ""
    assert rec.iterations == r.iterations == len(rec.history_load_factor) - 1
    assert rec.total_iterations == sum(d.iterations for d in r.directions)
    assert rec.lambda_band == r.sequence.lambda_band and rec.mechanism_band == r.mechanism_band
    assert rec.history_load_factor == tuple(h.load_factor for h in r.sequence.history)
    assert rec.solver == "clarabel (start, certificate) + highs-simplex (iterated) + highs-ipm (cold check)"
    d = rec.to_dict()
    _flat(d)
    back = micro.NonAssociativeRecord.from_dict(json.loads(json.dumps(d)))
    assert _same(back, rec)
    if not r.converged:
        assert math.isnan(back.load_factor) and back.lambda_band is not None and back.mechanism_band is None
    s = r.summary()
    assert {k: s[k] for k in d} == d


def _same_number(a: float, b: float) -> bool:
    return a == b or (math.isnan(a) and math.isnan(b))


def test_from_dict_names_a_missing_field() -> None:
    d = micro.solve_associative(table7_wall("set12")).to_record().to_dict()
    del d["nnz"]
    with pytest.raises(KeyError, match="nnz"):
        micro.AssociativeRecord.from_dict(d)


def test_summaries_hold_no_nan_at_any_depth() -> None:
    """The summary of a run with the descent and the global search (a 5-block wall, a node-limited
    search) is strict JSON at every depth: NaN and infinities become ``null`` in the record, the
    descent's and the search's nested parts (:func:`micro.columns.json_number`)."""
    from comparison.domain.wall import WallSpec
    from micro.columns import json_number

    assert [json_number(x) for x in (0.5, 1, math.nan, math.inf, -math.inf)] == [0.5, 1.0, None, None, None]
    wall = WallSpec.from_paper(t=1, m=1, rows=2, f=0.6).to_micro()
    r = micro.solve_nonassociative(wall, lowest=True)
    g = micro.solve_global(wall, start=r, options=micro.GlobalOptions(node_limit=5))
    assert r.converged and r.lowest
    summary = r.summary(search=g)
    assert summary["global_status"] == g.status and summary["global_nodes"] == g.nodes
    text = json.dumps(summary, allow_nan=False)  # raises on any NaN or infinity left
    assert math.isnan(r.sequence.cold_load_factor) == (summary["cold_load_factor"] is None)
    assert json.loads(text)["lowest"][0]["direction"] == r.lowest[0].direction


def test_a_record_reads_as_a_mapping_of_its_fields() -> None:
    """A record is a read-only mapping of its fields (``rec["lowest_stop"]``; the values as in memory: NaN,
    tuples); ``to_dict()`` is its JSON form."""
    from collections.abc import Mapping

    r = micro.solve_nonassociative(table7_wall("set12"))
    rec = r.to_record()
    assert isinstance(rec, Mapping)
    assert rec["lowest_stop"] == rec.lowest_stop and rec["mechanism_band"] == r.mechanism_band
    names = [f.name for f in dataclasses.fields(rec)]
    assert list(rec) == names and len(rec) == len(names) and "lowest_stop" in rec
    assert dict(rec) == {n: getattr(rec, n) for n in names}
    assert rec.get("no such field") is None and "no such field" not in rec
    with pytest.raises(KeyError, match="no such field"):
        rec["no such field"]
    with pytest.raises(TypeError):
        rec["lowest_stop"] = "budget"  # type: ignore[index]
    assert {k: rec.to_dict()[k] for k in rec} == rec.to_dict()  # same keys, same order as the JSON form
    failed = micro.solve_associative(dataclasses.replace(table7_wall("set12"), live=0 * table7_wall("set12").live))
    frec = failed.to_record()
    assert math.isnan(frec["load_factor"]) and frec.to_dict()["load_factor"] is None
    assert rec == r.to_record() and rec != dict(rec)  # equality stays the record's, field by field


def test_a_field_declared_once_reaches_the_record_its_json_and_its_schema() -> None:
    """One :func:`~micro.columns.column` line is all a diagnostic the result already holds needs: the record
    reads it along its source, its JSON form and ``from_dict`` carry it, the schema documents it with its
    type and description (here ``sliding_points``, which the iterated LP's diagnostics hold). Every value
    of a record is read along a declared source: none is computed in a second place."""
    import dataclasses

    from micro.columns import column, record_of, record_schema
    from micro.records import NonAssociativeRecord

    @dataclasses.dataclass(frozen=True)
    class Extended(NonAssociativeRecord):
        sliding_points: int = column("Points of the final mechanism that slide in contact.",
                                     source="sequence.sliding_points", default=0)

    r = micro.solve_nonassociative(table7_wall("set12"))
    plain = r.to_record()
    assert type(plain) is NonAssociativeRecord and "sliding_points" not in plain
    ext = record_of(Extended, r, search=None)  # no global search composed: its fields keep their defaults
    assert _same(plain, NonAssociativeRecord.from_dict(ext.to_dict()))
    assert ext.sliding_points == r.sequence.sliding_points and ext.to_dict()["sliding_points"] == ext.sliding_points
    assert _same(Extended.from_dict(json.loads(json.dumps(ext.to_dict()))), ext)
    schema = record_schema(Extended, inherited=False)
    assert schema["sliding_points"] == {"type": "integer", "minimum": 0,
                                        "description": "Points of the final mechanism that slide in contact."}


def test_record_sources_break_off_at_none_to_the_default_and_unknown_values_are_refused() -> None:
    """A source path through an absent part (no vertex attempt, no fused wall, no global search) gives the
    field's default."""

    r = micro.solve_nonassociative(table7_wall("set12"), tuning=micro.Tuning(selection="vertex"))
    assert r.sequence.vertex_attempt is None and r.sequence.fusion is None
    rec = r.to_record()
    assert (rec.vertex_stop_reason, rec.vertex_lambda_band, rec.fused_bodies, rec.fused_points) == ("", None, 0, 0)
    assert rec.reduced is False
    assert rec.global_status == "" and math.isnan(rec.global_load_factor)


def test_every_record_field_is_described_and_typed_in_the_schema() -> None:
    """Every field of both records has a description and a JSON type (the schema's properties are made
    from them, :func:`micro.columns.record_schema`)."""
    from micro.columns import record_schema
    from micro.records import AssociativeRecord, NonAssociativeRecord

    for cls in (AssociativeRecord, NonAssociativeRecord):
        schema = record_schema(cls)
        assert list(schema) == list(cls.__dataclass_fields__)
        for name, entry in schema.items():
            assert entry["description"].strip(), name
            assert {"type", "$ref", "enum"} & set(entry), name
