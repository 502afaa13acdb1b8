"""The proximal selection: the next ``nbar`` moves towards its projection onto the fields its LP allows."""

from __future__ import annotations

import math

import numpy as np
import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative import (
    NonAssociativeOptions,
    Tuning,
    resolve,
    solve_nonassociative,
    verify_collapse_state,
)
from micro.nonassociative.iteration import LPSequence
from micro.nonassociative.model import IterationModel, restart
from micro.nonassociative.proximal import PROX_MARGIN, Projection
from micro.nonassociative.selections import detect_stall

EXACT = ("equilibrium", "coulomb", "interpenetration", "dilatancy", "slip_off_yield", "energy")


def wall(t: float, m: float, rows: int = 12, f: float = 0.75) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=1).to_micro()


@pytest.mark.parametrize("t, m", [(0.5, 1 / 3), (1.0, 1 / 3), (1.0, 1.0)])  # Table 7, Sets 11, 12 and 14
def test_proximal_sequences_end_in_exact_states(t: float, m: float) -> None:
    """A proximal sequence ends certified, in a state that passes every
    collapse condition, inside its mechanism band and below the associative
    load; each LP after the first records the step that gave its ``nbar``."""
    w = wall(t, m)
    r = solve_nonassociative(w, tuning=Tuning(selection="proximal"), lowest=False)
    assert r.converged, r.message
    lp = micro.assemble(w)
    for d in r.directions:
        q = d.sequence
        assert q is not None and q.stop_reason == "certified" and q.selection == "proximal"
        v = verify_collapse_state(lp, d)
        assert max(v[k] for k in EXACT) <= 1e-9, v
        lo, hi = q.mechanism_band
        assert lo - 1e-7 <= d.load_factor <= hi + 1e-7
        assert d.load_factor <= q.associative_load_factor + 1e-9
        steps = [h.proximal_step for h in q.history]
        assert math.isnan(steps[0]) and math.isnan(steps[1])  # the associative LP and the first LP
        assert all(0.0 <= s < 1.0 for s in steps[2:])


def _first_iterate(w: micro.BlockWall) -> tuple[micro.LimitLP, np.ndarray, float]:
    """The capacities ``nbar`` (associative normal forces) and Gilbert's LP optimum at them."""
    lp = micro.assemble(w)
    a = micro.solve_associative(w, solver="clarabel", directions="+x")
    assert a.normal is not None
    nbar = np.maximum(a.normal / lp.force_scale, 0.0)
    m = IterationModel(lp, 1, "a", 0.3)
    m.set_capacity(nbar, 0.0, 0.0, 0.0)
    out = restart(m.model)
    return lp, nbar, m.load_factor(out.x)


@pytest.mark.parametrize("solver, status", [("normal-ipm", "converged"), ("clarabel", "Solved")])
def test_projection_is_feasible(solver: str, status: str) -> None:
    """The projection carries ``lambda* (1 - PROX_MARGIN)`` with ``|s| <= mu nbar``
    and ``n >= 0``, and its step is its 1-norm distance from ``nbar``."""
    lp, nbar, lam = _first_iterate(wall(1.0, 1 / 3))
    proj = Projection(lp, 1, solver=solver).project(nbar, lam)
    assert proj.normal is not None and proj.shear is not None and proj.status == status
    assert proj.solver == solver
    n, s = proj.normal, proj.shear
    r = lp.Bn @ n + lp.Bs @ s + lam * (1.0 - PROX_MARGIN) * lp.live - lp.rhs
    assert float(np.max(np.abs(r))) <= 1e-6
    assert float(np.max(np.abs(s) - lp.mu * nbar)) <= 1e-7
    assert float(np.min(n)) >= 0.0
    assert proj.step == pytest.approx(float(np.abs(n - nbar).sum() / np.abs(nbar).sum()), rel=1e-12)
    assert 0.0 < proj.step < 1.0


def test_projection_is_no_farther_than_a_feasible_field() -> None:
    """Where ``nbar`` itself carries the load with its own capacities (the
    associative field at its load factor), the projection's objective
    ``|n - nbar|^2 / 2 + |s|^2 / 2`` is at most that field's, ``|s_assoc|^2 / 2``."""
    w = wall(1.0, 1 / 3)
    lp = micro.assemble(w)
    a = micro.solve_associative(w, solver="clarabel", directions="+x")
    assert a.normal is not None and a.shear is not None
    nbar = np.maximum(a.normal / lp.force_scale, 0.0)
    s_a = a.shear / lp.force_scale
    # the QP asks for lam (1 - margin): pass the associative load divided by it
    proj = Projection(lp, 1).project(nbar, a.load_factor / (1.0 - PROX_MARGIN))
    assert proj.normal is not None and proj.shear is not None
    objective = 0.5 * float(np.sum((proj.normal - nbar) ** 2) + np.sum(proj.shear**2))
    assert objective <= 0.5 * float(np.sum(s_a**2)) * (1 + 1e-6) + 1e-9
    assert objective < 0.5 * float(np.sum(s_a**2))  # and the field moved: shear is traded for distance


