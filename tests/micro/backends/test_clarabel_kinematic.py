"""The kinematic-form Clarabel back end: its settings are pinned, and its load
factors match the pinned vertex references to 1e-6."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.backends import CLARABEL_KINEMATIC, CLARABEL_TIGHT, MAX_RESIDUAL, ClarabelKinematicBackend

REFERENCE = json.loads((Path(__file__).parents[1] / "associative_reference.json").read_text())["walls"]
#: Relative accuracy the back end must reach against the pinned references.
REL = 1e-6


def _wall(entry: dict[str, Any]) -> micro.BlockWall:
    return WallSpec.from_paper(**entry["paper"]).to_micro(first_course=entry["first_course"],
                                                          head_joints=entry["head_joints"],
                                                          ends=entry.get("ends", "closers"))


def test_settings_are_explicit() -> None:
    """A later Clarabel whose defaults change cannot move the back end onto a
    slower linear solver or looser tolerances: everything it relies on is set."""
    lp = micro.assemble(micro.build_wall(length=6.0, block_length=3.0, block_height=1.0, rows=(2,),
                                         thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=0.6))
    s = ClarabelKinematicBackend(lp).settings
    assert s.direct_solve_method == "qdldl"
    assert s.tol_gap_abs == s.tol_gap_rel == s.tol_feas == 1e-10
    assert s.static_regularization_constant == 1e-13
    assert s.iterative_refinement_enable
    assert (s.iterative_refinement_reltol, s.iterative_refinement_abstol, s.iterative_refinement_max_iter) == (
        1e-13, 1e-12, 10)
    assert s.equilibrate_enable and s.presolve_enable and s.max_iter == 400
    assert set(CLARABEL_KINEMATIC) <= {k for k in dir(s) if not k.startswith("_")}
    assert CLARABEL_TIGHT["direct_solve_method"] == "qdldl"


def test_qdldl_is_used_where_auto_would_pick_faer() -> None:
    """3,630 blocks: Clarabel's ``auto`` chooses faer here (3x slower on one core)."""
    w = WallSpec.from_paper(t=1, m=1, rows=60, f=0.6, storeys=3).to_micro()
    backend = ClarabelKinematicBackend(micro.assemble(w))
    info = backend.solver(+1).get_info().linsolver  # set up, not solved
    assert (info.name, info.threads) == ("qdldl", 1)
    auto = ClarabelKinematicBackend(micro.assemble(w), settings={"direct_solve_method": "auto"})
    assert auto.solver(+1).get_info().linsolver.name == "faer"  # what the explicit setting guards against


@pytest.mark.parametrize("key", [k for k, e in REFERENCE.items() if e["blocks"] < 1000])
def test_small_walls_match_the_vertex_reference(key: str) -> None:
    entry = REFERENCE[key]
    r = micro.solve_associative(_wall(entry), solver="clarabel", directions="both")
    assert r.ok, r.message
    for d, ref in entry["directions"].items():
        got = r.by_direction("+x" if d == "1" else "-x")
        assert got.load_factor == pytest.approx(ref["load_factor"], rel=REL)
        assert got.info["primal_residual"] <= MAX_RESIDUAL


def test_reference_wall_1230_blocks() -> None:
    """The Table 5 reference wall: lambda to 1e-6 of the vertex, in one attempt
    (no retry), by QDLDL, in at most 50 iterations (40 measured)."""
    entry = REFERENCE["w1230 full frictional"]
    assert entry["method"] == "vertex"
    r = micro.solve_associative(_wall(entry), solver="clarabel")
    d = r.directions[0]
    assert r.ok and r.blocks == 1230 and r.mirror_symmetric
    assert r.load_factor == pytest.approx(entry["directions"]["1"]["load_factor"], rel=REL)
    assert d.info["linear_solver"] == "qdldl" and "fallback" not in d.info
    assert d.iterations <= 50
    # the two sides of the duality agree, and the live load does unit work
    assert d.info["kinematic_load_factor"] == pytest.approx(r.load_factor, rel=1e-8)
    assert d.info["live_work"] == pytest.approx(1.0, rel=1e-12)


def test_kinematic_and_static_forms_agree_on_a_cut_wall() -> None:
    w = micro.build_wall(length=13.7, block_length=3.0, block_height=1.0, rows=(8,), thickness=(1.0,),
                         overload=(0.0,), unit_weight=1.0, friction=0.6)
    kin = micro.solve_associative(w, solver="clarabel")
    ref = micro.solve_associative(w, solver="highs-simplex")
    assert kin.ok and ref.ok and len(kin.directions) == 2
    for d in kin.directions:
        assert d.load_factor == pytest.approx(ref.by_direction(d.direction).load_factor, rel=REL)


def test_degenerate_optimum_falls_back_and_says_so() -> None:
    """m = 1/4, 12 rows: base sliding governs exactly (lambda = mu = 0.75); the
    kinematic form stalls twice at residuals ~1e-9 and the static form answers."""
    w = WallSpec.from_paper(t=1, m=0.25, rows=12, f=0.75).to_micro()
    r = micro.solve_associative(w, solver="clarabel")
    assert r.ok and r.load_factor == pytest.approx(0.75, rel=REL)
    assert "static form" in r.directions[0].info["fallback"]
