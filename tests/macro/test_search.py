"""The global search of Eq. (10) against a dense brute force."""

from __future__ import annotations

import numpy as np
import pytest
from brute_force import Walls, brute_force, random_walls

import macro
from comparison.domain.wall import WallSpec
from macro.equations import evaluate
from macro.search import DEFAULT_SEARCH, SearchSettings, WallMinima, minimise_walls
from macro.solve import _problems

#: The search may not lose more than this (relative) to the brute force.
BRUTE_TOL = 1e-10


def _minima(w: Walls, settings: SearchSettings = DEFAULT_SEARCH, wall_minimum_only: bool = False) -> WallMinima:
    return minimise_walls(
        w.length, w.overlap, w.block_height, w.unit_weight, w.friction, w.rows, w.thickness, w.overload, settings,
        wall_minimum_only=wall_minimum_only,
    )  # fmt: skip


@pytest.mark.parametrize(("storeys", "count"), [(1, 100), (3, 40), (5, 20)])
def test_every_hinge_against_brute_force(storeys: int, count: int) -> None:
    """Per hinge, no crack angle of a 100,001-point grid (plus kinks and ends) beats the search. The brute
    force costs about storeys² per wall: the walls of several storeys are fewer (about a hundred hinges each)."""
    w = random_walls(np.random.default_rng(100 + storeys), count, storeys)
    found = _minima(w)
    shared = _minima(w, wall_minimum_only=True)
    worst = 0.0
    for i in range(count):
        pb = w.problems(i)
        grid = brute_force(pb)
        lam, tau = found.rocking_load_factor[i], found.tan_alpha_c[i]
        # the reported value is Eq. (10) at the reported slope, inside Eq. (11)
        np.testing.assert_allclose(evaluate(tau[:, None], pb)["lambda_r"][:, 0], lam, rtol=1e-12)
        assert np.all(pb.tau_low[:, 0] * (1 - 1e-15) <= tau) and np.all(tau <= pb.tau_high[:, 0] * (1 + 1e-15))
        worst = max(worst, float(np.max(lam / grid - 1.0)))
        # pruning across hinges keeps the wall's minimum and its hinge
        k = found.hinge_storey[i]
        assert shared.hinge_storey[i] == k and shared.rocking_load_factor[i, k - 1] == lam[k - 1]
        assert lam[k - 1] == lam.min()
    assert worst <= BRUTE_TOL, f"the search lost {worst:.2e} to the brute force"


@pytest.mark.parametrize("storeys", [1, 3, 5])
def test_sweep_against_brute_force(storeys: int) -> None:
    rng = np.random.default_rng(7 + storeys)
    n = 12
    t, m, f, p = (
        rng.uniform(0.3, 4, n),
        rng.choice([0.25, 1 / 3, 0.5, 2 / 3, 1.0], n),
        rng.uniform(0.2, 1.2, n),
        rng.uniform(0, 8, n),
    )
    rows = storeys * rng.integers(1, 25, n)
    p[::3] = 0.0
    t = np.minimum(t, rows * m)  # a wall at least one block long (macro.checks.wall_bounds)
    s = macro.sweep(t, m, rows, f, p, storeys=storeys)
    for i in range(n):
        wall = WallSpec.from_paper(t=t[i], m=m[i], rows=int(rows[i]), f=f[i], p=p[i], storeys=storeys).to_macro()
        grid = brute_force(_problems(wall)).min()
        assert s.rocking_load_factor[i] <= grid * (1 + BRUTE_TOL)
        assert s.rocking_load_factor[i] >= grid * (1 - 1e-8)  # the grid is dense: it is not far above the minimum


# A wall where Eq. (10) rises from the first kink to a local maximum before it falls to the
# hinge's minimum (found by scanning random walls): the derivative is positive at both ends of
# that piece, so the ends alone miss the minimum; its interior samples do not.
HUMP = Walls(
    length=np.array([54.438482424498545]),
    overlap=np.array([1.3068756370534895]),
    block_height=np.ones(1),
    unit_weight=np.ones(1),
    friction=np.array([0.7655292443318689]),
    rows=np.array([[29.0, 4.0, 28.0]]),
    thickness=np.array([[1.8164347815428241, 1.4382105351452337, 0.6013836139340487]]),
    overload=np.zeros((1, 3)),
)


def test_minimum_behind_a_local_maximum() -> None:
    grid = brute_force(HUMP.problems(0))
    found = _minima(HUMP)
    assert np.all(found.rocking_load_factor[0] <= grid * (1 + BRUTE_TOL))
    # with one or two cells per piece the derivative's sign change is missed
    coarse = _minima(HUMP, settings=SearchSettings(cells=2))
    assert coarse.rocking_load_factor[0, 2] > grid[2] * (1 + 1e-4)


def test_one_row_mechanism() -> None:
    """One row in the mechanism: Eq. (11) is the point tan(alpha_c) = v/b."""
    s = macro.sweep(1.5, 0.5, 3, 0.6, 0.0, storeys=3)  # one block long: t = o m
    r = macro.solve(WallSpec.from_paper(t=1.5, m=0.5, rows=3, f=0.6, storeys=3).to_macro())
    assert r.hinges[0].tan_alpha_c == pytest.approx(1.0, rel=1e-15)
    assert s.rocking_load_factor == pytest.approx(r.rocking_load_factor, rel=1e-12)


def test_sliding_factor_matches_term_by_term() -> None:
    """Eq. (12) of the compiled search equals the Table 2 terms summed one by one."""
    w = random_walls(np.random.default_rng(5), 40, 3)
    found = _minima(w)
    for i in range(40):
        k = found.hinge_storey[i]
        pb = w.problems(i).select(slice(k - 1, k))
        lam_s = evaluate(found.tan_alpha_c[i, k - 1 : k][None, :], pb)["lambda_s"][0, 0]
        assert found.sliding_load_factor[i] == pytest.approx(lam_s, rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(cells=0), r"cells must be an integer in 1..10,000, got 0"),
        (dict(cells=2.5), "cells must be an integer in 1..10,000"),
        (dict(cells=10**9), "cells must be an integer in 1..10,000"),  # else a search that never ends
        (dict(max_iterations=0), "max_iterations must be an integer in 1..10,000"),
        (dict(max_iterations=10**400), "max_iterations must be an integer in 1..10,000"),
        (dict(tolerance=0.0), "tolerance must be in"),
        (dict(tolerance=float("nan")), "tolerance must be in"),
        (dict(tolerance="1e-9"), "tolerance must be in"),  # named, not a TypeError from math.isfinite
    ],
)
def test_settings_bad_input(kwargs: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        SearchSettings(**kwargs)  # type: ignore[arg-type]
