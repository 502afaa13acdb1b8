"""Reproducibility: the contact counts and the printed digits of a result do not depend on the machine.

The interior point's velocities are accurate to about 1e-4 of the largest rate, so contacts classified
much finer than that count differently on another BLAS kernel (Sets 15-17's associative sliding counts
by tens), and λ is guaranteed to about eight digits: the contacts are counted above 1e-3 of the largest
rate and λ printed to seven significant digits.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import micro
from comparison.domain.cases import case
from comparison.report.tables import DIGITS, plain
from micro.backends.clarabel import CLARABEL_TIGHT
from micro.backends.normal_ipm import NORMAL_IPM
from micro.mechanism import CONTACT_STATE_TOL, STATE_TOL, mechanism_from_duals


@pytest.fixture(scope="module")
def set5() -> tuple[micro.BlockWall, micro.LimitResult]:
    wall = case("5").spec().to_micro()  # 450 blocks, 1,266 contacts
    return wall, micro.solve_associative(wall)


def test_the_tolerance_is_above_the_accuracy_of_the_interior_points() -> None:
    """An interior point's duals (the velocities) are accurate to about the square root of its gap tolerance
    relative to the largest; the classification stays ten times above it."""
    for gap in (NORMAL_IPM.gap_tol, CLARABEL_TIGHT["tol_gap_rel"]):
        assert 10 * math.sqrt(gap) <= CONTACT_STATE_TOL
    assert STATE_TOL < CONTACT_STATE_TOL  # the iterated LP's own tolerance on vertex rates is unchanged


def test_two_interior_points_count_the_same_contacts(set5: tuple[micro.BlockWall, micro.LimitResult]) -> None:
    """Two interior points stop at different points of the central path within their tolerances, as one
    does on two machines: on Set 5 ``normal-ipm`` and ``highs-ipm`` gave 247 closed / 243 opening / 776
    sliding and 254 / 244 / 768 at 1e-6; at :data:`CONTACT_STATE_TOL` the same counts."""
    wall, ours = set5
    other = micro.solve_associative(wall, solver="highs-ipm")
    assert ours.ok and other.ok and ours.load_factor == pytest.approx(other.load_factor, rel=1e-7)
    assert ours.to_record().contact_states == other.to_record().contact_states
    assert ours.to_record().contact_states == {"closed": 500, "opening": 206, "sliding": 560}


def test_counts_do_not_move_when_the_velocities_move_by_1e_9(
    set5: tuple[micro.BlockWall, micro.LimitResult],
) -> None:
    wall, r = set5
    lp = micro.assemble(wall)
    assert r.mechanism is not None
    direction = 1 if r.direction == "+x" else -1
    v = r.mechanism.velocities.ravel()
    base = mechanism_from_duals(lp, v, direction).state_counts()
    rng = np.random.default_rng(41)
    for _ in range(20):
        moved = v * (1 + 1e-9 * rng.uniform(-1, 1, v.size))
        assert mechanism_from_duals(lp, moved, direction).state_counts() == base


#: The associative λ of Table 9's walls computed with three OpenBLAS kernels (default, Haswell,
#: Sandybridge; one thread): the same LP, other last digits.
KERNEL_LAMBDAS = {
    "Set 15": (0.5072551119, 0.5072551176, 0.5072551182),
    "Set 16": (0.5002933769, 0.5002933773, 0.5002933757),
    "Set 17": (0.4993533672, 0.4993533655, 0.4993533673),
}


@pytest.mark.parametrize("wall", list(KERNEL_LAMBDAS))
def test_the_printed_digits_are_the_same_on_every_kernel(wall: str) -> None:
    """The report's CSV tables and ``report.json`` print the digits every BLAS kernel agrees on."""
    printed = {plain(lam) for lam in KERNEL_LAMBDAS[wall]}
    assert len(printed) == 1


def test_the_printed_digits_do_not_move_with_a_1e_9_perturbation(
    set5: tuple[micro.BlockWall, micro.LimitResult],
) -> None:
    lam = set5[1].load_factor
    assert {plain(lam * (1 + e)) for e in (-1e-9, 0.0, 1e-9)} == {plain(lam)}
    assert plain(lam) == float(f"{lam:.{DIGITS}g}") and plain(math.nan) is None and plain(3) == 3