@pytest.mark.parametrize("t, m", [(1.0, 1 / 3), (1.0, 1.0)])
def test_both_projection_solvers_find_the_same_field(t: float, m: float) -> None:
    """The QP's answer is unique: the normal-equations interior point and Clarabel
    agree to 1e-5 of the largest normal force (the feasible set is thin: it asks
    for 1e-4 below the LP's optimum), with objectives within 1e-7; the interior
    point's field holds equilibrium and the capacities to 1e-10 (Clarabel's may
    exceed a capacity by its feasibility tolerance, 1e-8, and so end a little lower)."""
    lp, nbar, lam = _first_iterate(wall(t, m))
    ours = Projection(lp, 1, solver="normal-ipm").project(nbar, lam)
    theirs = Projection(lp, 1, solver="clarabel").project(nbar, lam)
    assert ours.normal is not None and ours.shear is not None
    assert theirs.normal is not None and theirs.shear is not None
    assert np.max(np.abs(ours.normal - theirs.normal)) <= 1e-5 * float(np.max(nbar))

    def objective(n: np.ndarray, s: np.ndarray) -> float:
        return 0.5 * float(np.sum((n - nbar) ** 2) + np.sum(s**2))

    assert objective(ours.normal, ours.shear) == pytest.approx(objective(theirs.normal, theirs.shear), rel=1e-7)
    r = lp.Bn @ ours.normal + lp.Bs @ ours.shear + lam * (1.0 - PROX_MARGIN) * lp.live - lp.rhs
    assert float(np.max(np.abs(r))) <= 1e-10
    assert float(np.max(np.abs(ours.shear) - lp.mu * nbar)) <= 1e-10 and float(np.min(ours.normal)) >= 0.0


def test_a_projection_the_interior_point_misses_goes_to_clarabel() -> None:
    """A QP with no feasible field (a load beyond any capacity): the normal-equations
    run does not converge, Clarabel is asked, and the projection says it was not solved."""
    lp, nbar, lam = _first_iterate(wall(1.0, 1 / 3))
    proj = Projection(lp, 1)
    out = proj.project(nbar, 50.0 * lam)
    assert out.normal is None and proj.fallbacks == 1 and out.solver == "clarabel"


def test_updated_projection_equals_a_fresh_one() -> None:
    """The QP built once and updated gives the same projection as a new one."""
    lp, nbar, lam = _first_iterate(wall(1.0, 1.0))
    kept = Projection(lp, 1)
    kept.project(nbar * 1.1, lam * 0.9)
    again = kept.project(nbar, lam)
    fresh = Projection(lp, 1).project(nbar, lam)
    assert again.normal is not None and fresh.normal is not None
    assert np.max(np.abs(again.normal - fresh.normal)) <= 1e-6 * max(1.0, float(np.max(fresh.normal)))


def test_detect_stall() -> None:
    """The proximal sequence stops only when its steps stop shrinking."""
    lams = [0.5 + 0.01 * (k % 2) for k in range(40)]  # lambda oscillating throughout
    shrinking = [0.9**k for k in range(40)]
    assert detect_stall(shrinking, lams, 20) is None
    assert detect_stall(shrinking[:39], lams, 20) is None  # too few steps
    flat = [0.1 + 0.01 * (k % 3) for k in range(40)]
    reason, band = detect_stall(flat, lams, 20)  # type: ignore[misc]
    assert reason == "stagnation" and band == (0.5, 0.51)


def test_vertex_then_proximal_retries_a_failed_direction() -> None:
    """``vertex+proximal``: Set 12's vertex sequence stopped at a cap of 4 LPs
    is run again with the proximal selection from its last normal forces; the
    result is that sequence's, exact, with the vertex attempt and the LPs of both."""
    w = wall(1.0, 1 / 3)
    lp = micro.assemble(w)
    r = solve_nonassociative(w, tuning=Tuning(retry_iterations=20), max_iterations=4, lowest=False)
    vertex = solve_nonassociative(w, tuning=Tuning(selection="vertex"), max_iterations=4, lowest=False)
    assert vertex.status == "max_iterations" and vertex.governing.normal is not None
    options = resolve(w.n_blocks, NonAssociativeOptions(max_iterations=20, lowest=False,
                                                        tuning=Tuning(selection="proximal")))
    prox = LPSequence(lp, 1, options, start=vertex.governing.normal / lp.force_scale).run()
    assert prox.converged
    assert r.converged and r.iterated_load_factor == pytest.approx(prox.load_factor, rel=1e-9)
    q = r.sequence
    assert q.selection == "proximal" and q.vertex_attempt is not None
    assert q.vertex_attempt.stop_reason == "max_iterations" and q.vertex_attempt.selection == "vertex"
    assert r.iterations == vertex.iterations + prox.iterations
    v = verify_collapse_state(lp, r.governing)
    assert max(v[k] for k in EXACT) <= 1e-9
    rec = r.to_record()
    assert rec.selection == "proximal" and rec.vertex_stop_reason == "max_iterations"


def test_proximal_needs_scheme_a() -> None:
    for sel in ("proximal", "vertex+proximal"):
        with pytest.raises(ValueError, match=f"selection '{sel.replace('+', '.')}' needs scheme 'a'"):
            Tuning(scheme="b", selection=sel)  # type: ignore[arg-type]
