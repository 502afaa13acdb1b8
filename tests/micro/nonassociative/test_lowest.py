"""The lowest certified collapse state: the descent and its two LPs."""

from __future__ import annotations

import math

import numpy as np
import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative import Tuning, solve_nonassociative, verify_collapse_state
from micro.nonassociative.descent.lowest import EXACT_TOL, LOWEST_TOL, Descent, is_exact, lowest_state
from micro.nonassociative.descent.states import ForceLP, refine, restricted_columns
from micro.nonassociative.model import IterationModel, restart

#: Table 7 of the paper (single storey, 12 rows, f = 0.75): (t, m) and the
#: lowest certified load factor the descent reaches (full first course,
#: frictional head joints), below the iterated LP's 0.7144, 0.7086, 0.4913, 0.2684.
#: Regression pins of the warm descent, each state certified by
#: verify_collapse_state in check_states; Set 11 was 0.7005249 from the cold
#: descent, whose Gilbert steps started from another vertex.
TABLE7 = {"set11": ((0.5, 1 / 3), 0.6999976), "set12": ((1.0, 1 / 3), 0.6911080),
          "set13": ((1.0, 1 / 2), 0.4894591), "set14": ((1.0, 1.0), 0.2658313)}


def wall(t: float, m: float, rows: int = 12, f: float = 0.75, **kw: object) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=1).to_micro(**kw)


def check_states(w: micro.BlockWall, r: micro.NonAssociativeResult) -> None:
    """Every state the descent reports is an exact collapse state, at most the
    iterated LP's load factor, reached by a path that never goes up."""
    lp = micro.assemble(w)
    assert r.converged and len(r.lowest) == len(r.directions)
    for low, d in zip(r.lowest, r.directions, strict=True):
        assert low.found and low.state is not None, low.message
        res = verify_collapse_state(lp, low.state)
        assert all(v <= EXACT_TOL for k, v in res.items() if k != "slipping_points"), res
        assert res == pytest.approx(low.residuals, abs=1e-15)
        assert low.load_factor <= d.load_factor * (1 + 1e-12)
        assert all(b <= a * (1 + 1e-12) for a, b in zip(low.path, low.path[1:], strict=False))
        assert low.path[-1] == low.load_factor
        assert low.band is not None and low.band[0] == low.load_factor <= low.band[1] * (1 + 1e-9)
        assert low.band[1] <= d.sequence.associative_load_factor * (1 + 1e-7)
    assert r.lowest_load_factor == min(low.load_factor for low in r.lowest) <= r.load_factor


@pytest.mark.parametrize("name", list(TABLE7))
def test_table7_lowest_states(name: str, table7_default: list[micro.NonAssociativeResult]) -> None:
    """On Table 7's walls the descent reaches an exact state below the lower
    end of the iterated LP's band; every state it reports passes the check."""
    (t, m), lam = TABLE7[name]
    w = wall(t, m)
    r = table7_default[list(TABLE7).index(name)]  # solve_nonassociative(w), shared (conftest.py)
    check_states(w, r)
    assert r.lowest_load_factor <= r.mechanism_band[0] * (1 + 1e-9)
    assert r.lowest_load_factor == pytest.approx(lam, rel=1e-6)
    # the default budget lets the descent finish here (the pinned values are unbounded descents)
    low = r.lowest[0]
    assert low.stop == "finished" and r.to_record().lowest_stop == "finished" and low.lps < low.budget


def test_a_descent_that_spends_its_budget_keeps_its_best_state() -> None:
    """With a budget of a few LPs the descent stops there (the same LPs on
    every machine: it counts LPs, not seconds), says so, and returns the
    lowest certified state it found so far: exact, at most the iterated LP's,
    at least the unbounded descent's."""
    (t, m), lam = TABLE7["set13"]
    w = wall(t, m)
    runs = [solve_nonassociative(w, lowest_budget=5) for _ in range(2)]
    r = runs[0]
    low = r.lowest[0]
    assert low.stop == "budget" and r.to_record().lowest_stop == "budget"
    assert low.budget == 5
    assert low.lps == low.budget + 1  # + the band
    check_states(w, r)
    assert lam * (1 - 1e-9) <= r.lowest_load_factor <= r.load_factor
    assert [x.lowest[0].path for x in runs] == [low.path, low.path] and runs[1].lowest[0].lps == low.lps


