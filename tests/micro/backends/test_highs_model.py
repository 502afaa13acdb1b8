"""The persistent HiGHS model: changes in place, warm starts, basis, cold copy, time limit."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from micro_walls import table7_wall

import micro
from micro.backends import PersistentHighsModel, Status


def _force_model(lp: micro.LimitLP, nbar: np.ndarray) -> PersistentHighsModel:
    """Columns [n, s, lambda] over the equilibrium rows with |s| <= mu nbar (scheme (a))."""
    P = lp.n_points
    A = sp.hstack([lp.Bn, lp.Bs, sp.csc_matrix(lp.live.reshape(-1, 1))], format="csc")
    cost = np.zeros(2 * P + 1)
    cost[-1] = -1.0
    lower = np.concatenate([np.zeros(P), -lp.mu * nbar, [-np.inf]])
    upper = np.concatenate([np.full(P, np.inf), lp.mu * nbar, [np.inf]])
    return PersistentHighsModel(A, cost, lower, upper, lp.rhs, lp.rhs, algorithm="simplex")


def test_bound_changes_run_warm() -> None:
    """The design the non-associative scheme needs: n, s columns, |s| <= mu nbar
    by bound changes only, the basis reused."""
    lp = micro.assemble(table7_wall("set12"))
    first = micro.make_backend(lp, "highs-simplex").solve(1)
    assert first.status is Status.OPTIMAL and first.n is not None
    P = lp.n_points
    nbar = first.n
    m = _force_model(lp, nbar)
    second = m.run()
    assert second.ok and second.x is not None
    # the associative optimum stays feasible: lambda cannot drop
    assert second.x[-1] >= first.load_factor - 1e-9
    assert np.all(np.abs(second.x[P : 2 * P]) <= lp.mu * nbar + 1e-7)
    m.set_col_bounds(np.arange(P, 2 * P), -0.99 * lp.mu * nbar, 0.99 * lp.mu * nbar)
    third = m.run()
    assert third.ok and third.x is not None
    assert third.simplex_iterations < second.simplex_iterations  # warm: the basis was reused
    assert third.x[-1] <= second.x[-1] + 1e-9  # tighter capacities, no larger lambda
    # a cold copy of the current model: same optimum, from no basis
    cold = m.cold_copy("ipm").run()
    assert cold.ok and cold.x is not None and cold.simplex_iterations == 0 and cold.ipm_iterations > 0
    assert cold.x[-1] == pytest.approx(third.x[-1], rel=1e-6)
    # clearing the solver forgets the basis; setting it back restores the warm start
    basis = m.get_basis()
    m.clear_solver()
    again = m.run()
    assert again.ok and again.simplex_iterations > 0
    m.set_basis(basis)
    assert m.run().simplex_iterations == 0


def test_duals_in_the_shared_sign() -> None:
    lp = micro.assemble(table7_wall("set12"))
    m = PersistentHighsModel.of(lp, 1)
    out = m.run()
    assert out.ok and out.duals is not None and out.x is not None
    v = out.duals[: lp.n_eq]
    assert float(lp.live @ v) == pytest.approx(1.0, abs=1e-6)
    assert float(lp.dead @ v) == pytest.approx(-out.x[lp.lam_col], abs=1e-6)


def test_rows_and_coefficients_change_in_place() -> None:
    """A row added, its bound and coefficient changed: lambda follows."""
    lp = micro.assemble(table7_wall("set12"))
    m = PersistentHighsModel.of(lp, 1, algorithm="simplex")
    free = m.run()
    assert free.ok and free.x is not None
    cap = 0.5 * free.x[lp.lam_col]
    row = sp.csr_matrix(([1.0], ([0], [lp.lam_col])), shape=(1, lp.n_cols))
    m.add_rows(row, np.array([-np.inf]), np.array([cap]))
    capped = m.run()
    assert capped.ok and capped.x is not None and capped.x[lp.lam_col] == pytest.approx(cap)
    m.change_coeffs(np.array([lp.n_eq]), np.array([lp.lam_col]), np.array([2.0]))
    halved = m.run()
    assert halved.ok and halved.x is not None and halved.x[lp.lam_col] == pytest.approx(cap / 2)
    m.set_row_bounds(np.array([lp.n_eq]), np.array([-np.inf]), np.array([np.inf]))
    assert m.run().x[lp.lam_col] == pytest.approx(free.x[lp.lam_col])


def test_time_limit_and_bad_algorithm() -> None:
    w = micro.build_wall(length=30, block_length=3, block_height=1, rows=(30,), thickness=(1,), overload=(0,),
                         unit_weight=1, friction=0.6)
    m = PersistentHighsModel.of(micro.assemble(w), 1, algorithm="simplex")
    m.limit_next_run(1e-4)
    out = m.run()
    assert out.status in (Status.TIME_LIMIT, Status.OPTIMAL)
    if out.status is Status.TIME_LIMIT:
        assert out.x is None and out.duals is None
    m.limit_next_run(None)
    assert m.run().ok
    with pytest.raises(ValueError, match="algorithm"):
        m.set_algorithm("barrier")


def test_stall_guard_counts_calls_per_iteration() -> None:
    """The guard fires on calls without progress, never on iterations that advance;
    the model's callback interrupts on simplex calls only and sets HiGHS' flag every call."""
    from types import SimpleNamespace

    from micro.backends.highs_runs import STALL_CALLS, RunCallback, StallGuard

    SIMPLEX, IPM = 1, 2
    callback = RunCallback(SIMPLEX)
    guard = callback.guard = StallGuard()
    flag = SimpleNamespace(user_interrupt=False)
    for it in range(1000):  # up to 7 calls per iteration were seen in normal runs
        for _ in range(7):
            callback(SIMPLEX, "", SimpleNamespace(simplex_iteration_count=it), flag, None)
    assert not flag.user_interrupt and not guard.fired
    for _ in range(2 * STALL_CALLS):  # interior-point calls (no simplex count) are not counted
        callback(IPM, "", SimpleNamespace(simplex_iteration_count=0, ipm_iteration_count=3), flag, None)
    assert not flag.user_interrupt and not guard.fired
    for _ in range(STALL_CALLS):
        callback(SIMPLEX, "", SimpleNamespace(simplex_iteration_count=1000), flag, None)
    assert flag.user_interrupt and guard.fired
    guard.reset()
    assert not guard.fired
    # HiGHS keeps the flag between runs: the next run's first call must clear it
    callback(SIMPLEX, "", SimpleNamespace(simplex_iteration_count=0), flag, None)
    assert flag.user_interrupt is False


def test_a_guarded_run_that_stalls_fails_and_says_so() -> None:
    """Through HiGHS' callback: a guard that fires at once interrupts the run
    (``solver_error``, ``info["stalled"]``, no solution); the default guard lets
    the same LP reach its optimum."""
    lp = micro.assemble(table7_wall("set12"))
    first = micro.make_backend(lp, "highs-simplex").solve(1)
    assert first.n is not None
    m = _force_model(lp, first.n)
    m.guard_stalls(calls=1)
    out = m.run()
    assert out.status is Status.SOLVER_ERROR and out.x is None and out.info["stalled"]
    assert out.native_status.startswith("stalled at simplex iteration")
    # the same guard, raised: the interrupted run leaves nothing behind (HiGHS kept
    # the interrupt flag, and every later run of the model stopped at once)
    assert m.stall_guard is not None
    m.stall_guard.calls = 10**9
    out = m.run()
    assert out.ok and out.x is not None and not out.info["stalled"]
    m.guard_stalls()
    out = m.run()
    assert out.ok and out.x is not None and not out.info["stalled"]
    assert out.x[-1] >= first.load_factor - 1e-9
