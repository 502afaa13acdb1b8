"""The fused wall: blocks that move as one rigid body fused into one body."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.backends.base import Status
from micro.backends.clarabel import ClarabelStaticBackend
from micro.nonassociative import (
    Tuning,
    fusion,
    pipeline,
    solve_nonassociative,
    verify_collapse_state,
)
from micro.nonassociative.certificate import Certificate, CertificateResult
from micro.nonassociative.config import Resolved, resolve
from micro.nonassociative.fusion import fuse, rigid_bodies

EXACT = ("equilibrium", "coulomb", "interpenetration", "dilatancy", "slip_off_yield", "energy")


def wall(t: float = 1.0, m: float = 1 / 3, rows: int = 12, f: float = 0.75) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=1).to_micro()


def test_every_block_its_own_body_is_the_wall_itself() -> None:
    """With one body per block and none at rest the fused LP is the wall's
    LP: the aggregation is the identity (moments about each block's own
    centroid) and no point drops out."""
    lp = micro.assemble(wall())
    nb = lp.wall.n_blocks
    f = fuse(lp, np.arange(nb, dtype=np.int64), nb)
    assert f.lp.n_points == lp.n_points and f.lp.n_eq == lp.n_eq
    assert abs(f.lp.Bn - lp.Bn).max() < 1e-12 and abs(f.lp.Bs - lp.Bs).max() < 1e-12
    assert abs(f.lp.A - lp.A).max() < 1e-12
    assert np.allclose(f.lp.live, lp.live) and np.allclose(f.lp.rhs, lp.rhs)


def test_fused_equilibrium_follows_from_the_walls() -> None:
    """The wall's associative field restricted to the kept points is in
    equilibrium on the fused LP (the forces inside a body cancel in its
    summed rows), and a motion of the bodies spread to the blocks is rigid
    inside every body and zero at rest."""
    lp = micro.assemble(wall())
    out = ClarabelStaticBackend(lp).solve(1)
    assert out.n is not None and out.s is not None and out.duals is not None
    body, nbody = rigid_bodies(lp, np.asarray(out.duals[: lp.n_eq]))
    assert 0 < nbody < lp.wall.n_blocks and np.sum(body < 0) > 0
    f = fuse(lp, body, nbody)
    assert f.lp.n_points < lp.n_points
    n, s, lam = np.asarray(out.n), np.asarray(out.s), out.load_factor
    r = f.lp.Bn @ n[f.points] + f.lp.Bs @ s[f.points] + lam * f.lp.live - f.lp.rhs
    assert np.max(np.abs(r)) < 1e-7
    v = f.velocities(np.random.default_rng(0).normal(size=3 * nbody))
    dn, ds = lp.Bn.T @ v, lp.Bs.T @ v
    inside = np.setdiff1d(np.arange(lp.n_points), f.points)
    assert np.max(np.abs(dn[inside]), initial=0.0) < 1e-12 and np.max(np.abs(ds[inside]), initial=0.0) < 1e-12
    assert np.all(v.reshape(-1, 3)[body < 0] == 0.0)


def test_rigid_bodies_of_a_still_and_of_a_one_block_mechanism() -> None:
    """No motion: every block at rest. One moving block: it and the blocks
    it touches (both sides of a moving contact stay single) are the bodies,
    one block each."""
    lp = micro.assemble(wall())
    nb = lp.wall.n_blocks
    body, nbody = rigid_bodies(lp, np.zeros(lp.n_eq))
    assert nbody == 0 and np.all(body == -1)
    v = np.zeros(lp.n_eq)
    v[3 * (nb - 1)] = 1.0  # the last block (top row) slides
    body, nbody = rigid_bodies(lp, v)
    a, b = lp.wall.contact_a, lp.wall.contact_b
    touching = set(a[b == nb - 1]) | set(b[a == nb - 1]) | {nb - 1}
    touching.discard(-1)
    assert nbody == len(touching) >= 2 and set(np.flatnonzero(body >= 0)) == touching


@pytest.mark.parametrize("t, m", [(1.0, 1 / 3), (0.5, 1 / 3)])  # Table 7, Sets 12 and 11
def test_fused_sequences_end_in_exact_states_of_the_wall(t: float, m: float) -> None:
    """A fused run ends in a state of the WALL (forces at all its points,
    every block's motion) that passes every collapse condition, inside the
    wall's mechanism band and below the associative load; the record says
    it was fused."""
    w = wall(t, m)
    r = solve_nonassociative(w, tuning=Tuning(selection="vertex+proximal", fuse=True), lowest=False)
    assert r.converged, r.message
    lp = micro.assemble(w)
    for d in r.directions:
        q = d.sequence
        assert q is not None and q.fusion is not None and q.fusion.wall_certificate == "certified"
        assert 0 < q.fusion.points < lp.n_points == q.fusion.wall_points
        assert d.normal is not None and d.normal.shape == (lp.n_points,)
        v = verify_collapse_state(lp, d)
        assert max(v[k] for k in EXACT) <= 1e-9, v
        lo, hi = q.mechanism_band
        assert lo - 1e-7 <= d.load_factor <= hi + 1e-7
        assert d.load_factor <= q.associative_load_factor + 1e-9
    rec = r.to_record()
    assert rec.fused_bodies == r.sequence.fusion.bodies > 0 and rec.fused_points == r.sequence.fusion.points


def test_a_state_the_wall_rejects_is_a_failure(monkeypatch: pytest.MonkeyPatch) -> None:
    """When the certificate of the whole wall finds no state for the fused
    mechanism, the run fails and says so (no load factor, no forces)."""

    class Rejecting(Certificate):
        def certify(self, v: np.ndarray, lam: float, *, time_limit: float = math.inf) -> CertificateResult:
            return CertificateResult(None, None, 0.0, 0)

    monkeypatch.setattr(fusion, "Certificate", Rejecting)  # the wall's certificate only
    r = solve_nonassociative(wall(), tuning=Tuning(fuse=True), lowest=False, directions="+x")
    d = r.directions[0]
    assert not r.converged and math.isnan(r.load_factor) and d.normal is None
    assert d.status == "solver_failure" and d.sequence.stop_reason == "fused_state_rejected"
    assert d.sequence.fusion.wall_certificate == "rejected"
    assert "not a state of the wall" in d.message


def test_fuse_option_is_a_flag() -> None:
    assert dataclasses.replace(Tuning(), fuse=True).fuse
    with pytest.raises(ValueError, match=r"^fuse must be True or False"):  # a bool, not 1 or "no"
        Tuning(fuse=1)  # type: ignore[arg-type]


def _capped(r: Resolved, cap: int) -> Resolved:
    """``r`` with its sequence capped at ``cap`` LPs."""
    return dataclasses.replace(r, max_lps=cap)


def _capped_wall_sequences(monkeypatch: pytest.MonkeyPatch, cap: int,
                           fused_too: bool = False) -> list[tuple[int, bool, str]]:
    """Cap the sequences on the wall's own LP (and with ``fused_too`` those on
    the fused wall) at ``cap`` LPs each, so that they end ``max_iterations``;
    returns every sequence made: its LP's points, continuation and selection."""
    real = pipeline.LPSequence
    calls: list[tuple[int, bool, str]] = []

    class Capped(real):  # type: ignore[misc, valid-type]
        def __init__(self, lp: micro.LimitLP, d: int, r: Resolved, start: np.ndarray | None = None,
                     iterate0: Any = None) -> None:
            calls.append((lp.n_points, r.continuation, r.selection))
            if fused_too or lp.n_eq == 3 * lp.wall.n_blocks:  # the wall's own LP (not the bodies')
                r = _capped(r, cap)
            super().__init__(lp, d, r, start=start, iterate0=iterate0)

    monkeypatch.setattr(pipeline, "LPSequence", Capped)
    return calls


