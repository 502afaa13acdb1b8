"""solve_associative: bounds, mechanisms, symmetry, invariances, closed-form cases."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from micro_walls import TABLE7, table7_wall, three_storey_wall

import micro


def _walls() -> dict[str, micro.BlockWall]:
    walls = {name: table7_wall(name) for name in TABLE7}
    walls["three-storey"] = three_storey_wall()
    return walls


WALLS = _walls()


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


@pytest.mark.parametrize("solver", ["highs-ipm", "clarabel", "clarabel-static"])
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


def test_results_are_immutable_and_bad_solver_named() -> None:
    r = micro.solve_associative(table7_wall("set12"))
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.load_factor = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="solver must be one of"):
        micro.solve_associative(table7_wall("set12"), solver="gurobi")
    with pytest.raises(ValueError, match="directions"):
        micro.solve_associative(table7_wall("set12"), directions="up")  # type: ignore[arg-type]
