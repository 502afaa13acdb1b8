"""Back ends of the associative LP: they agree, map statuses, and sign duals the shared way."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from micro_walls import TABLE7, table7_wall, three_storey_wall

import micro
from micro.backends import Status, make_backend

BACKENDS = ["highs-ipm", "highs-simplex", "clarabel", "clarabel-static", "normal-ipm", "cvxpy", "cvxpy-highs"]
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


@pytest.mark.parametrize("solver", BACKENDS)
def test_dual_sign_convention_virtual_work(solver: str) -> None:
    """Pins each back end's dual sign: raw velocities give live work +1, dead work -lambda."""
    lp = micro.assemble(WALLS["three-storey"])
    be = make_backend(lp, solver)
    for d in (1, -1):
        raw = be.solve(d)
        assert raw.status is Status.OPTIMAL
        assert d * float(lp.live @ raw.duals) == pytest.approx(1.0, abs=1e-6)
        assert float(lp.dead @ raw.duals) == pytest.approx(-raw.load_factor, abs=1e-6)


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


@pytest.mark.parametrize("solver", ["highs-ipm", "clarabel", "clarabel-static", "normal-ipm", "cvxpy"])
def test_outcome_is_one_type_for_success_and_failure(solver: str) -> None:
    w = table7_wall("set12")
    lp = micro.assemble(w)
    ok = make_backend(lp, solver).solve(1)
    assert isinstance(ok, micro.Outcome) and ok.ok and ok.iterations > 0
    assert ok.n is not None and ok.duals is not None and ok.info["primal_residual"] <= 1e-6
    bad = make_backend(micro.assemble(_without_base(w)), solver).solve(1)
    assert isinstance(bad, micro.Outcome) and not bad.ok and bad.status is Status.INFEASIBLE
    assert math.isnan(bad.load_factor) and bad.n is None and bad.duals is None
    with pytest.raises(dataclasses.FrozenInstanceError):
        ok.load_factor = 1.0  # type: ignore[misc]


def test_every_back_end_has_a_status_map() -> None:
    from micro.backends import (
        ClarabelKinematicBackend,
        ClarabelStaticBackend,
        CvxpyBackend,
        HighsBackend,
        PersistentHighsModel,
    )

    for cls in (ClarabelStaticBackend, ClarabelKinematicBackend, CvxpyBackend, HighsBackend, PersistentHighsModel):
        assert Status.OPTIMAL in cls.STATUS_MAP.values() and Status.INFEASIBLE in cls.STATUS_MAP.values()
