"""``comparison.compare``: the verdict on the macro model and its proof, on the paper's walls and on the rule.

What may be concluded: a macro λ above the associative λ is unsafe by that bound (the non-associative solve
is then not needed); above a certified collapse state's λ, unsafe by that state; below every state found,
"not refuted" (never "safe" without a closed global search's bound); a method that fails leaves only the
verdict that was proven.
"""

from __future__ import annotations

import importlib
import json
import math
from pathlib import Path
from typing import Any

import pytest

import comparison
import micro
from comparison.domain.proof import ACCURACY, judge
from comparison.domain.verdict import CompareOptions, Comparison
from comparison.domain.wall import WallSpec

SET12 = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75)
SET13 = WallSpec.from_paper(t=1, m=1 / 2, rows=12, f=0.75)
#: Two storeys of 12 rows, t = 1, m = 1/3, f = 0.75 (204 blocks): the macro λ (0.6285) lies above the
#: associative λ (0.6143), so the associative bound settles the verdict.
ABOVE_BOUND = WallSpec.from_paper(t=1, m=1 / 3, rows=24, f=0.75, storeys=2)
COMPARE = importlib.import_module("comparison.domain.verdict")


@pytest.fixture(scope="module")
def set12() -> Comparison:
    return comparison.compare(SET12)


@pytest.fixture(scope="module")
def set13() -> Comparison:
    return comparison.compare(SET13, full=True)


def test_set13_unsafe_by_certified_state(set13: Comparison) -> None:
    c = set13
    assert (c.verdict, c.proof, c.status, c.diagnostics) == ("unsafe", "certified state", "ok", ())
    assert c.micro_quoted == "lowest certified" and c.certified_load_factor == c.micro_load_factor
    assert c.macro_load_factor > c.micro_load_factor * (1 + ACCURACY)
    assert c.macro_load_factor < c.associative_load_factor  # the bound alone would not settle it
    assert c.micro_load_factor <= c.iterated_load_factor <= c.associative_load_factor
    assert c.difference_percent == pytest.approx(100 * (c.macro_load_factor / c.micro_load_factor - 1), rel=1e-12)
    assert c.sentence().startswith("The macro model is unsafe for this wall: its λ 0.4914 is above the certified "
                                   "collapse state's 0.4895 (+0.4 %)")
    assert not c.search_stopped and c.to_dict()["search_stopped"] is False


def test_set13_search_stops_below_the_macro_value() -> None:
    """Without ``full`` the search stops at the first certified state below the macro λ (here the iterated
    LP's, 0.021 % below it: more than the solvers' accuracy), which proves the verdict; no descent LP runs."""
    c = comparison.compare(SET13)
    assert (c.verdict, c.proof, c.status) == ("unsafe", "certified state", "ok")
    assert c.search_stopped and c.to_dict()["search_stopped"] is True
    assert c.micro_load_factor == c.iterated_load_factor == pytest.approx(0.4912758, abs=1e-7)
    assert c.macro_load_factor > c.micro_load_factor * (1 + ACCURACY)
    na = c.nonassociative_result
    assert na is not None and [low.stop for low in na.lowest] == ["target"] and na.lowest[0].lps == 0
    assert any("stopped at the first certified state below the macro" in d for d in c.diagnostics)


def test_set12_not_refuted(set12: Comparison) -> None:
    c = set12
    assert (c.verdict, c.proof, c.status) == ("not refuted", None, "ok")
    assert c.macro_load_factor < c.micro_load_factor < c.associative_load_factor
    assert c.micro_load_factor == pytest.approx(0.6911, abs=1e-4)
    assert c.sentence() == ("The macro model is not refuted for this wall: its λ 0.6481 lies below every collapse "
                            "state found (lowest certified 0.6911, −6.2 %); no lower bound was computed.")


def test_the_models_values_are_theirs(set12: Comparison) -> None:
    """The comparison reports the models' own values, not recomputed ones."""
    import macro

    assert set12.macro_load_factor == macro.solve(SET12.to_macro()).load_factor
    assert set12.macro_mechanism == set12.macro_result.mechanism  # type: ignore[union-attr]
    na = set12.nonassociative_result
    assert na is not None and set12.micro_load_factor == na.load_factor
    assert set12.associative_load_factor == pytest.approx(na.associative_load_factor, rel=1e-6)
    assert set12.local_mechanism is None and set12.blocks == 54


