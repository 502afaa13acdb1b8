"""The lowest certified state against the global minimum where the MIP closes.

On walls of a few blocks the branch and bound proves the global minimum of
the non-associative collapse load (its own tests check it against an
exhaustive enumeration of the contact patterns, ``test_global_mip.py``). The
descent's state must never lie below the proven bound, and on these walls it
reaches the global minimum, also where the iterated LP stops at the top of
its band (two blocks side by side: band [1/2, 8/13], derived by hand in
``test_closed_form.py``).
"""

from __future__ import annotations

import pytest
from hand_walls import column_wall, small_wall

import micro

#: Branch-and-bound nodes per direction (each search here closes in far fewer).
NODES = 20_000
#: (name, wall, closed-form global minimum or None)
WALLS = [
    ("block", lambda: small_wall(1.0, 1.0, 2.0, 1, 0.75), 0.5),
    ("column 3", lambda: column_wall(3, 1.0, 1.0, 0.75), 1 / 3),
    ("two blocks", lambda: small_wall(1.0, 0.5, 1.0, 1, 0.75), 0.5),
    ("two blocks mu 0.6", lambda: small_wall(0.8, 0.4, 1.0, 1, 0.6), 0.4),
    ("three blocks side by side", lambda: small_wall(1.5, 0.5, 1.0, 1, 0.75), None),
    ("running bond, 3 courses", lambda: small_wall(1.0, 1.0, 0.6, 3, 0.8), None),
]


@pytest.mark.parametrize("name, make, exact", WALLS, ids=[w[0] for w in WALLS])
def test_lowest_reaches_the_proven_global_minimum(name: str, make, exact: float | None) -> None:  # type: ignore[no-untyped-def]
    # a node limit, not a time limit: the test ends alike on every machine
    wall = make()
    r = micro.solve_nonassociative(wall)
    g = micro.solve_global(wall, start=r, options=micro.GlobalOptions(direction_time_limit=None, node_limit=NODES))
    assert r.converged and g is not None and g.status == "optimal", g and g.message
    lam_it, lam_low = r.load_factor, r.lowest_load_factor
    assert lam_low <= lam_it * (1 + 1e-12)
    # never below the proven bound, and here the global minimum itself
    assert g.lower_bound <= lam_low * (1 + 1e-7) + 1e-9
    assert lam_low == pytest.approx(g.load_factor, rel=1e-7)
    if exact is not None:
        assert lam_low == pytest.approx(exact, rel=1e-7)
    rec = r.to_record(search=g)
    assert rec.global_status == "optimal" and rec.global_gap <= 1e-6
    assert rec.global_lower_bound == pytest.approx(g.lower_bound)


def test_iterated_lp_can_stop_above_the_global_minimum() -> None:
    """Two blocks side by side: the iterated LP stops at the band's top,
    8/13, 23 % above the global minimum 1/2 that the descent reaches."""
    r = micro.solve_nonassociative(small_wall(1.0, 0.5, 1.0, 1, 0.75))
    assert r.iterated_load_factor == pytest.approx(8 / 13, rel=1e-6)
    assert r.lowest_load_factor == pytest.approx(0.5, rel=1e-9) and r.load_factor == r.lowest_load_factor
