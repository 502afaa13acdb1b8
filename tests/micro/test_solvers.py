"""Associative LP: back ends agree, statuses, dual signs, bounds and invariances."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import micro
from micro.solvers import HighsBackend, Status, make_backend

from micro_walls import TABLE7, table7_wall, three_storey_wall

BACKENDS = ["highs", "highs-simplex", "clarabel", "cvxpy", "cvxpy-highs"]
REL = 1e-6


def _walls() -> dict[str, micro.BlockWall]:
    walls = {name: table7_wall(name) for name in TABLE7}
    walls["three-storey"] = three_storey_wall()
    return walls


WALLS = _walls()


@pytest.fixture(scope="module")
def reference() -> dict[str, micro.LimitResult]:
    return {name: micro.solve_associative(w, solver="highs-simplex") for name, w in WALLS.items()}


@pytest.mark.parametrize("name", list(WALLS))
@pytest.mark.parametrize("solver", BACKENDS)
def test_back_ends_agree(name: str, solver: str, reference: dict[str, micro.LimitResult]) -> None:
    ref = reference[name]
    r = micro.solve_associative(WALLS[name], solver=solver)
    assert ref.ok and r.ok, (ref.status, r.status, r.message)
    assert r.load_factor == pytest.approx(ref.load_factor, rel=REL)
    for d in r.directions:
        assert d.load_factor == pytest.approx(ref.by_direction(d.direction).load_factor, rel=REL)
    assert r.blocks == WALLS[name].n_blocks and r.contacts == WALLS[name].n_contacts
    assert r.points == 2 * r.contacts and r.variables == 2 * r.points + 1 and r.rows == 3 * r.blocks
    assert r.iterations > 0 and r.solve_seconds > 0 and r.build_seconds > 0


@pytest.mark.parametrize("name", list(TABLE7))
def test_base_sliding_bound_and_orduna(name: str, table7: dict[str, micro.BlockWall]) -> None:
    r = micro.solve_associative(table7[name])
    assert r.ok
    assert 0.0 < r.load_factor <= 0.75 + 1e-9
    # associative friction overestimates the non-associative micro model
    assert r.load_factor >= TABLE7[name][2]


def test_three_storey_not_symmetric_solves_both_directions() -> None:
    r = micro.solve_associative(WALLS["three-storey"])
    assert not r.mirror_symmetric
    assert {d.direction for d in r.directions} == {"+x", "-x"}
    assert r.load_factor == min(d.load_factor for d in r.directions)


@pytest.mark.parametrize("solver", ["highs", "highs-simplex", "clarabel", "cvxpy", "cvxpy-highs"])
def test_dual_sign_convention_virtual_work(solver: str) -> None:
    """Pins each back end's dual sign: raw velocities give live work +1, dead work -lambda."""
    lp = micro.assemble(WALLS["three-storey"])
    be = make_backend(lp, solver)
    for d in (1, -1):
        raw = be.solve(d)
        assert raw.status is Status.OPTIMAL
        assert d * float(lp.live @ raw.velocities) == pytest.approx(1.0, abs=1e-6)
        assert float(lp.dead @ raw.velocities) == pytest.approx(-raw.load_factor, abs=1e-6)


@pytest.mark.parametrize("name", list(WALLS))
def test_mechanism_virtual_work_balances(name: str) -> None:
    r = micro.solve_associative(WALLS[name], directions="both")
    for d in r.directions:
        m = d.mechanism
        assert m is not None
        assert m.live_work == pytest.approx(1.0, abs=1e-9)
        assert m.dead_work == pytest.approx(-d.load_factor, abs=1e-6)
        assert abs(m.virtual_work_residual(d.load_factor)) < 1e-6
        # a mechanism moves something and lets some contacts open or slide
        assert np.max(np.abs(m.velocities)) > 0
        assert m.state_counts()["closed"] < WALLS[name].n_contacts
    assert r.contact_state is not None and len(r.contact_state) == r.contacts


def test_single_block_rocking_and_sliding_by_hand() -> None:
    tall = micro.build_wall(length=1.0, block_length=1.0, block_height=4.0, rows=(1,), thickness=(1.0,),
                            overload=(0.0,), unit_weight=1.0, friction=0.75)
    r = micro.solve_associative(tall)
    assert r.load_factor == pytest.approx(0.25, rel=1e-7)  # (l/2) / (h/2)
    assert r.contact_state == ("opening",)
    u, v, w = r.velocities[0]
    assert w < 0 and u > 0  # rotates clockwise about the right base corner under +x
    flat = micro.build_wall(length=3.0, block_length=3.0, block_height=1.0, rows=(1,), thickness=(1.0,),
                            overload=(0.0,), unit_weight=1.0, friction=0.5)
    r = micro.solve_associative(flat)
    assert r.load_factor == pytest.approx(0.5, rel=1e-7)
    assert r.contact_state == ("sliding",)


def test_mirror_symmetric_wall_same_both_ways() -> None:
    w = table7_wall("set12")
    assert w.mirror_symmetric
    r = micro.solve_associative(w, directions="both")
    lp, lm = (r.by_direction(d).load_factor for d in ("+x", "-x"))
    assert lp == pytest.approx(lm, rel=1e-7)


