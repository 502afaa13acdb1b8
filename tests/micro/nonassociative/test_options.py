"""NonAssociativeOptions: validation with the parameter named, overrides."""

from __future__ import annotations

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative import Tuning, solve_nonassociative

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey,
#: 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


def wall(t: float, m: float, rows: int = 12, storeys: int = 1, f: float = 0.75, **kw: object) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=storeys).to_micro(**kw)


@pytest.mark.parametrize(
    "kw, word",
    [
        (dict(max_iterations=1), "max_iterations"),
        (dict(directions="up"), "directions"),
        (dict(time_limit=-1.0), "time_limit"),
        (dict(max_seconds=0), "max_seconds"),
        (dict(lowest_budget=-1.0), "lowest_budget"),
        (dict(lowest_budget=float("inf")), "lowest_budget"),
        (dict(lowest="yes"), "lowest"),
    ],
)
def test_bad_options(kw: dict, word: str) -> None:
    with pytest.raises(ValueError, match=word):
        solve_nonassociative(wall(1.0, 1 / 3, rows=6), **kw)


@pytest.mark.parametrize(
    "kw, word",
    [
        (dict(scheme="c"), "scheme"),
        (dict(relaxation=0.0), "relaxation"),
        (dict(relaxation=1.5), "relaxation"),
        (dict(relaxation=True), "relaxation"),
        (dict(start="warm"), "start"),
        (dict(retry_iterations=1), "retry_iterations"),
        (dict(max_simplex_iterations=0), "max_simplex_iterations"),
    ],
)
def test_bad_tuning(kw: dict, word: str) -> None:
    with pytest.raises(ValueError, match=word):
        Tuning(**kw)


def test_options_and_tuning_are_frozen_defaults_and_overrides() -> None:
    import dataclasses

    o = micro.NonAssociativeOptions()
    assert o.max_iterations == 100 and o.lowest is True and o.lowest_budget == 100 and o.time_limit is None
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.max_iterations = 3  # type: ignore[misc]
    b = o.with_overrides(max_seconds=20)
    assert b.max_seconds == 20.0 and isinstance(b.max_seconds, float) and o.max_seconds is None
    with pytest.raises(TypeError, match="unknown option"):
        o.with_overrides(max_iteration=3)
    # a research knob is no option: it says where it lives
    with pytest.raises(TypeError, match="tuning="):
        solve_nonassociative(wall(1.0, 1 / 3, rows=6), scheme="b")
    t = Tuning()
    assert t.scheme == "a" and t.beta == 0.6 and t.relaxation is None and t.resolved_selection == "vertex+proximal"
    assert Tuning(scheme="b").resolved_selection == "vertex" and t.changed() == {}
    assert Tuning(scheme="b", relaxation=0.5).changed() == {"scheme": "b", "relaxation": 0.5}
    with pytest.raises(TypeError, match="unknown tuning knob"):
        t.with_overrides(shceme="b")
    # the options object and keyword overrides give the same run
    w = wall(1.0, 1 / 3, rows=6)
    r1 = solve_nonassociative(w, micro.NonAssociativeOptions(max_iterations=10, tuning=Tuning(scheme="b")))
    r2 = solve_nonassociative(w, tuning=Tuning(scheme="b"), max_iterations=10)
    assert [h.load_factor for h in r1.sequence.history] == [h.load_factor for h in r2.sequence.history]
    assert r1.resolved == r2.resolved and r1.summary()["options"]["relaxation"] == 0.6


def test_the_options_are_resolved_for_the_walls_size() -> None:
    """With no tuning, walls of more than FUSE_BLOCKS blocks run fused with the
    continuation; smaller ones do not; an explicit knob wins."""
    from micro.nonassociative import FUSE_BLOCKS, NonAssociativeOptions, resolve

    small, large = resolve(FUSE_BLOCKS), resolve(FUSE_BLOCKS + 1)
    assert small.selection == large.selection == "vertex+proximal" and small.tuning.retry_iterations == 40
    assert not small.fuse and not small.continuation and large.fuse and large.continuation
    assert not resolve(FUSE_BLOCKS + 1, NonAssociativeOptions(tuning=Tuning(fuse=False, continuation=False))).fuse
    assert not resolve(FUSE_BLOCKS + 1, NonAssociativeOptions(tuning=Tuning(selection="proximal"))).fuse


def test_the_descent_runs_by_default_on_every_size() -> None:
    """The descent is on by default on walls of any size; False turns it off; its budget is a count of LPs."""
    from micro.nonassociative import resolve

    assert resolve(10).options.lowest and resolve(100_000).options.lowest
    assert not resolve(100_000, micro.NonAssociativeOptions(lowest=False)).options.lowest
    for bad in (None, "auto", 1):
        with pytest.raises(ValueError, match="lowest must be True or False"):
            micro.NonAssociativeOptions(lowest=bad)  # type: ignore[arg-type]
    for bad in (-1, 2.5, True, "100"):
        with pytest.raises((ValueError, TypeError), match="lowest_budget"):
            micro.NonAssociativeOptions(lowest_budget=bad)  # type: ignore[arg-type]


def test_one_options_object_resolved_without_copies() -> None:
    """The options hold the tuning; :func:`resolve` keeps them as given and adds only what they leave to
    the wall and to each sequence (no field copied from an option or a knob: a stage reads
    ``resolved.options.time_limit``, ``resolved.tuning.scheme``); the JSON form names every option and
    knob once, the resolved values in place of the unresolved ones."""
    import dataclasses

    from micro.nonassociative import Resolved, resolve

    tuning = Tuning(scheme="b", fuse=None)
    options = micro.NonAssociativeOptions(max_iterations=7, time_limit=30, tuning=tuning)
    r = resolve(100, options)
    assert r.options is options and r.tuning is tuning
    assert (r.selection, r.fuse, r.continuation, r.max_lps) == ("vertex", False, False, 7)
    assert [f.name for f in dataclasses.fields(Resolved)] == [
        "options", "selection", "max_lps", "fuse", "continuation", "reduce", "progress"]
    assert len(dataclasses.fields(Tuning)) <= 12
    d = r.as_dict()
    names = {f.name for cls in (micro.NonAssociativeOptions, Tuning) for f in dataclasses.fields(cls)} - {"tuning"}
    assert names <= set(d) and d["relaxation"] == 0.6 and d["fuse"] is False and d["time_limit"] == 30.0
    assert micro.NonAssociativeOptions(tuning=None).tuning == Tuning()


def test_the_global_search_is_composed_after_the_run_not_an_option() -> None:
    """The iterated LP's options hold no global search (``global_`` is an unknown option, naming the
    options); its caller composes it from the result: every setting travels in one GlobalOptions, kept as
    given, and the search runs the result's directions."""
    from micro.global_search import GlobalOptions, solve_global

    w = WallSpec.from_paper(t=1, m=1, rows=2, f=0.6).to_micro()  # 5 blocks
    with pytest.raises(TypeError, match="unknown option"):
        solve_nonassociative(w, global_=True)
    r = solve_nonassociative(w)
    given = GlobalOptions(node_limit=3, direction_time_limit=None, bounds="uniform")
    g = solve_global(w, start=r, options=given)
    assert g.options is given and [d.direction for d in g.directions] == [d.direction for d in r.directions]
    assert all(d.bounds is not None and d.bounds.policy == "uniform" for d in g.directions)
