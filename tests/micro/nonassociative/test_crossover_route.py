"""The crossover route of the iterated LP (``Tuning.lp_route="crossover"``): each LP's vertex
from the normal-equations interior point and HiGHS' crossover instead of a warm dual simplex."""

from __future__ import annotations

import numpy as np
import pytest

from comparison.wall import WallSpec
from micro.backends.clarabel import ClarabelBackend
from micro.lp import LimitLP, assemble
from micro.nonassociative import Tuning, solve_nonassociative, verify_collapse_state
from micro.nonassociative.iteration import CROSSOVER
from micro.nonassociative.model import IterationModel, restart


def _lp(t: float = 1.0, m: float = 1 / 3, rows: int = 12) -> LimitLP:
    return assemble(WallSpec.from_paper(t=t, m=m, rows=rows, f=0.75, p=0, storeys=1).to_micro())


@pytest.mark.parametrize("scheme", ["a", "b"])
def test_the_route_finds_the_simplex_optimum(scheme: str) -> None:
    """Scheme (a)'s LP and the continuation's at slope 0 (rows ``+-s <= c0 + mu nbar``) at the
    associative forces of Set 12: the route's vertex has HiGHS' optimum to 1e-9 and its
    forces satisfy the LP's friction conditions."""
    alpha = 0.0
    lp = _lp()
    nbar = np.maximum(np.asarray(ClarabelBackend(lp).solve(1).n), 0.0)
    c0 = 1e-9 * float(nbar.max()) if scheme == "b" else 0.0
    routed, plain = IterationModel(lp, 1, scheme, alpha), IterationModel(lp, 1, scheme, alpha)
    for m in (routed, plain):
        m.set_capacity(nbar, alpha, alpha, c0)
    out = routed.interior_vertex(None)
    ref = restart(plain.model)
    assert out is not None and out.ok and ref.x is not None and out.x is not None
    assert routed.load_factor(out.x) == pytest.approx(plain.load_factor(ref.x), abs=1e-9)
    n, s = routed.forces(out.x)
    cap = c0 + lp.mu * nbar
    assert np.all(n >= -1e-9) and np.all(np.abs(s) <= cap + 1e-8)


@pytest.mark.parametrize("alpha", [0.3, -0.5])
def test_the_route_does_not_take_a_sloped_lp(alpha: float) -> None:
    """Scheme (b)'s rows and the continuation's with a non-zero slope stay with the simplex."""
    lp = _lp()
    m = IterationModel(lp, 1, "b", alpha)
    m.set_capacity(np.ones(lp.n_points), alpha, alpha, 0.0)
    assert m.interior_vertex(None) is None


@pytest.mark.parametrize("t, m", [(1.0, 1 / 3), (1.0, 0.5)])  # Table 7, Sets 12 and 13
def test_sequences_on_the_route_end_in_exact_states(t: float, m: float) -> None:
    """The whole method on the route: every LP after the associative one went through it, and
    the state returned is an exact collapse state inside its mechanism band."""
    w = WallSpec.from_paper(t=t, m=m, rows=12, f=0.75, p=0, storeys=1).to_micro()
    r = solve_nonassociative(w, tuning=Tuning(lp_route="crossover"), lowest=False)
    assert r.converged, r.message
    d = r.directions[0]
    assert d.sequence is not None and d.sequence.mechanism_band is not None
    assert all(h.algorithm == CROSSOVER for h in d.sequence.history[1:])
    lo, hi = d.sequence.mechanism_band
    assert lo - 1e-6 <= r.load_factor <= hi + 1e-6
    res = verify_collapse_state(assemble(w), d)
    assert res["equilibrium"] <= 1e-6 and res["coulomb"] <= 1e-9 and res["dilatancy"] <= 1e-6


def test_a_bad_route_is_refused() -> None:
    with pytest.raises(ValueError, match="lp_route"):
        Tuning(lp_route="barrier")  # type: ignore[arg-type]