@pytest.mark.parametrize("solver", ["highs", "clarabel"])
def test_mirrored_wall_swaps_direction(solver: str) -> None:
    kw = dict(length=13.5, block_length=3.0, block_height=1.0, rows=(8,), thickness=(1.0,), overload=(0.0,),
              unit_weight=1.0, friction=0.6)
    a = micro.solve_associative(micro.build_wall(**kw, first_course="full"), solver=solver)
    b = micro.solve_associative(micro.build_wall(**kw, first_course="half"), solver=solver)
    assert not a.mirror_symmetric
    # 9 half blocks: the "half" wall is the mirror image of the "full" one
    assert a.by_direction("+x").load_factor == pytest.approx(b.by_direction("-x").load_factor, rel=1e-6)
    assert a.by_direction("-x").load_factor == pytest.approx(b.by_direction("+x").load_factor, rel=1e-6)
    assert a.load_factor == pytest.approx(b.load_factor, rel=1e-6)
    assert a.direction != b.direction or math.isclose(a.directions[0].load_factor, a.directions[1].load_factor)


@pytest.mark.parametrize(("s_len", "s_gamma"), [(0.1, 18.0), (7.0, 0.25)])
def test_scale_invariance(s_len: float, s_gamma: float) -> None:
    base = dict(length=6.75, block_length=1.5, block_height=0.5, rows=(3, 4), thickness=(0.3, 0.5),
                overload=(1.0, 2.0), unit_weight=1.0, friction=0.6)
    r0 = micro.solve_associative(micro.build_wall(**base))
    scaled = dict(base)
    for k in ("length", "block_length", "block_height"):
        scaled[k] = base[k] * s_len
    scaled["thickness"] = tuple(t * s_len for t in base["thickness"])
    scaled["unit_weight"] = s_gamma
    scaled["overload"] = tuple(q * s_gamma * s_len**2 for q in base["overload"])
    r1 = micro.solve_associative(micro.build_wall(**scaled))
    assert r1.load_factor == pytest.approx(r0.load_factor, rel=1e-7)
    for d in ("+x", "-x"):
        assert r1.by_direction(d).load_factor == pytest.approx(r0.by_direction(d).load_factor, rel=1e-7)
    # forces scale with the weight; compare resultants (point forces need not be unique)
    assert np.sum(r1.normal) == pytest.approx(np.sum(r0.normal) * s_gamma * s_len**3, rel=1e-5)


def _without_base(w: micro.BlockWall) -> micro.BlockWall:
    keep = w.contact_kind != 0
    return dataclasses.replace(
        w, contact_a=w.contact_a[keep], contact_b=w.contact_b[keep], contact_kind=w.contact_kind[keep],
        normal=w.normal[keep], px=w.px[keep], py=w.py[keep], mu=w.mu[keep],
    )


@pytest.mark.parametrize("solver", BACKENDS)
def test_infeasible_and_unbounded_are_statuses(solver: str) -> None:
    w = table7_wall("set12")
    r = micro.solve_associative(_without_base(w), solver=solver)
    assert r.status == "infeasible" and math.isnan(r.load_factor) and not r.ok
    assert "cannot stand" in r.message
    r = micro.solve_associative(dataclasses.replace(w, live=np.zeros_like(w.live)), solver=solver)
    assert r.status == "unbounded" and math.isnan(r.load_factor)


def test_time_limit_is_a_status_not_a_number() -> None:
    w = micro.build_wall(length=30, block_length=3, block_height=1, rows=(30,), thickness=(1,), overload=(0,),
                         unit_weight=1, friction=0.6)
    r = micro.solve_associative(w, solver="highs-simplex", time_limit=1e-3)
    assert r.status in ("time_limit", "optimal")
    if r.status == "time_limit":
        assert math.isnan(r.load_factor)


def test_results_are_immutable_and_bad_solver_named() -> None:
    r = micro.solve_associative(table7_wall("set12"))
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.load_factor = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="solver must be one of"):
        micro.solve_associative(table7_wall("set12"), solver="gurobi")
    with pytest.raises(ValueError, match="directions"):
        micro.solve_associative(table7_wall("set12"), directions="up")  # type: ignore[arg-type]


def test_persistent_highs_model_takes_bound_changes_warm() -> None:
    """The design the non-associative scheme needs: add n, s columns once, then
    switch the generators off and bound |s| <= mu nbar by bound changes only."""
    w = table7_wall("set12")
    lp = micro.assemble(w)
    be = HighsBackend(lp, algorithm="simplex")
    first = be.solve(1)
    assert first.status is Status.OPTIMAL
    P = lp.n_points
    nbar = first.n
    import scipy.sparse as sp

    be.add_columns(sp.hstack([lp.Bn, lp.Bs], format="csc"),
                   np.concatenate([np.zeros(P), -lp.mu * nbar]), np.concatenate([np.full(P, np.inf), lp.mu * nbar]))
    be.set_col_bounds(np.arange(2 * P), np.zeros(2 * P), np.zeros(2 * P))
    second = be.solve(1)
    assert second.status is Status.OPTIMAL
    # the associative optimum stays feasible: lambda cannot drop; the basis was reused
    assert second.load_factor >= first.load_factor - 1e-9
    assert second.iterations < first.iterations
    assert np.all(np.abs(second.s) <= lp.mu * nbar + 1e-7)
