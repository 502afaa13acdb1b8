"""The cvxpy back end where sliding governs exactly (``lambda = f``) and several mechanisms tie.

The quick report's 3-row wall (one block long: every bed joint spans the wall)
came back ``inaccurate`` from cvxpy while the other back ends solved it. The
cause is the tie: with the tight settings Clarabel stops short on it through
either API (the direct back end only solved it by its retry); with one
mechanism (bed joints rougher than the base) the same settings solve it.
"""

from __future__ import annotations

import warnings

import cvxpy as cp
import numpy as np
import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.backends.clarabel import CLARABEL_TIGHT
from micro.geometry import BED


def _wall(rows: int) -> micro.BlockWall:
    return WallSpec.from_paper(t=1, m=1 / 3, rows=rows, f=0.75).to_micro()


@pytest.mark.parametrize("rows", [3, 6])
def test_cvxpy_solves_the_quick_reports_tied_walls(rows: int) -> None:
    ref = micro.solve_associative(_wall(rows), solver="highs-simplex")
    got = micro.solve_associative(_wall(rows), solver="cvxpy")
    assert got.ok, (got.status, got.message)
    assert got.load_factor == pytest.approx(ref.load_factor, rel=1e-6) and ref.load_factor == pytest.approx(0.75)


def _tight_status(lp: micro.LimitLP, mu: np.ndarray) -> str:
    """The reference formulation with the tight Clarabel settings alone (no retry)."""
    Bn, Bs = lp.equilibrium_matrix()
    n, s, lam = cp.Variable(lp.n_points, nonneg=True), cp.Variable(lp.n_points), cp.Variable()
    problem = cp.Problem(
        cp.Maximize(lam),
        [Bn @ n + Bs @ s + lam * lp.live == lp.rhs, s <= cp.multiply(mu, n), -s <= cp.multiply(mu, n)],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        problem.solve(solver="CLARABEL", **CLARABEL_TIGHT)
    return str(problem.status)


def test_the_cause_is_the_tie_of_sliding_mechanisms() -> None:
    wall = _wall(3)
    lp = micro.assemble(wall)
    assert _tight_status(lp, lp.mu) == "optimal_inaccurate"  # three bed joints slide at lambda = f
    bed = np.repeat(wall.contact_kind, 2) == BED
    assert _tight_status(lp, np.where(bed, 0.8, lp.mu)) == "optimal"  # only the base slides: one mechanism
    direct = micro.solve_associative(wall, solver="clarabel")
    assert "fallback" in direct.directions[0].info  # the direct back end needs its retry too
