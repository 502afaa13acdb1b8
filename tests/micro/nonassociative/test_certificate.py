"""The certificate and the mechanism band."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative import Tuning, solve_nonassociative
from micro.nonassociative.certificate import Certificate

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey,
#: 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


def wall(t: float, m: float, rows: int = 12, storeys: int = 1, f: float = 0.75, **kw: object) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=storeys).to_micro(**kw)


@pytest.mark.parametrize("relaxation", [1.0, 0.6])
def test_scheme_b_certified_states_are_collapse_states(relaxation: float) -> None:
    """Regression: scheme (b)'s mechanisms may interpenetrate (its n columns
    enter the friction rows); such a mechanism is never certified (seen: a
    "certified" state with a dilatancy residual of 0.5 on this wall)."""
    from micro.nonassociative import verify_collapse_state

    w = wall(0.5, 1 / 3, rows=6, f=0.6)
    r = solve_nonassociative(w, tuning=Tuning(scheme="b", relaxation=relaxation))
    lp = micro.assemble(w)
    for d in r.directions:
        if d.converged and d.sequence.stop_reason == "certified":
            v = verify_collapse_state(lp, d)
            assert v["interpenetration"] <= 1e-8 and v["dilatancy"] <= 1e-8, v
            assert d.sequence.dilatancy_residual <= 1e-8
    # and the test the certificate applies: a mechanism run backwards closes
    # every opening joint, which no force field can make a collapse state
    a = solve_nonassociative(w)
    vel = np.asarray(a.governing.mechanism.velocities).ravel()
    for scheme in ("a", "b"):
        cert = Certificate(lp, 1, scheme)
        assert cert.pattern(vel) is not None
        assert cert.pattern(-vel) is None


def test_certified_stop(table7_default: list[micro.NonAssociativeResult]) -> None:
    """Set 14: the LPs' own forces never satisfy Coulomb (the plain sequence
    cycles), but a settled iterate's mechanism admits an exact collapse state
    at its load factor; the band of such states contains it."""
    w = wall(1.0, 1.0)
    r = table7_default[3]  # solve_nonassociative(w), shared (conftest.py)
    assert r.sequence.stop_reason == "certified" and r.converged
    assert r.sequence.history[-1].certificate == "certified"
    assert r.sequence.history[-1].certificate_iterations > 0
    assert r.sequence.coulomb_residual <= 1e-9
    lo, hi = r.mechanism_band
    assert lo <= r.iterated_load_factor <= hi
    assert hi <= r.associative_load_factor * (1 + 1e-7)
    # without the certificate the same sequence does not converge
    assert not solve_nonassociative(w, tuning=Tuning(certify=False)).converged


def test_certificate_rejects_wrong_load_factor(table7_default: list[micro.NonAssociativeResult]) -> None:
    """The certificate can fail: no state of the final mechanism lies far outside its band."""
    w = wall(1.0, 1.0)
    r = table7_default[3]  # solve_nonassociative(w), shared (conftest.py)
    lp = micro.assemble(w)
    cert = Certificate(lp, 1, "a")
    v = np.asarray(r.governing.mechanism.velocities).ravel()
    lo, hi = r.mechanism_band
    assert cert.certify(v, lo * 0.98, time_limit=60.0).forces is None
    assert cert.certify(v, hi * 1.02, time_limit=60.0).forces is None
    found = cert.certify(v, 0.5 * (lo + hi), time_limit=60.0).forces
    assert found is not None
    n, s = found
    assert np.max(np.abs(s) - lp.mu * n) <= 1e-9 * n.max()


def test_certificate_only_ends_the_sequence_earlier(table7_default: list[micro.NonAssociativeResult]) -> None:
    """The certificate does not change the path of the sequence: with and
    without it the LPs are the same up to the certified stop."""
    for (t, m, _), cert in zip(TABLE7, table7_default, strict=True):
        w = wall(t, m)
        plain = solve_nonassociative(w, tuning=Tuning(certify=False, selection="vertex"))
        assert cert.converged
        assert plain.iterations >= cert.iterations
        k = cert.iterations
        cert_lambdas = [h.load_factor for h in cert.sequence.history]
        assert [h.load_factor for h in plain.sequence.history[: k + 1]] == cert_lambdas


@pytest.mark.parametrize("trouble", ["inaccurate", "iteration_limit", "solver_error", "infeasible"])
def test_a_certificate_lp_in_numerical_trouble_is_solved_again(
        trouble: str, table7_default: list[micro.NonAssociativeResult], monkeypatch: pytest.MonkeyPatch,
        failing_solver: Callable[..., type]) -> None:
    """Where Clarabel ends a certificate LP in numerical trouble, HiGHS' interior point solves it again and
    gives the same band (on the 60-row base wall with frictionless head joints every Clarabel try had ended
    "inaccurate"); an answer (infeasible) is not solved again."""
    from micro.backends import roles  # the interior-point roles the certificate's LPs use
    from micro.backends.base import Status

    w = wall(1.0, 1.0)
    r = table7_default[3]  # solve_nonassociative(w), shared (conftest.py)
    lp = micro.assemble(w)
    v = np.asarray(r.governing.mechanism.velocities).ravel()
    lo, hi = r.mechanism_band

    monkeypatch.setattr(roles, "InteriorLP", failing_solver(Status(trouble), seconds=0.25))
    low, out = Certificate(lp, 1, "a").state_lp(v, 1.0)
    high, _ = Certificate(lp, 1, "a").state_lp(v, -1.0)
    if trouble == "infeasible":
        assert low is None and high is None and out.status is Status.INFEASIBLE
        return
    assert low is not None and high is not None and out.status is Status.OPTIMAL
    assert low[2] == pytest.approx(lo, rel=1e-6) and high[2] == pytest.approx(hi, rel=1e-6)
    assert out.seconds >= 0.25  # the failed try's time counts
    found = Certificate(lp, 1, "a").certify(v, 0.5 * (lo + hi)).forces
    assert found is not None


def test_the_same_restricted_lp_is_answered_once(table7_default: list[micro.NonAssociativeResult],
                                                 monkeypatch: pytest.MonkeyPatch,
                                                 failing_solver: Callable[..., type]) -> None:
    """A settled sequence asks about the same mechanism at each later iterate (Set 14 with frictionless
    head joints: four tries, one pattern): the LP of a pattern already solved is answered from its first
    solve (the same state, no time), another sense is solved, and a solve the user's time limit stopped is
    not kept."""
    from micro.backends import roles  # the interior-point roles the certificate's LPs use
    from micro.backends.base import Outcome, Status

    r = table7_default[3]  # solve_nonassociative(wall(1.0, 1.0)), shared (conftest.py)
    lp = micro.assemble(wall(1.0, 1.0))
    v = np.asarray(r.governing.mechanism.velocities).ravel()
    calls: list[int] = []
    real = roles.InteriorLP

    class Counting(real):  # type: ignore[misc, valid-type]
        def solve(self, direction: int) -> Outcome:
            calls.append(direction)
            return super().solve(direction)

    monkeypatch.setattr(roles, "InteriorLP", Counting)
    cert = Certificate(lp, 1, "a")
    first, out = cert.state_lp(v, 1.0)
    again, out_again = cert.state_lp(v.copy(), 1.0)
    assert first is not None and again is not None and len(calls) == 1
    assert again[2] == first[2] and np.array_equal(again[0], first[0]) and np.array_equal(again[1], first[1])
    assert out.seconds > 0 and out_again.seconds == 0 and out_again.status is Status.OPTIMAL
    high, _ = cert.state_lp(v, -1.0)
    assert len(calls) == 2 and high is not None and high[2] >= first[2]
    assert cert.certify(v, 0.5 * (first[2] + high[2])).forces is not None and len(calls) == 2

    monkeypatch.setattr(roles, "InteriorLP", failing_solver(Status.TIME_LIMIT, calls=calls))
    stopped = Certificate(lp, 1, "a")
    assert stopped.state_lp(v, 1.0, 1.0)[0] is None and stopped.state_lp(v, 1.0, 1.0)[0] is None
    assert len(calls) == 4