@pytest.mark.parametrize("kw", [dict(t=2.0, m=1 / 2, rows=6, f=0.6), dict(t=0.75, m=1 / 2, rows=6),
                                dict(t=1.0, m=1 / 3, first_course="half"),
                                dict(t=1.0, m=1 / 2, head_joints="frictionless")])
def test_other_walls(kw: dict) -> None:
    """Walls with both load directions, a half first course, frictionless head joints."""
    w = wall(**kw)
    r = solve_nonassociative(w)
    check_states(w, r)
    if kw.get("head_joints") == "frictionless":
        assert all(not low.moves for low in r.lowest)  # no head-joint friction to release


def test_lower_end_is_a_fixed_point_of_the_iterated_lp() -> None:
    """Gilbert's LP with nbar = the lower end's normal forces returns the
    lower end's load factor: the iterated LP's next step cannot descend."""
    w = wall(1.0, 1 / 3)
    lp = micro.assemble(w)
    r = solve_nonassociative(w, lowest=False)
    v = r.governing.mechanism.velocities.ravel()
    f = ForceLP(lp, 1).solve(restricted_columns(lp, v))
    assert f is not None and f.load_factor == pytest.approx(r.mechanism_band[0], rel=1e-7)
    model = IterationModel(lp, 1, "a", 0.3)
    model.set_capacity(f.n, 0.0, 0.0, 0.0)
    out = restart(model.model)
    assert out.x is not None
    assert model.load_factor(out.x) == pytest.approx(f.load_factor, rel=1e-9)


def test_polish_never_goes_up_and_keeps_exact_states() -> None:
    """Polish from the iterated LP's mechanism: at most its band's lower end."""
    w = wall(1.0, 1 / 3, first_course="half")
    lp = micro.assemble(w)
    r = solve_nonassociative(w, lowest=False)
    desc = Descent(lp, 1, r.resolved)
    state = desc.polish(r.governing.mechanism.velocities.ravel(), "lower end")
    assert state is not None and desc.exact(state)
    assert state.load_factor <= r.mechanism_band[0] * (1 + LOWEST_TOL)
    assert state.load_factor < r.mechanism_band[0] * (1 - 1e-3)  # it does descend here (0.6935 -> 0.6915)


def test_is_exact_keeps_a_certified_state_and_rejects_it_moved(
        table7_default: list[micro.NonAssociativeResult]) -> None:
    """The one test of a kept state (the descent's and the reduced wall's): Set 12's lowest state passes it;
    the same forces at a load factor 1e-4 higher break equilibrium and the power balance, and the shear
    forces reversed break equilibrium and friction against the slip, so neither passes."""
    w = wall(*TABLE7["set12"][0])
    lp = micro.assemble(w)
    low = table7_default[list(TABLE7).index("set12")].lowest[0]
    assert low.state is not None and low.state.mechanism is not None
    d = 1 if low.direction == "+x" else -1
    n, s = low.state.normal / lp.force_scale, low.state.shear / lp.force_scale
    v = np.asarray(low.state.mechanism.velocities, dtype=float).ravel()
    assert is_exact(lp, d, low.load_factor, n, s, v)
    assert not is_exact(lp, d, low.load_factor * (1 + 1e-4), n, s, v)
    assert not is_exact(lp, d, low.load_factor, n, -s, v)


def test_restricted_columns() -> None:
    """Opening points lose both generators, slipping points the one on the
    slip's side; frictionless points keep theirs when they slip; a mechanism
    run backwards interpenetrates (no pattern)."""
    w = wall(1.0, 1 / 2, head_joints="frictionless")
    lp = micro.assemble(w)
    r = solve_nonassociative(w, lowest=False)
    v = r.governing.mechanism.velocities.ravel()
    mask = restricted_columns(lp, v)
    assert mask is not None and restricted_columns(lp, -v) is None
    P = lp.n_points
    dn, ds = lp.Bn.T @ v, lp.Bs.T @ v
    tol = 1e-6 * max(np.abs(dn).max(), np.abs(ds).max())
    opening = dn > tol
    assert np.all(mask[:P][opening]) and np.all(mask[P:][opening])
    frictionless_slip = (lp.mu == 0) & (np.abs(ds) > tol) & ~opening
    assert frictionless_slip.any() and not mask[:P][frictionless_slip].any()
    slip_pos = (lp.mu > 0) & (ds > tol) & ~opening
    assert np.all(mask[:P][slip_pos]) and not mask[P:][slip_pos].any()


