"""Exact closed-form collapse loads: one block, a column, two blocks side by side.

Each case has a load factor derived by hand (in the test's docstring) that
the associative LP, the iterated LP and the global MIP must reproduce.
"""

from __future__ import annotations

import numpy as np
import pytest
from enumeration import Enumerator
from hand_walls import column_wall, small_wall

import micro
from micro.global_search import solve_global
from micro.global_search.global_types import Pattern
from micro.global_search.pattern import force_state, mechanism


@pytest.mark.parametrize("b, h, mu", [(1.0, 2.0, 0.75), (2.0, 1.0, 0.75), (1.0, 1.0, 0.6), (1.5, 1.0, 0.7)])
def test_single_block(b: float, h: float, mu: float) -> None:
    """A block ``b`` wide and ``h`` high on a fixed base, live load ``lambda W``
    at its centroid: it slides when the base shear ``lambda W`` reaches
    ``mu W``, and overturns about its toe when the moment ``lambda W h / 2``
    reaches ``W b / 2``. The forces are statically determinate, so the
    associative and the non-associative collapse loads coincide:
    ``lambda = min(mu, b / h)``."""
    w = small_wall(b, b, h, 1, mu)
    exact = min(mu, b / h)
    assert micro.solve_associative(w).load_factor == pytest.approx(exact, rel=1e-7)
    g = solve_global(w, direction="both")
    assert g.status == "optimal"
    assert g.load_factor == pytest.approx(exact, abs=1e-9)
    assert g.lower_bound == pytest.approx(exact, abs=1e-7)
    it = micro.solve_nonassociative(w)
    assert it.converged and it.load_factor == pytest.approx(exact, rel=1e-7)
    state = g.directions[0].mechanism
    assert state is not None
    expected = "sliding" if mu < b / h else "opening"
    assert micro.mechanism.CONTACT_STATE_NAMES[int(state.contact_state[0])] == expected


def test_builder_makes_no_column() -> None:
    """``build_wall`` lays running bond: a wall one block long is a full block
    under two half blocks, so the column below is built by hand."""
    w = small_wall(1.0, 1.0, 1.0, 2, 0.75)
    assert w.n_blocks == 3
    assert column_wall(2, 1.0, 1.0, 0.75).n_blocks == 2


@pytest.mark.parametrize("k, b, h, mu", [(2, 1.0, 1.0, 0.75), (3, 1.0, 1.0, 0.75), (4, 1.0, 0.5, 0.3),
                                         (3, 2.0, 0.5, 0.6)])
def test_column(k: int, b: float, h: float, mu: float) -> None:
    """``k`` aligned blocks ``b x h`` (weight ``W`` each). Below the top ``j``
    blocks the resultant is ``N_j = j W`` (vertical), ``S_j = lambda j W``
    (horizontal) at height ``j h / 2`` above the joint: sliding there needs
    ``lambda = mu``; overturning about the toe needs ``lambda j W j h / 2 =
    j W b / 2``, i.e. ``lambda = b / (j h)``, least for the whole column
    (``j = k``: ``b / H``). The statics is determinate and no joint reaches a
    limit below ``min(mu, b / H)``: ``lambda = min(mu, b / (k h))`` with
    either friction law."""
    w = column_wall(k, b, h, mu)
    exact = min(mu, b / (k * h))
    assert micro.solve_associative(w).load_factor == pytest.approx(exact, rel=1e-7)
    g = solve_global(w, direction=1)
    assert g.status == "optimal"
    assert g.load_factor == pytest.approx(exact, abs=1e-9)
    it = micro.solve_nonassociative(w)
    assert it.converged and it.load_factor == pytest.approx(exact, rel=1e-7)


def test_two_blocks_band() -> None:
    """Two blocks ``A = [0, l] x [0, h]`` and ``B = [l, 2l] x [0, h]`` side by
    side on a fixed base, weight ``W`` each, live load ``lambda W`` at each
    centroid (``+x``), ``l / h = 1/2``, ``mu = 3/4``.

    Mechanism: each block rocks about its own right toe with the same
    rotation; the head joint stays closed (its points keep their horizontal
    distance) and B slides UP along A by ``omega l`` (slip rate < 0 along the
    head joint's tangent ``(0, -1)``), so the head's friction pulls B down and
    pushes A up: ``t_i = mu m_i`` at its points (``m_i`` normal forces, ``M``
    and ``T = mu M`` their sums, ``m_1`` at the top). Moments about the toes:

    * A about ``(l, 0)``: ``-lambda W h/2 + W l/2 + h m_1 = 0``;
    * B about ``(2l, 0)``: ``-lambda W h/2 + W l/2 + l T - h m_1 = 0``.

    Adding: ``lambda = (l/h)(1 + tau)`` with ``tau = T / W``, and
    ``m_1 = l T / (2h)``, ``m_0 = T/mu - m_1 >= 0`` (holds for ``mu <= 2h/l``).
    The base of B must not slide: ``lambda W + M <= mu (W + T)``, i.e.
    ``tau (l/h + 1/mu - mu) <= mu - l/h``; A's base (``|M - lambda W| <= mu
    (W - T)``) and ``T <= W`` are slack. So the mechanism forms at every
    ``lambda`` in ``[l/h, (l/h)(1 + tau*)]`` with ``tau* = (mu - l/h) /
    (l/h + 1/mu - mu) = 3/13``: the band ``[1/2, 8/13]``. Its lower end
    (``T = 0``: two free-standing blocks rocking) is the global minimum
    ``l/h``, strictly below the associative load factor."""
    ell, h, mu = 0.5, 1.0, 0.75  # l, h, mu of the docstring
    w = small_wall(2 * ell, ell, h, 1, mu)
    lp = micro.assemble(w)
    assert w.n_blocks == 2 and lp.n_points == 6  # contacts: base A, base B, head
    tau = (mu - ell / h) / (ell / h + 1 / mu - mu)
    band = (ell / h, (ell / h) * (1 + tau))
    assert band[1] == pytest.approx(8 / 13)
    # points: A base (0,0) open, (l,0) pivot; B base (l,0) open, (2l,0) pivot; head closed
    pattern = Pattern(np.array([True, False, True, False, False, False]), np.array([0, 0, -1]))
    lo, hi = force_state(lp, 1, pattern), force_state(lp, 1, pattern, sense=-1.0)
    assert lo is not None and hi is not None
    assert (lo[2], hi[2]) == pytest.approx(band, abs=1e-9)
    assert mechanism(lp, 1, pattern) is not None
    # the same band from the independent enumeration code
    e = Enumerator(lp, 1)
    states = [(1, 0, 0), (1, 0, 0), (0, 0, -1)]
    assert (e.forces(states), e.forces(states, sense=-1.0)) == pytest.approx(band, abs=1e-9)
    g = solve_global(w, direction=1)
    assert g.status == "optimal" and g.load_factor == pytest.approx(ell / h, abs=1e-9)
    assert micro.solve_associative(w).load_factor > ell / h + 0.1
