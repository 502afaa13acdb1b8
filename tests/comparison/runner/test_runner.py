"""The caching runner: records computed once, read back typed from the cache."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import pytest

import micro
from comparison.domain.wall import WallSpec
from comparison.runner import MACRO, MICRO_ASSOC, MICRO_NONASSOC, Record, ResultCache, Runner
from comparison.runner.cache import default_cache_dir
from comparison.runner.macro_record import MacroRecord
from micro.records import AssociativeRecord, NonAssociativeRecord


def test_runner_caches_and_recomputes_only_what_changed(tmp_path: Path) -> None:
    spec = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75, name="Set 12")
    lines: list[str] = []
    r1 = Runner(tmp_path, lines.append)
    a = r1.run(spec, MICRO_ASSOC)
    m = r1.run(spec, MACRO)
    assert (r1.computed, r1.hits) == (2, 0) and len(lines) == 2
    # the record holds the library's own answer (here against a vertex of the same LP, an independent solve)
    vertex = micro.solve_associative(spec.to_micro(), solver="highs-simplex").load_factor
    assert a.load_factor == pytest.approx(vertex, rel=1e-7) and not a.cached
    r2 = Runner(tmp_path)
    b = r2.run(spec, MICRO_ASSOC)
    assert (r2.computed, r2.hits) == (0, 1) and b.cached
    assert b.load_factor == a.load_factor and b.micro is not None and b.micro.blocks == 54
    assert r2.run(spec, MACRO).load_factor == m.load_factor
    # another friction is another wall: computed anew
    r2.run(WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.6), MICRO_ASSOC)
    assert r2.computed == 1
    mech = r2.mechanism(spec, MICRO_ASSOC)
    assert mech is not None and mech.velocities.shape == (54, 3)


def test_not_buildable_micro_wall_is_reported_not_raised(tmp_path: Path) -> None:
    # 600,000 rows of 200,000 blocks: beyond any memory (a wall shorter than a block is refused by WallSpec)
    spec = WallSpec.from_paper(t=1, m=1 / 3, rows=600_000, f=0.6)
    rec = Runner(tmp_path).run(spec, MICRO_ASSOC)
    assert rec.status == "not_applicable" and math.isnan(rec.load_factor)
    assert "too large" in rec.message and rec.result is None


def test_cached_records_are_typed_and_equal_to_the_computed_ones(tmp_path: Path) -> None:
    spec = WallSpec.from_paper(t=1, m=1, rows=6, f=0.75, name="small")
    first = {m: Runner(tmp_path).run(spec, m) for m in (MACRO, MICRO_ASSOC, MICRO_NONASSOC)}
    again = {m: Runner(tmp_path).run(spec, m) for m in first}
    for m, kind in ((MACRO, MacroRecord), (MICRO_ASSOC, AssociativeRecord), (MICRO_NONASSOC, NonAssociativeRecord)):
        assert isinstance(again[m].result, kind) and again[m].cached
        assert again[m].result == first[m].result
        assert again[m].failure == first[m].failure
    assert first[MICRO_ASSOC].failure is not None and first[MACRO].failure is None
    macro_rec = again[MACRO].result
    assert isinstance(macro_rec, MacroRecord)
    assert macro_rec.alpha_c_star_deg < macro_rec.alpha_c_deg  # the stepped crack is steeper


def test_a_scheme_b_method_runs_its_own_selection(tmp_path: Path) -> None:
    """A method with the tuning ``scheme="b"`` runs scheme (b) with the vertex selection (the report's
    ``vertex+proximal`` is scheme (a)'s) instead of failing on the pair."""
    spec = WallSpec.from_paper(t=1, m=1, rows=6, f=0.75, name="small")
    method = replace(MICRO_NONASSOC, tuning=(("scheme", "b"),))
    rec = Runner(tmp_path).run(spec, method)
    assert rec.nonassoc is not None and rec.nonassoc.scheme == "b", rec.message
    assert rec.nonassoc.selection == "vertex" and rec.nonassoc.vertex_stop_reason == ""
    assert Record.from_dict(rec.to_dict()).method == rec.method


def test_the_reports_method_is_the_librarys_default() -> None:
    """The runner's non-associative record of a wall is ``micro.solve_nonassociative(wall)``'s, apart
    from the seconds: the report runs the library's defaults, and its method carries no recipe knob."""
    import dataclasses

    import micro
    from comparison.runner import compute

    assert MICRO_NONASSOC.tuning == () and {f.name for f in dataclasses.fields(MICRO_NONASSOC)} == {
        "kind", "solver", "first_course", "head_joints", "tuning"}
    spec = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75, name="Set 12")
    ran = compute(spec, MICRO_NONASSOC)[0].nonassoc
    lib = micro.solve_nonassociative(spec.to_micro()).to_record()
    assert ran is not None

    def timeless(rec: NonAssociativeRecord) -> dict[str, object]:
        return {k: v for k, v in rec.to_dict().items() if "seconds" not in k}

    assert timeless(ran) == timeless(lib)
    assert lib.selection == "vertex" and lib.lowest_status == "found" and lib.lowest_stop == "finished"


def test_cache_entries_are_json_of_the_typed_record(tmp_path: Path) -> None:
    spec = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75)
    rec = Runner(tmp_path).run(spec, MICRO_ASSOC)
    path = ResultCache(tmp_path).path(spec, MICRO_ASSOC)
    stored = json.loads(path.read_text())["record"]
    assert Record.from_dict(stored).result == rec.result
    assert stored["result"]["blocks"] == 54 and stored["method"]["kind"] == "micro-assoc"


def test_no_cache_computes_each_pair_once() -> None:
    spec = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75)
    runner = Runner(None)
    a, b = runner.run(spec, MICRO_ASSOC), runner.run(spec, MICRO_ASSOC)
    assert a is b and runner.computed == 1 and runner.hits == 0
    assert runner.mechanism(spec, MICRO_ASSOC) is not None


def test_default_cache_dir(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("XCHECK_CACHE", str(tmp_path / "a"))
    assert default_cache_dir() == tmp_path / "a"
    monkeypatch.delenv("XCHECK_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_dir() == tmp_path / "xdg" / "xcheck"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert default_cache_dir() == tmp_path / "home" / ".cache" / "xcheck"
