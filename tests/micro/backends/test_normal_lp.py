"""The bounded LP with a free column on the normal equations (the iterated LP's crossover route)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from comparison.wall import WallSpec
from micro.backends.clarabel import ClarabelBackend
from micro.backends.highs import PersistentHighsModel
from micro.backends.normal_lp import BoxLP, BoxLPSettings
from micro.lp import assemble


def _highs_optimum(A: sp.csc_matrix, f: np.ndarray, b: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                   d: int) -> float:
    """``lambda`` of the same LP by HiGHS' dual simplex (the reference)."""
    cols = sp.hstack([A, sp.csc_matrix(f.reshape(-1, 1))], format="csc")
    cost = np.zeros(cols.shape[1])
    cost[-1] = -float(d)
    m = PersistentHighsModel(cols, cost, np.append(lower, -np.inf), np.append(upper, np.inf), b, b,
                             algorithm="simplex")
    out = m.run()
    assert out.x is not None
    return float(out.x[-1])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_bounded_lps_match_the_simplex(seed: int) -> None:
    """A feasible LP with boxed columns (two-sided, one-sided and fixed; every box finite but
    one, so ``lambda`` is bounded): the optimum within 1e-7 of HiGHS', the bounds held,
    the equality rows within the tolerance."""
    rng = np.random.default_rng(seed)
    rows, cols = 8, 40
    A = sp.random(rows, cols, density=0.3, random_state=rng, format="csc") + sp.hstack(
        [sp.identity(rows), -sp.identity(rows), sp.csc_matrix((rows, cols - 2 * rows))], format="csc")
    lower = np.concatenate([np.zeros(20), -rng.uniform(0.1, 1.0, 20)])
    upper = np.concatenate([np.full(20, 2.0), -lower[20:]])
    upper[3] = np.inf
    lower[25] = upper[25] = 0.2  # a fixed column
    x0 = np.clip(rng.uniform(0, 1, cols), lower, upper)
    f = rng.normal(size=rows)
    b = A @ x0 + 0.3 * f
    out = BoxLP(A, f).solve(np.zeros(cols), b, lower, upper, +1)
    assert out.converged, out.reason
    assert out.lam == pytest.approx(_highs_optimum(A, f, b, lower, upper, +1), abs=1e-7)
    assert np.all(out.x >= lower - 1e-12) and np.all(out.x <= upper + 1e-12) and out.x[25] == 0.2
    assert np.max(np.abs(A @ out.x + f * out.lam - b)) <= 1e-7


def test_gilberts_lp_on_a_wall_matches_the_simplex() -> None:
    """Gilbert's LP of Table 7's Set 12 at the associative normal forces (``|s| <= mu nbar``),
    both load directions: ``lambda`` within 5e-8 of HiGHS' vertex (the interior point stops at
    primal residuals of 1e-8; the crossover route takes its vertex from HiGHS)."""
    lp = assemble(WallSpec.from_paper(t=1.0, m=1 / 3, rows=12, f=0.75, p=0, storeys=1).to_micro())
    P = lp.n_points
    box = BoxLP(sp.hstack([lp.Bn, lp.Bs]), lp.live)
    for d in (+1, -1):
        nbar = np.maximum(np.asarray(ClarabelBackend(lp).solve(d).n), 0.0)
        cap = lp.mu * nbar
        lower, upper = np.concatenate([np.zeros(P), -cap]), np.concatenate([np.full(P, np.inf), cap])
        out = box.solve(np.zeros(2 * P), lp.rhs, lower, upper, d)
        assert out.converged, out.reason
        ref = _highs_optimum(sp.hstack([lp.Bn, lp.Bs], format="csc"), lp.live, lp.rhs, lower, upper, d)
        assert out.lam == pytest.approx(ref, abs=5e-8)


def test_an_infeasible_lp_is_not_converged() -> None:
    """``x >= 0``, ``x1 + x2 = -1`` (the free column has no entry there): no point, no answer."""
    A = sp.csc_matrix(np.array([[1.0, 1.0], [0.0, 1.0]]))
    f = np.array([0.0, 1.0])
    out = BoxLP(A, f, BoxLPSettings(max_iter=60)).solve(np.zeros(2), np.array([-1.0, 0.0]), np.zeros(2),
                                                       np.full(2, np.inf), +1)
    assert not out.converged


@pytest.mark.parametrize("bad", [{"gap_tol": 0.0}, {"max_iter": 0}, {"fix_width": -1.0}])
def test_bad_settings_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ValueError, match=next(iter(bad))):
        BoxLPSettings(**bad)  # type: ignore[arg-type]
