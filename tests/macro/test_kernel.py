"""The compiled Eq. (10) on smooth pieces against the term-by-term equations."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from brute_force import random_walls
from numpy.typing import NDArray

from macro.equations import HingeProblems, evaluate
from macro.kernel import N_COEF, lambda_derivatives, lower_bound, piece_coefficients, storey_constants


def _pieces() -> Iterator[tuple[HingeProblems, NDArray[np.float64], float, float, float, float]]:
    """Every non-empty piece of every hinge of random walls: (problem, coefficients, tau_low, alpha_b, a, b)."""
    rng = np.random.default_rng(3)
    for storeys in (1, 2, 3, 5):
        w = random_walls(rng, 12, storeys)
        for i in range(12):
            problems = w.problems(i)
            for k in range(1, storeys + 1):
                st, cf = np.empty((storeys, 12)), np.empty(N_COEF)
                L, v, b = w.length[i], w.overlap[i], w.block_height[i]
                args = (w.unit_weight[i], w.friction[i], w.rows, w.thickness, w.overload, st)
                moment_a, overturn_a, n = storey_constants(k, i, L, v, b, *args)
                tau_low, tau_high, alpha_b = v / (n * b), v / b, np.arctan(v / b)
                kinks = [0.0] + [L / ((st[p, 1] + st[p, 0]) * b) for p in range(k)] + [np.inf]
                for p in range(k + 1):
                    lo, hi = max(tau_low, kinks[p]), min(tau_high, kinks[p + 1])
                    if hi > lo:
                        piece_coefficients(p, k, st, moment_a, overturn_a, L, v, b, w.friction[i], cf)
                        yield problems.select(slice(k - 1, k)), cf.copy(), tau_low, alpha_b, lo, hi


def test_pieces_match_term_by_term_and_bound_from_below() -> None:
    count = 0
    for pb, cf, tau_low, alpha_b, lo, hi in _pieces():
        tau = np.linspace(lo, hi, 41)
        got = np.array([lambda_derivatives(t, cf, tau_low, alpha_b, True) for t in tau])
        ref = evaluate(tau[None, :], pb)["lambda_r"][0]
        np.testing.assert_allclose(got[:, 0], ref, rtol=1e-12)
        # the first derivative without the second is the same
        np.testing.assert_array_equal([lambda_derivatives(t, cf, tau_low, alpha_b, False)[1] for t in tau], got[:, 1])
        # derivatives against central differences inside the piece
        h = 1e-5 * (hi - lo)
        inner = tau[1:-1]
        up = np.array([lambda_derivatives(t + h, cf, tau_low, alpha_b, False)[:2] for t in inner])
        down = np.array([lambda_derivatives(t - h, cf, tau_low, alpha_b, False)[:2] for t in inner])
        d1, d2 = (up - down).T / (2 * h)
        np.testing.assert_allclose(got[1:-1, 1], d1, rtol=1e-5, atol=1e-6 * np.abs(got[:, 1]).max())
        np.testing.assert_allclose(got[1:-1, 2], d2, rtol=1e-4, atol=1e-5 * np.abs(got[:, 2]).max())
        # the interval bound holds over the piece and over each of its cells
        assert lower_bound(lo, hi, cf, tau_low, alpha_b) <= ref.min() * (1 + 1e-14)
        for a, b, lam in zip(tau[:-1], tau[1:], np.minimum(ref[:-1], ref[1:]), strict=True):
            assert lower_bound(a, b, cf, tau_low, alpha_b) <= lam * (1 + 1e-14)
        count += 1
    assert count > 100
