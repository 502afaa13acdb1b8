"""The polish of the kinematic back end's static forces onto exact equilibrium
(:mod:`micro.backends.polish`): it closes the residual, keeps every generator's
sign, moves the load factor by a rounding correction only, and makes a heavily
loaded wall pass the re-check it failed."""

from __future__ import annotations

import numpy as np
import pytest
from micro_walls import table7_wall

import micro
from comparison.domain.wall import WallSpec
from micro.backends import MAX_RESIDUAL, ClarabelKinematicBackend, Status, polish
from micro.backends.polish import Polished, polish_equilibrium

#: A polished residual within this many rounding units of the largest force
#: (measured: 1e-16 to 1e-15 of it).
ROUNDING_UNITS = 100 * np.finfo(float).eps


def loaded_wall() -> micro.BlockWall:
    """560 blocks, five storeys, floors with overloading ratio p = 64: generators up to
    1.2e5 block weights, Set 17's scale (1.7e5) at a thirteenth of its blocks. Clarabel's
    forces miss equilibrium by 3.6e-6 block weights here (Set 17: 4.1e-6)."""
    return WallSpec.from_paper(t=1.0, m=1 / 3, rows=40, f=0.75, p=64.0, storeys=5).to_micro()


WALLS = {
    "set11": table7_wall("set11"),
    "set14 half frictionless": table7_wall("set14", first_course="half", head_joints="frictionless"),
    "set13 half": table7_wall("set13", first_course="half"),
    "cut": micro.build_wall(length=13.7, block_length=3.0, block_height=1.0, rows=(8,), thickness=(1.0,),
                            overload=(0.0,), unit_weight=1.0, friction=0.6, ends="cut"),
    "loaded": loaded_wall(),
}


def _raw(wall: micro.BlockWall) -> tuple[ClarabelKinematicBackend, np.ndarray, float, float]:
    """The back end, the generators and load factor read from Clarabel's duals
    (no polish), and the kinematic objective."""
    backend = ClarabelKinematicBackend(micro.assemble(wall))
    sol = backend.solver(+1).solve()
    assert str(sol.status).split(".")[-1] == "Solved"  # not a degenerate optimum's AlmostSolved
    z, x = np.asarray(sol.z), np.asarray(sol.x)
    return backend, z[1:], -float(z[0]), float(backend.lp.rhs @ x) / backend.work_scale


def _polish(name: str) -> tuple[Polished, np.ndarray, float, float, ClarabelKinematicBackend]:
    backend, g, lam, kinematic_lam = _raw(WALLS[name])
    return polish_equilibrium(backend.A_g, backend.lp.live, backend.lp.rhs, g, lam), g, lam, kinematic_lam, backend


@pytest.mark.parametrize("name", list(WALLS))
def test_polish_closes_the_residual_keeps_signs_and_lambda(name: str) -> None:
    p, g, lam, kinematic_lam, backend = _polish(name)
    assert p.residual_before > 0.0 and p.steps >= 1
    assert p.residual < p.residual_before
    floor = ROUNDING_UNITS * max(1.0, float(g.max()))
    assert p.residual <= floor
    # every generator keeps its sign (Clarabel's are all > 0) and the state is admissible
    assert np.all(g > 0.0) and np.all(p.g > 0.0)
    lp = backend.lp
    full = np.zeros(2 * lp.n_points)
    full[backend.active] = p.g
    assert lp.primal_residual(*lp.forces(full), p.load_factor) <= floor  # the re-check's own arithmetic
    # a rounding correction of lambda, towards the lower bound the state now certifies
    assert abs(p.load_factor - lam) <= polish.POLISH_MAX_LOAD_FACTOR_CHANGE * max(1.0, abs(lam))
    assert p.load_factor <= kinematic_lam * (1.0 + 1e-12)


def test_the_loaded_wall_fails_without_the_polish_and_passes_with_it() -> None:
    """The Set 17 failure at 560 blocks: the forces read from the duals fail the
    re-check; polished, they pass it, lambda within the tolerance of the unpolished
    value and within 1e-8 of the kinematic objective."""
    lp = micro.assemble(loaded_wall())
    bare = ClarabelKinematicBackend(lp, polish=False).solve(+1)
    assert bare.status is Status.INACCURATE and bare.info["primal_residual"] > MAX_RESIDUAL
    out = ClarabelKinematicBackend(lp).solve(+1)
    assert out.ok and out.info["primal_residual"] <= 1e-9
    assert out.info["unpolished_residual"] == bare.info["primal_residual"]
    assert out.info["unpolished_load_factor"] == bare.info["raw_load_factor"]
    assert out.info["polish_steps"] >= 1 and out.seconds >= out.info["polish_seconds"] > 0.0
    assert abs(out.load_factor - out.info["unpolished_load_factor"]) <= polish.POLISH_MAX_LOAD_FACTOR_CHANGE
    assert out.load_factor == pytest.approx(out.info["kinematic_load_factor"], rel=1e-8)
    r = micro.solve_associative(loaded_wall(), solver="clarabel")
    assert r.ok and r.load_factor == out.load_factor


def test_the_polish_is_rejected_when_it_moves_lambda_too_far(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(polish, "POLISH_MAX_LOAD_FACTOR_CHANGE", 0.0)
    out = ClarabelKinematicBackend(micro.assemble(loaded_wall())).solve(+1)
    assert out.status is Status.INACCURATE and np.isnan(out.load_factor)
    assert "the polish moved lambda" in out.info["polish_rejected"]


def test_a_passing_solve_is_not_polished() -> None:
    """Forces that pass the re-check come back as Clarabel gave them: the polish
    cannot make a passing solve fail, nor move its load factor."""
    lp = micro.assemble(WALLS["set11"])
    on, off = ClarabelKinematicBackend(lp).solve(+1), ClarabelKinematicBackend(lp, polish=False).solve(+1)
    assert on.ok and off.ok and on.load_factor == off.load_factor
    assert "polish_steps" not in on.info
    assert on.n is not None and off.n is not None and np.array_equal(on.n, off.n)
