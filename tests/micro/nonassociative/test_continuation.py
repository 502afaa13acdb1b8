"""The continuation: scheme (a) reached from associative friction through friction rows of falling slope."""

from __future__ import annotations

import math

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative import Tuning, solve_nonassociative, verify_collapse_state
from micro.nonassociative.config import EQUILIBRIUM_RESIDUAL
from micro.nonassociative.selections import CONT_FACTOR, CONT_GAMMA0, CONT_GAMMA_MIN

EXACT = ("coulomb", "interpenetration", "dilatancy", "slip_off_yield")


def wall(t: float = 1.0, m: float = 1 / 3) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=12, f=0.75, p=0, storeys=1).to_micro()


@pytest.mark.parametrize("fuse", [False, True])
def test_continuation_ends_in_exact_states(fuse: bool) -> None:
    """Table 7's Set 12 by the continuation (on the wall and fused) ends
    certified in states that pass every collapse condition, inside their
    mechanism bands; the slopes of its LPs are ``-gamma``, ``gamma`` falling
    by :data:`CONT_FACTOR` from :data:`CONT_GAMMA0`, then 0 from the first
    LP where it would reach :data:`CONT_GAMMA_MIN`."""
    w = wall()
    r = solve_nonassociative(w, tuning=Tuning(continuation=True, fuse=fuse), lowest=False)
    assert r.converged, r.message
    lp = micro.assemble(w)
    n_cont = 1 + math.floor(math.log(CONT_GAMMA_MIN / CONT_GAMMA0) / math.log(CONT_FACTOR))
    for d in r.directions:
        q = d.sequence
        assert q is not None and (q.fusion is not None) == fuse
        v = verify_collapse_state(lp, d)
        assert max(v[k] for k in EXACT) <= 1e-9, v
        # its lambda sits at the top of the band, within the certificate's
        # slack (BAND_SLACK): the end state is checked at the iterate's lambda
        assert v["equilibrium"] <= EQUILIBRIUM_RESIDUAL and v["energy"] <= 1e-6, v
        lo, hi = q.mechanism_band
        assert lo - 1e-7 <= d.load_factor <= hi + 1e-7
        alphas = [h.alpha for h in q.history[1:]]
        assert len(alphas) > n_cont and all(a == 0.0 for a in alphas[n_cont:])
        assert alphas[:n_cont] == pytest.approx([-CONT_GAMMA0 * CONT_FACTOR**k for k in range(n_cont)])
        assert -alphas[n_cont - 1] > CONT_GAMMA_MIN >= -alphas[n_cont - 1] * CONT_FACTOR
        certified = [h.iteration for h in q.history if h.certificate]
        assert certified and min(certified) > n_cont  # tried only once gamma = 0


@pytest.mark.parametrize("kw", [{"scheme": "b"}, {"selection": "proximal"}])
def test_continuation_needs_a_vertex_sequence_of_scheme_a(kw: dict[str, str]) -> None:
    with pytest.raises(ValueError, match="continuation needs scheme 'a'"):
        Tuning(continuation=True, **kw)  # type: ignore[arg-type]


def test_continuation_is_a_flag() -> None:
    assert Tuning(continuation=True, selection="vertex+proximal").continuation is True
    # a flag is a bool (1 or "no" would read as True); like global_=1, it is refused
    with pytest.raises(ValueError, match=r"^continuation must be True or False or None \(by the wall's size\), got 1$"):
        Tuning(continuation=1, selection="vertex+proximal")  # type: ignore[arg-type]