def test_refine_removes_the_equilibrium_residual() -> None:
    """A vertex perturbed by 1e-6 is brought back to equilibrium on its support."""
    w = wall(1.0, 1.0)
    lp = micro.assemble(w)
    f = ForceLP(lp, 1).solve(np.zeros(2 * lp.n_points, dtype=bool))
    assert f is not None
    x = np.concatenate([f.g, [f.load_factor]])
    noisy = x.copy()
    support = np.flatnonzero(x[:-1] > 1e-3)
    noisy[support] *= 1 + 1e-6 * np.cos(np.arange(support.size))
    before = float(np.max(np.abs(lp.A @ noisy - lp.rhs)))
    fixed = refine(lp, noisy)
    assert before > 1e-7 and float(np.max(np.abs(lp.A @ fixed - lp.rhs))) < 1e-11
    assert np.all(fixed[:-1] >= 0) and np.array_equal(fixed[:-1] > 0, noisy[:-1] > 0)


def test_lowest_off_and_records() -> None:
    """lowest=False leaves the fields empty; the record carries the descent."""
    w = wall(1.0, 1 / 3)
    off = solve_nonassociative(w, lowest=False)
    assert off.lowest == () and math.isnan(off.lowest_load_factor) and off.to_record().lowest_status == ""
    on = solve_nonassociative(w)
    rec = on.to_record()
    assert rec.lowest_status == "found" and rec.lowest_load_factor == on.lowest_load_factor
    assert rec.lowest_band == on.lowest_state.band and rec.lowest_moves == len(on.lowest_state.moves)
    assert rec.global_status == "" and math.isnan(rec.global_load_factor)
    assert type(rec).from_dict(rec.to_dict()).to_dict() == rec.to_dict()
    s = on.summary()
    assert s["lowest_load_factor"] == on.lowest_load_factor and s["lowest"][0]["contact_states"]
    assert on.iterated_load_factor == off.iterated_load_factor == off.load_factor  # unchanged by the descent
    assert on.load_factor == on.lowest_load_factor < on.iterated_load_factor  # the value to quote: the lowest


def test_lowest_state_needs_a_final_state() -> None:
    w = wall(1.0, 1.0)
    # a run that ends without a final state (three LPs of the vertex sequence; the descent reads its options)
    r = solve_nonassociative(w, tuning=Tuning(relaxation=1.0, certify=False, selection="vertex"), lowest=False,
                             max_iterations=3)  # fmt: skip
    assert not r.converged
    with pytest.raises(ValueError, match="has no final state"):
        lowest_state(micro.assemble(w), micro.DirectionResult("+x", "cycling", math.nan, 0, 0.0), r.resolved)


@pytest.mark.parametrize("bad", [0, -1.0, math.inf, "10", True])
def test_global_time_limit_is_checked(bad: object) -> None:
    with pytest.raises(ValueError, match="direction_time_limit must be a positive number"):
        micro.GlobalOptions(direction_time_limit=bad)  # type: ignore[arg-type]