def test_associative_bound_settles_without_the_nonassociative_solve(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[str] = []
    real = COMPARE.solve_micro

    def spy(wall: micro.BlockWall, friction: str, options: CompareOptions, **kw: Any) -> Any:
        calls.append(friction)
        return real(wall, friction, options, **kw)

    monkeypatch.setattr(COMPARE, "solve_micro", spy)
    c = comparison.compare(ABOVE_BOUND)
    assert calls == ["associative"]
    assert (c.verdict, c.proof, c.status) == ("unsafe", "associative bound", "ok")
    assert not c.nonassociative_run and math.isnan(c.micro_load_factor) and math.isnan(c.seconds.nonassociative)
    assert c.macro_load_factor > c.associative_load_factor * (1 + ACCURACY)
    assert "skipped" in c.diagnostics[0]
    calls.clear()
    full = comparison.compare(ABOVE_BOUND, full=True)
    assert calls == ["associative", "nonassociative"] and full.local_mechanism is None
    # both prove it; the certified state (0.5838, +7.7 %) by a larger margin than the bound (+2.3 %): cited
    assert (full.verdict, full.proof) == ("unsafe", "certified state") and full.nonassociative_run
    assert full.micro_load_factor <= full.associative_load_factor and full.diagnostics == ()
    assert full.sentence().startswith("The macro model is unsafe for this wall: its λ 0.6285 is above the certified "
                                      "collapse state's 0.5838 (+7.7 %)")


@pytest.mark.usefixtures("failing_nonassociative")
def test_a_failed_solve_leaves_only_what_was_proven() -> None:
    c = comparison.compare(SET13)  # unsafe by a certified state when the solve converges: now nothing proves it
    assert (c.status, c.verdict, c.proof) == ("failed", None, None)
    assert math.isnan(c.micro_load_factor) and math.isnan(c.difference_percent)
    assert any("non-associative solve failed" in d for d in c.diagnostics)
    assert c.sentence().startswith("No verdict for this wall")
    bound = comparison.compare(ABOVE_BOUND, full=True)  # the bound holds whatever the solve did
    assert (bound.status, bound.verdict, bound.proof) == ("failed", "unsafe", "associative bound")


@pytest.mark.parametrize(
    ("args", "kwargs", "expected"),
    [
        ((0.61, 0.505), {}, ("unsafe", "associative bound")),
        ((0.5, 0.5 * (1 + 0.5 * ACCURACY)), {}, (None, None)),  # within the accuracy: not above the bound
        ((0.5 * (1 + 2 * ACCURACY), 0.6, 0.5), {"found_load_factor": 0.5}, ("unsafe", "certified state")),
        ((0.5 * (1 + 0.5 * ACCURACY), 0.6, 0.5), {"found_load_factor": 0.5}, ("not refuted", None)),  # agrees
        ((0.45, 0.6, 0.5), {"found_load_factor": 0.5}, ("not refuted", None)),
        ((0.45, 0.6, 0.5), {"found_load_factor": 0.5, "global_lower_bound": 0.49}, ("safe", "global bound")),
        ((0.45, 0.6, 0.5), {"found_load_factor": 0.5, "global_lower_bound": 0.45}, ("not refuted", None)),
        ((0.45, 0.6, 0.5), {}, (None, None)),  # no non-associative value: nothing to be below
        ((0.45, 0.6), {"found_load_factor": 0.5}, ("not refuted", None)),  # below a state not certified
        ((0.55, 0.6), {"found_load_factor": 0.5}, (None, None)),  # above a state not certified: no proof
        ((math.nan, 0.6, 0.5), {"found_load_factor": 0.5}, (None, None)),  # the macro model failed
        ((0.7, math.nan, 0.5), {"found_load_factor": 0.5}, ("unsafe", "certified state")),  # no associative LP
        ((0.61, 0.6, 0.5), {"found_load_factor": 0.5}, ("unsafe", "certified state")),  # the larger margin
        ((0.61, 0.6, math.nan), {"found_load_factor": 0.5}, ("unsafe", "associative bound")),
    ],
)
def test_judge(args: tuple[float, ...], kwargs: dict[str, Any], expected: tuple[str | None, str | None]) -> None:
    assert judge(*args, **kwargs) == expected


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [({"first_course": "third"}, "first_course"), ({"head_joints": "glued"}, "head_joints"),
     ({"time_limit": 0}, "time_limit"), ({"node_limit": 5}, "node_limit"),
     ({"global_": True, "node_limit": 0}, "node_limit")],
)
def test_bad_options_name_themselves(kwargs: dict[str, Any], word: str) -> None:
    with pytest.raises(ValueError, match=word):
        CompareOptions(**kwargs)


def test_not_a_wall_spec() -> None:
    with pytest.raises(TypeError, match="WallSpec"):
        comparison.compare({"t": 1})  # type: ignore[arg-type]


#: t = 3/2, m = 1/3, 16 rows, f = 0.65, cut ends (72 blocks): the top course's cut end piece (1/6 of a block
#: wide) tips over alone, at ``lambda = (w/b)(1 + mu^2)/(1 - mu^2 + 2 mu w/b)`` in the associative LP; the
#: verdict rests on the wall as built, the held wall (every sliver held) is reported beside it.
CUT_TOP = WallSpec.from_paper(t=1.5, m=1 / 3, rows=16, f=0.65, ends="cut")