def test_fused_retry_certifies_where_the_walls_sequences_end_at_their_caps(monkeypatch: pytest.MonkeyPatch) -> None:
    """Where the vertex and the proximal sequences both end at their caps
    (forced: 2 LPs each on Table 7's Set 11), the fused wall with the
    continuation runs third; its state is an exact state of the WALL, the
    wall's sequences are kept in ``unfused_attempt`` and every LP counts."""
    calls = _capped_wall_sequences(monkeypatch, 2)
    w = wall(0.5)
    r = solve_nonassociative(w, tuning=Tuning(selection="vertex+proximal"), lowest=False, directions="+x")
    lp = micro.assemble(w)
    d = r.directions[0]
    q = d.sequence
    assert r.converged, r.message
    assert calls[:2] == [(lp.n_points, False, "vertex"), (lp.n_points, False, "proximal")]
    assert calls[2][1] and calls[2][0] < lp.n_points  # then the fused wall, with the continuation
    assert q.unfused_attempt is not None and q.unfused_attempt.stop_reason == "max_iterations"
    assert q.unfused_attempt.vertex_attempt is not None  # the vertex sequence, then the proximal one
    assert q.fusion is not None and q.fusion.wall_certificate == "certified"
    assert d.iterations == (len(q.unfused_attempt.vertex_attempt.history) - 1
                            + len(q.unfused_attempt.history) - 1 + len(q.history) - 1)
    v = verify_collapse_state(lp, d)  # the certificate's interior point: equilibrium to 7e-8 block weights here
    assert v["equilibrium"] <= 1e-6 and v["energy"] <= 1e-6, v
    assert max(v[k] for k in ("coulomb", "interpenetration", "dilatancy", "slip_off_yield")) <= 1e-9, v
    rec = r.to_record()
    assert rec.unfused_stop_reason == "max_iterations" and rec.fused_bodies > 0