@pytest.mark.parametrize("name, bad, message", [
    ("node_limit", 0, "node_limit must be"),
    ("node_limit", 1.5, "node_limit must be"),
    ("bounds", "tight", "bounds must be one of per_point, uniform"),
])
def test_global_search_options_are_checked(name: str, bad: object, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        micro.GlobalOptions(**{name: bad})  # type: ignore[arg-type]


def test_the_descent_runs_warm_from_the_iterated_lps_model() -> None:
    """The descent takes over the iterated LP's model: no LP of it on Table 7's
    Set 13 is solved from scratch (interior point + crossover) but the
    mechanism LP's first, and its lowest state is the pinned one."""
    (t, m), lam = TABLE7["set13"]
    events: list[micro.nonassociative.LPProgress] = []
    r = solve_nonassociative(wall(t, m), progress=events.append)
    algorithms = [e.algorithm for e in events if e.stage == "lowest"]
    assert len(algorithms) == r.lowest[0].lps
    assert algorithms.count("ipm+crossover+simplex") == 1  # the mechanism LP's first run
    assert r.lowest_load_factor == pytest.approx(lam, rel=1e-6)


def test_a_lower_end_from_the_carried_over_basis_is_the_cold_one() -> None:
    """The force LP started from the Gilbert basis carried over to the
    generator columns (a primal simplex) reaches the optimum of the same LP
    solved from scratch."""
    w = wall(1.0, 1 / 2)
    lp = micro.assemble(w)
    r = solve_nonassociative(w, lowest=False)
    v = r.governing.mechanism.velocities.ravel()
    restricted = restricted_columns(lp, v)
    model = IterationModel(lp, 1, "a", 0.0)
    model.set_capacity(r.governing.normal / lp.force_scale, 0.0, 0.0, 0.0)
    restart(model.model)
    start = model.generator_basis()
    assert start is not None and int((start[0] == 1).sum()) + int((start[1] == 1).sum()) == lp.n_eq
    warm, cold = ForceLP(lp, 1), ForceLP(lp, 1)
    f_warm = warm.solve(restricted, start=start)
    f_cold = cold.solve(restricted)
    assert f_warm is not None and f_cold is not None
    assert f_warm.load_factor == pytest.approx(f_cold.load_factor, rel=1e-9)
    assert f_warm.load_factor == pytest.approx(r.mechanism_band[0], rel=1e-6)


def test_a_primal_run_from_a_set_basis_stays_warm_after_a_failed_run(monkeypatch: pytest.MonkeyPatch) -> None:
    """The band's upper end (``Descent._band``) sets the lowest state's basis and asks for the primal
    simplex: it runs from that basis even when the model's last run failed (a capped warm run before it
    had sent it to the interior point + crossover), and reaches the optimum of the same LP solved from
    scratch."""
    w = wall(1.0, 1 / 2)
    lp = micro.assemble(w)
    r = solve_nonassociative(w, lowest=False)
    restricted = restricted_columns(lp, r.governing.mechanism.velocities.ravel())
    assert restricted is not None
    runs = ForceLP(lp, 1)
    low = runs.solve(restricted)
    assert low is not None and low.basis is not None
    runs.cold = True  # as a failed warm run leaves it
    colds: list[int] = []
    cold_run = runs._cold
    monkeypatch.setattr(runs, "_cold", lambda: colds.append(1) or cold_run())
    runs.model.set_basis(low.basis)
    top = runs.solve(restricted, sense=-1.0, primal=True)
    top_cold = ForceLP(lp, 1).solve(restricted, sense=-1.0)
    assert colds == [] and top is not None and top_cold is not None
    assert top.load_factor == pytest.approx(top_cold.load_factor, rel=1e-9)
    assert top.load_factor == pytest.approx(r.mechanism_band[1], rel=1e-6)


def test_the_descent_runs_by_default_on_a_wall_of_any_size() -> None:
    """No size switch: a two-storey wall of 342 blocks gets its lowest state by default."""
    w = WallSpec.from_paper(t=2.0, m=1 / 2, rows=36, f=0.7, p=0, storeys=2).to_micro()
    assert w.n_blocks > 300
    r = solve_nonassociative(w)
    assert r.converged and r.lowest_state is not None and r.to_record().lowest_stop == "finished"
    check_states(w, r)


def test_on_a_fused_wall_the_descent_takes_the_lower_end_of_its_band() -> None:
    """Where the iterated LP ran on the fused wall (no model of the wall to take over), the descent takes
    the lower end of the certified state's mechanism band and makes no proposal."""
    (t, m), _ = TABLE7["set12"]
    w = wall(t, m)
    r = solve_nonassociative(w, tuning=Tuning(fuse=True))
    assert r.sequence.fusion is not None and r.converged
    check_states(w, r)
    low = r.lowest[0]
    assert low.moves == () and low.stop == "finished"
    assert low.load_factor <= r.mechanism_band[0] * (1 + 1e-7)