def test_a_local_mechanism_is_named_and_the_wall_as_built_is_compared() -> None:
    c = comparison.compare(CUT_TOP)
    loc = c.local_mechanism
    assert loc is not None and loc["method"] == "associative"  # the bound settles it: no non-associative solve
    assert "cut end piece of course 16" in loc["description"]
    w_b, mu = 1 / 6, 0.65  # the piece's width over its height (block heights), the friction coefficient
    assert loc["load_factor"] == pytest.approx(w_b * (1 + mu**2) / (1 - mu**2 + 2 * mu * w_b), rel=1e-6)
    # the value compared is the wall as built's; the held wall's is higher, beside it, and no proof uses it
    assert c.associative_load_factor == loc["load_factor"]
    assert loc["held_load_factor"] > loc["load_factor"] * 1.5
    assert c.associative_wall is not None and c.associative_wall.n_blocks == c.blocks
    assert (c.verdict, c.proof) == ("unsafe", "associative bound")
    assert "The wall as built collapses there by a local mechanism: the cut end piece of course 16" in c.sentence()
    assert c.to_dict()["local_mechanism"]["description"] == loc["description"]
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((Path(__file__).parents[2] / "docs" / "schemas" / "compare.schema.json").read_text())
    doc = json.loads(json.dumps({**c.to_dict(), "wall": {}, "paper_parameters": {}, "plot": None}))
    errors = [e.message for e in jsonschema.Draft202012Validator(schema).iter_errors(doc)
              if e.path and e.path[0] == "local_mechanism"]
    assert errors == []


def test_global_runs_on_the_wall_as_built() -> None:
    """Two rows, t = 40/31, m = 1, f = 0.6 with cut ends: the 0.05-wide top piece tips over alone (0.05); the
    global search of the wall as built cannot prove it safe (the held wall's bound, 0.3797, is another wall's);
    with closers (the default) the wall has no sliver and the search's bound is its own."""
    spec = WallSpec.from_paper(t=40 / 31, m=1, rows=2, f=0.6, ends="cut")
    c = comparison.compare(spec, full=True, global_=True)
    assert c.verdict == "unsafe" and c.micro_load_factor == pytest.approx(0.05, rel=1e-6)
    assert c.global_lower_bound <= 0.05 * (1 + ACCURACY)
    closers = comparison.compare(WallSpec.from_paper(t=40 / 31, m=1, rows=2, f=0.6), global_=True)
    assert closers.local_mechanism is None and closers.blocks == 4
    assert closers.global_status == "optimal" and closers.global_lower_bound == pytest.approx(0.3797, abs=1e-4)


def test_no_local_mechanism_on_the_paper_s_walls(set12: Comparison, set13: Comparison) -> None:
    assert set12.local_mechanism is None and set13.local_mechanism is None
    assert set13.associative_wall is not None and set13.associative_wall.n_blocks == set13.blocks


def test_a_value_that_is_absent_is_none_in_python_as_in_json(set12: Comparison) -> None:
    """A value that is absent (``global_status``, ``micro_quoted``, ``macro_mechanism`` without one) is
    ``None`` in Python as it is ``null`` in the JSON."""
    d = set12.to_dict()
    assert set12.global_status is None and d["global_status"] is None
    for name in ("global_status", "micro_quoted", "macro_mechanism", "verdict", "proof"):
        assert getattr(set12, name) == d[name], name


def test_a_comparison_has_a_flat_record(set12: Comparison) -> None:
    """``to_record()``: a read-only mapping of the numbers, the verdict and the bond; its JSON form round-trips,
    and every field named as a key of ``--json`` holds the same value there."""
    from comparison.domain.comparison_record import ComparisonRecord

    rec = set12.to_record()
    assert rec["verdict"] == "not refuted" and rec["micro_load_factor"] == set12.micro_load_factor
    assert rec["ends"] == "closers" and rec["local_description"] == "" and math.isnan(rec["held_load_factor"])
    assert rec["total_seconds"] == set12.seconds.total and list(rec)[0] == "verdict"
    with pytest.raises(KeyError):
        rec["no such field"]
    back = ComparisonRecord.from_dict(json.loads(json.dumps(rec.to_dict())))
    assert back.to_dict() == rec.to_dict()
    doc = set12.to_dict()
    shared = [k for k in rec if k in doc]
    assert len(shared) >= 20 and all(rec.to_dict()[k] == doc[k] for k in shared)


def test_the_record_names_the_local_mechanism_and_the_held_wall() -> None:
    c = comparison.compare(CUT_TOP)
    rec = c.to_record()
    assert rec["local_description"] == c.local_mechanism["description"]  # type: ignore[index]
    assert rec["held_load_factor"] == c.local_mechanism["held_load_factor"] > rec["associative_load_factor"]  # type: ignore[index]