def test_no_fused_retry_when_off_or_with_one_sequence(monkeypatch: pytest.MonkeyPatch) -> None:
    """``fused_retry=False``, or the vertex selection alone: the failed
    direction stays failed, and the wall's sequences are the only run."""
    calls = _capped_wall_sequences(monkeypatch, 2)
    points = micro.assemble(wall(0.5)).n_points
    for opts in ({"selection": "vertex+proximal", "fused_retry": False}, {"selection": "vertex"}):
        calls.clear()
        r = solve_nonassociative(wall(0.5), tuning=Tuning(**opts), lowest=False, directions="+x")  # type: ignore[arg-type]
        assert r.status == "max_iterations" and math.isnan(r.load_factor)
        assert calls and all(c[0] == points and not c[1] for c in calls)  # the wall's own sequences only
        assert r.directions[0].sequence.unfused_attempt is None and r.to_record().unfused_stop_reason == ""


def test_a_failed_fused_retry_leaves_the_walls_result(monkeypatch: pytest.MonkeyPatch) -> None:
    """A fused retry that fails too (its continuation capped at 2 LPs here)
    leaves the wall's status and band, with both runs' LPs and a message
    naming both."""
    _capped_wall_sequences(monkeypatch, 2, fused_too=True)
    r = solve_nonassociative(wall(0.5), tuning=Tuning(selection="vertex+proximal"), lowest=False, directions="+x")
    d = r.directions[0]
    assert d.status == "max_iterations" and d.sequence.lambda_band is not None
    assert "the fused wall with the continuation:" in d.message
    assert d.iterations > len(d.sequence.history) - 1 + len(d.sequence.vertex_attempt.history) - 1


@pytest.mark.parametrize("tuning, fused_retry, statuses, expected", [
    (Tuning(), True, ("converged",), ["vertex"]),
    (Tuning(), True, ("cycling", "converged"), ["vertex", "proximal"]),
    (Tuning(), True, ("cycling", "max_iterations", "converged"), ["vertex", "proximal", "fused"]),
    (Tuning(), True, ("max_iterations", "solver_failure"), ["vertex", "proximal"]),
    (Tuning(), False, ("cycling", "max_iterations"), ["vertex", "proximal"]),  # on the fused wall itself
    (Tuning(fused_retry=False), True, ("cycling", "max_iterations"), ["vertex", "proximal"]),
    (Tuning(selection="vertex"), True, ("cycling",), ["vertex"]),
    (Tuning(scheme="b"), True, ("cycling",), ["vertex"]),
])
def test_the_fallback_chain_runs_each_stage_where_the_ones_before_failed(
    monkeypatch: pytest.MonkeyPatch, tuning: Tuning, fused_retry: bool, statuses: tuple[str, ...],
    expected: list[str],
) -> None:
    """The chain of a direction (:func:`pipeline.run_stages`, plain code): the vertex sequence; with
    ``"vertex+proximal"`` the proximal retry where it cycled or hit its cap; then the fused wall with the
    continuation where both did (``fused_retry`` on scheme (a)). Fakes stand in for the stages: no LP."""
    from micro.nonassociative.config import resolve

    ran: list[str] = []
    left = list(statuses)

    def fake(name: str) -> Any:
        def run(*args: Any) -> pipeline.Attempt:
            ran.append(name)
            status = left.pop(0)
            lam = 0.5 if status == "converged" else math.nan
            return pipeline.Attempt(micro.DirectionResult("+x", status, lam, 1, 0.0), None)
        return run

    for name, stage in (("vertex", "_first_sequence"), ("proximal", "_proximal_retry"),
                        ("fused", "_fused_continuation")):
        monkeypatch.setattr(pipeline, stage, fake(name))
    resolved = resolve(10, micro.NonAssociativeOptions(tuning=tuning))
    result, _ = pipeline.run_stages(micro.assemble(wall(0.5)), 1, resolved, fused_retry=fused_retry)
    assert ran == expected and result.status == statuses[len(expected) - 1] and not left


def test_the_fused_walls_start_is_retried_where_clarabel_fails(
        monkeypatch: pytest.MonkeyPatch, failing_solver: Callable[..., type]) -> None:
    """The fused wall's associative LP goes through ``solve_interior`` as the iterated LP's start does: where
    ``InteriorLP`` fails, HiGHS' interior point gives the mechanism, and the fused wall is the same one (its
    bodies are read at a tolerance far above the two solvers' difference); the failed try's seconds count."""
    import micro.backends.roles as roles

    lp = micro.assemble(wall())
    resolved = resolve(lp.wall.n_blocks, micro.NonAssociativeOptions(tuning=Tuning(fuse=True)))
    made = fusion.fused_wall(lp, 1, resolved)
    assert made is not None
    monkeypatch.setattr(roles, "InteriorLP", failing_solver(Status.INACCURATE, seconds=0.25))
    again = fusion.fused_wall(lp, 1, resolved)
    assert again is not None, "the fused wall gave up where HiGHS' interior point would have solved its start"
    assert again[1].seconds >= 0.25 and again[1].load_factor == pytest.approx(made[1].load_factor, rel=1e-6)
    assert again[0].n_bodies == made[0].n_bodies and np.array_equal(again[0].points, made[0].points)
    monkeypatch.setattr(roles, "InteriorLPRetry", failing_solver(Status.INACCURATE))
    assert fusion.fused_wall(lp, 1, resolved) is None  # both fail: the wall itself runs
