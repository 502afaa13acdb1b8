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
    r1 = solve_nonassociative(w, micro.NonAssociativeOptions(max_iterations=10), Tuning(scheme="b"))
    r2 = solve_nonassociative(w, tuning=Tuning(scheme="b"), max_iterations=10)
    assert [h.load_factor for h in r1.sequence.history] == [h.load_factor for h in r2.sequence.history]
    assert r1.recipe == r2.recipe and r1.summary()["options"]["relaxation"] == 0.6


def test_the_recipe_is_resolved_for_the_walls_size() -> None:
    """With no tuning, walls of more than FUSE_BLOCKS blocks run fused with the
    continuation; smaller ones do not; an explicit knob wins."""
    from micro.nonassociative import FUSE_BLOCKS, recipe_for

    small, large = recipe_for(FUSE_BLOCKS), recipe_for(FUSE_BLOCKS + 1)
    assert small.selection == large.selection == "vertex+proximal" and small.tuning.retry_iterations == 40
    assert not small.fuse and not small.continuation and large.fuse and large.continuation
    assert not recipe_for(FUSE_BLOCKS + 1, tuning=Tuning(fuse=False, continuation=False)).fuse
    assert not recipe_for(FUSE_BLOCKS + 1, tuning=Tuning(selection="proximal")).fuse  # no vertex sequence


def test_the_descent_runs_by_default_on_every_size() -> None:
    """The descent is on by default on walls of any size; False turns it off; its budget is a count of LPs."""
    from micro.nonassociative import recipe_for

    assert recipe_for(10).lowest and recipe_for(100_000).lowest
    assert not recipe_for(100_000, micro.NonAssociativeOptions(lowest=False)).lowest
    for bad in (None, "auto", 1):
        with pytest.raises(ValueError, match="lowest must be True or False"):
            micro.NonAssociativeOptions(lowest=bad)  # type: ignore[arg-type]
    for bad in (-1, 2.5, True, "100"):
        with pytest.raises((ValueError, TypeError), match="lowest_budget"):
            micro.NonAssociativeOptions(lowest_budget=bad)  # type: ignore[arg-type]


def test_the_recipe_composes_the_options_and_the_tuning() -> None:
    """The recipe holds the user's options and the tuning as given, the few choices resolved for the
    wall, and every option and knob a stage reads as a field of the same name and value (one hop from
    what a user sets to what a stage reads); its JSON form names every option and knob once, the
    resolved values in place of the unresolved ones."""
    import dataclasses

    from micro.nonassociative import recipe_for
    from micro.nonassociative.config import READ

    options, tuning = micro.NonAssociativeOptions(max_iterations=7, time_limit=30), Tuning(scheme="b", fuse=None)
    r = recipe_for(100, options, tuning)
    assert r.options is options and r.tuning is tuning
    assert (r.selection, r.beta, r.fuse, r.continuation, r.max_iterations) == ("vertex", 0.6, False, False, 7)
    assert (r.time_limit, r.scheme, r.lowest_budget) == (30.0, "b", options.lowest_budget)
    assert READ and all(getattr(r, n) == getattr(options if hasattr(options, n) else tuning, n) for n in READ)
    assert len(dataclasses.fields(Tuning)) <= 12
    d = r.as_dict()
    names = {f.name for cls in (micro.NonAssociativeOptions, Tuning) for f in dataclasses.fields(cls)}
    assert names <= set(d) and d["relaxation"] == 0.6 and d["fuse"] is False and d["time_limit"] == 30.0


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


def test_no_stage_reads_the_options_or_the_tuning_through_the_recipe() -> None:
    """A stage reads ``recipe.time_limit``, never ``recipe.options.time_limit`` or ``recipe.tuning.scheme``:
    one hop, so that what a stage reads is listed in one place (the recipe's fields)."""
    import re
    from pathlib import Path

    root = Path(micro.__file__).parent / "nonassociative"
    hops = [f"{p.name}: {m}" for p in root.rglob("*.py") if p.name != "config.py"
            for m in re.findall(r"\w+\.(?:options|tuning)\.\w+", p.read_text(encoding="utf-8"))]
    assert not hops, hops
