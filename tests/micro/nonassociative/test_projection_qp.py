"""The least-distance QP on the normal equations (the proximal projection's solver)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from micro.backends.normal_qp import LeastDistanceQP, LeastDistanceSettings


def _simplex_projection(t: np.ndarray, total: float) -> np.ndarray:
    """The projection of ``t`` onto ``{x >= 0, sum x = total}`` in closed form (sort and threshold)."""
    u = np.sort(t)[::-1]
    css = np.cumsum(u) - total
    k = np.nonzero(u - css / np.arange(1, t.size + 1) > 0)[0][-1]
    return np.maximum(t - css[k] / (k + 1), 0.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_projection_onto_a_simplex_matches_the_closed_form(seed: int) -> None:
    """One equality row and lower bounds: the sort-and-threshold answer, to 1e-6 of the
    largest ``|t|`` (the accuracy of an interior point stopped at a relative gap of 1e-9)."""
    rng = np.random.default_rng(seed)
    t = rng.normal(size=40) * 3.0
    qp = LeastDistanceQP(sp.csc_matrix(np.ones((1, 40))))
    out = qp.solve(t, np.array([5.0]), np.zeros(40), np.full(40, np.inf))
    assert out.converged, out.reason
    assert np.max(np.abs(out.x - _simplex_projection(t, 5.0))) <= 1e-6 * np.max(np.abs(t))


def test_box_bounds_and_fixed_columns() -> None:
    """Two-sided bounds are held, a column with ``upper <= lower`` stays at ``lower``, and
    the answer is the KKT point: ``x - t = A^T y`` on the columns strictly inside their box."""
    rng = np.random.default_rng(7)
    A = sp.random(6, 30, density=0.4, random_state=rng, format="csc") + sp.hstack(
        [sp.identity(6), sp.csc_matrix((6, 24))], format="csc")
    lower = np.concatenate([np.zeros(15), -np.full(15, 0.3)])
    upper = np.concatenate([np.full(15, np.inf), np.full(15, 0.3)])
    lower[20] = upper[20] = 0.0  # fixed at 0
    x0 = np.clip(rng.uniform(0, 1, 30), lower, upper)
    b = A @ x0
    t = rng.normal(size=30)
    out = LeastDistanceQP(A).solve(t, b, lower, upper)
    assert out.converged, out.reason
    x = out.x
    assert np.max(np.abs(A @ x - b)) <= 1e-8
    assert np.all(x >= lower - 1e-12) and np.all(x <= upper + 1e-12) and x[20] == 0.0
    inside = (x > lower + 1e-6) & (x < upper - 1e-6)
    y = np.linalg.lstsq(A[:, inside].T.toarray(), (x - t)[inside], rcond=None)[0]
    assert np.max(np.abs(A[:, inside].T @ y - (x - t)[inside])) <= 1e-6


def test_an_infeasible_qp_is_not_converged() -> None:
    """``x >= 0`` with ``sum x = -1`` has no point: the run says so instead of answering."""
    qp = LeastDistanceQP(sp.csc_matrix(np.ones((1, 5))), LeastDistanceSettings(max_iter=60))
    out = qp.solve(np.ones(5), np.array([-1.0]), np.zeros(5), np.full(5, np.inf))
    assert not out.converged and out.reason != "converged"


@pytest.mark.parametrize("field, value", [("gap_tol", 0.0), ("step_fraction", 1.0), ("max_iter", 0),
                                          ("regularization", -1.0), ("refine_steps", True)])
def test_bad_settings_are_refused(field: str, value: object) -> None:
    with pytest.raises(ValueError, match=field):
        LeastDistanceSettings(**{field: value})  # type: ignore[arg-type]
