"""The report's explicit run plan: what it lists, and that it is built without running anything."""

from __future__ import annotations

from dataclasses import replace

import pytest

from comparison.domain.cases import case, cases_in_table
from comparison.report.plan import NONASSOC_MAX_BLOCKS, approximate_blocks, build_plan
from comparison.runner import MICRO_ASSOC, MICRO_NONASSOC, Runner


def test_quick_plan_lists_every_pair_once_and_runs_nothing() -> None:
    runner = Runner(None)
    plan = build_plan(quick=True)
    items = plan.items()
    pairs = [(it.spec, it.method) for it in items]
    assert len(pairs) == len(set(pairs))
    assert runner.computed == 0
    assert all(c.rows <= 12 for c in plan.cases)
    assert {c.case for c in cases_in_table("7")} <= {c.case for c in plan.cases}
    # the bond variants of Table 7 and the speed study's back ends are in the plan
    set12 = case("12").spec()
    assert (set12, replace(plan.methods[0], first_course="half")) in pairs
    assert (set12, replace(MICRO_NONASSOC, head_joints="frictionless")) in pairs
    assert (plan.speed_spec(3), replace(MICRO_ASSOC, solver="cvxpy")) in pairs
    assert not any(it.skip for it in items)


def test_full_plan_skips_the_iterated_lp_on_large_walls() -> None:
    """The paper's walls up to 4,000 blocks (Set 10, fused) run, the Table 9
    walls and the other walls above 2,000 blocks do not."""
    plan = build_plan(quick=False)
    skipped = {(it.spec.name, it.method.kind) for it in plan.items() if it.skip}
    assert ("Set 15", "micro-nonassoc") in skipped and ("Set 10", "micro-nonassoc") not in skipped
    assert ("Ref", "micro-nonassoc") not in skipped and ("102 rows", "micro-nonassoc") in skipped
    assert all(kind == "micro-nonassoc" for _, kind in skipped)
    big = [it for it in plan.items() if it.skip]
    assert all(approximate_blocks(it.spec) > NONASSOC_MAX_BLOCKS for it in big)
    assert plan.reference == MICRO_NONASSOC


def test_speed_walls_reach_7575_blocks_against_the_finest_iterated_lp() -> None:
    plan = build_plan(quick=False)
    assert max(approximate_blocks(plan.speed_spec(r)) for r in plan.resolutions) >= 7575
    # the reference is the finest wall the iterated LP runs on, not the finest wall
    assert plan.reference_rows == 60 < plan.resolutions[-1]
    runs = {(it.spec.name, it.method.kind, it.method.solver) for it in plan.items() if not it.skip}
    for solver in plan.solvers:
        assert ("150 rows", "micro-assoc", solver) in runs
    assert not any(name == "150 rows" and kind == "micro-nonassoc" for name, kind, _ in runs)
    assert build_plan(quick=True).reference_rows == 12


def test_results_refuse_a_pair_outside_the_plan() -> None:
    from comparison.report.computed import Results

    plan = build_plan(quick=True)
    res = Results(plan, {}, {}, {}, 0.0)
    with pytest.raises(KeyError):
        res.record(case("Ref").spec(), MICRO_ASSOC)


def test_the_reports_associative_method_is_the_library_default() -> None:
    """The report's associative records are what ``micro.solve_associative(wall)`` runs."""
    import micro
    from comparison.report.plan import micro_methods

    assert MICRO_ASSOC.solver == micro.DEFAULT_SOLVER
    assert micro_methods()[0] == MICRO_ASSOC
    assert build_plan(quick=False).methods[0] == MICRO_ASSOC


@pytest.mark.parametrize("skip", ["not_run", "not_applicable"])
def test_all_cases_explains_n_a_only_where_a_cell_shows_it(skip: str) -> None:
    """REPORT.md's "All cases" table carries the note explaining n/a only when a cell shows n/a (a note
    with nothing to explain misleads)."""
    import macro
    from comparison.report.computed import Results
    from comparison.report.tables import all_cases
    from comparison.runner import Record

    plan = build_plan(quick=True)
    results = {c.spec(): macro.solve(c.spec().to_macro()) for c in plan.cases}
    records = {(c.spec(), m): Record(c.label, m, 0.0, skipped="not_run") for c in plan.cases for m in plan.methods}
    first = plan.cases[0]
    records[(first.spec(), plan.methods[0])] = Record(first.label, plan.methods[0], 0.0, skipped=skip)  # type: ignore[arg-type]
    table = all_cases(Results(plan, results, records, {}, 0.0))
    cells = [c for row in table.rows for c in row]
    assert ("n/a" in cells) is (skip == "not_applicable")
    assert table.note.startswith("n/a: the micro wall cannot be built") is (skip == "not_applicable")
    assert "Set 8: L = 20, l = 3" in table.note  # the cut blocks are said either way
