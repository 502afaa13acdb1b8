"""Non-associative friction by the iterated LP (issue 4): fast tests.

Every wall here has 36-150 blocks; the whole file runs in a few seconds.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import micro
from comparison.cli import main
from comparison.wall import WallSpec
from micro.nonassociative import (
    CONVERGED,
    CYCLING,
    MAX_ITERATIONS,
    STATUSES,
    _detect_cycle,
    solve_nonassociative,
)

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey,
#: 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


def wall(t: float, m: float, rows: int = 12, storeys: int = 1, f: float = 0.75, **kw: object) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=storeys).to_micro(**kw)


@pytest.fixture(scope="module")
def table7_default() -> list[micro.NonAssociativeResult]:
    return [solve_nonassociative(wall(t, m)) for t, m, _ in TABLE7]


# ------------------------------------------------------------------ accuracy
@pytest.mark.parametrize("i", range(4))
def test_table7_within_5_percent(table7_default: list, i: int) -> None:
    """Last iterate (or the band of a cycling sequence) within 5 % of Orduna's value."""
    t, m, ref = TABLE7[i]
    r = table7_default[i]
    g = r.governing
    assert abs(g.last_load_factor / ref - 1) <= 0.05
    if r.converged:
        assert abs(r.load_factor / ref - 1) <= 0.05
    else:
        lo, hi = r.lambda_band
        assert abs(lo / ref - 1) <= 0.05 and abs(hi / ref - 1) <= 0.05


def test_table7_sets_11_to_13_converge(table7_default: list) -> None:
    """The default (scheme a, relaxation 0.6) converges on sets 11-13."""
    assert [r.status for r in table7_default[:3]] == [CONVERGED] * 3


@pytest.mark.parametrize("i", range(4))
def test_below_associative(table7_default: list, i: int) -> None:
    r = table7_default[i]
    assoc = micro.solve_associative(wall(*TABLE7[i][:2])).load_factor
    assert r.associative_load_factor == pytest.approx(assoc, rel=1e-6)
    # intermediate iterates may exceed it (|s| <= mu nbar with n free); the final one may not
    assert r.governing.last_load_factor <= assoc * (1 + 1e-7)
    if r.lambda_band is not None:
        assert r.lambda_band[1] <= assoc * (1 + 1e-7)


@pytest.mark.parametrize("scheme", ["a", "b"])
@pytest.mark.parametrize("kw", [dict(t=1.6, m=1 / 3), dict(t=0.8, m=1 / 2, rows=8), dict(t=1, m=1 / 3, rows=6),
                                dict(t=2, m=1 / 2, rows=6, f=0.6)])
def test_below_associative_other_walls(scheme: str, kw: dict) -> None:
    """lambda_nonassoc <= lambda_assoc per direction, also on a wall that is not mirror-symmetric."""
    w = wall(**kw)
    r = solve_nonassociative(w, scheme=scheme, directions="both")
    for d in r.directions:
        assoc = micro.solve_associative(w, directions=d.direction).load_factor
        assert d.associative_load_factor == pytest.approx(assoc, rel=1e-6)
        # scheme (b)'s tiny cohesion c0 (1e-6 of the largest normal force per
        # point) may lift lambda by a few 1e-6 relative; scheme (a) has none
        assert d.last_load_factor <= assoc * (1 + (1e-7 if scheme == "a" else 2e-5))
        assert d.status != "solver_failure", d.message
        assert d.equilibrium_residual <= 1e-7  # regression: -x once checked with +lambda


# ------------------------------------------------------------ final state
@pytest.mark.parametrize("i", range(3))
def test_final_state_checks_scheme_a(table7_default: list, i: int) -> None:
    r = table7_default[i]
    assert r.converged
    assert r.coulomb_residual <= 1e-6
    assert r.dilatancy_residual <= 1e-8  # |s| <= mu nbar: no dilatancy by construction
    assert r.warm_cold_rel_diff <= 1e-6
    g = r.governing
    assert g.equilibrium_residual <= 1e-7
    assert g.sliding_points > 0
    # Coulomb recomputed here from the dimensional forces
    mu = np.repeat(wall(*TABLE7[i][:2]).mu, 2)
    n, s = g.normal, g.shear
    assert np.all(n >= -1e-9 * n.max())
    assert np.max(np.abs(s) - mu * n) <= 1e-6 * n.max()


def test_scheme_b_converges_with_small_dilatancy() -> None:
    r = solve_nonassociative(wall(1.0, 1 / 3), scheme="b")
    assert r.status == CONVERGED
    assert r.history[-1].alpha == pytest.approx(1e-3)
    assert r.dilatancy_residual <= 2 * 1e-3 * 0.75  # slope alpha mu of the last line
    assert r.coulomb_residual <= 1e-5
    assert r.warm_cold_rel_diff <= 1e-6
    assert abs(r.load_factor / 0.68 - 1) <= 0.05


# ------------------------------------------------------------------ cycling
@pytest.mark.parametrize("t, m", [(0.5, 1 / 3), (1.0, 1 / 3), (1.0, 1.0)])
def test_naive_scheme_cycles_default_converges(t: float, m: float) -> None:
    """Regression: the plain iterated LP (scheme a, no relaxation, no certificate)
    cycles on these walls; the default converges."""
    w = wall(t, m)
    naive = solve_nonassociative(w, scheme="a", relaxation=1.0, certify=False)
    assert naive.status == CYCLING
    assert not naive.converged and not naive.ok
    assert math.isnan(naive.load_factor)
    lo, hi = naive.lambda_band
    assert lo <= naive.governing.last_load_factor <= hi
    assert naive.governing.stop_reason in ("repeating", "oscillating", "stagnation")
    assert solve_nonassociative(w).status == CONVERGED


def test_cycling_band_on_set_14() -> None:
    """Set 14 (m = 1): the naive scheme oscillates by ~5 %; the band is reported."""
    r = solve_nonassociative(wall(1.0, 1.0), scheme="a", relaxation=1.0, certify=False)
    assert r.status == CYCLING
    lo, hi = r.lambda_band
    assert hi > lo * 1.01
    assert r.summary()["lambda_band"] == [lo, hi]
    assert r.summary()["load_factor"] is None


def test_max_iterations_is_not_converged() -> None:
    r = solve_nonassociative(wall(1.0, 1 / 2), max_iterations=3)
    assert r.status == MAX_ITERATIONS
    assert math.isnan(r.load_factor) and not r.converged
    assert r.iterations == 3 and len(r.history) == 4
    assert r.lambda_band is not None


def test_detect_cycle_synthetic() -> None:
    tol = 1e-6
    assert _detect_cycle([0.5, 0.6, 0.5, 0.6], [1.0] * 4, tol, 10) == ("repeating", (0.5, 0.6))
    assert _detect_cycle([0.5, 0.6, 0.7, 0.5, 0.6, 0.7], [1.0] * 6, tol, 10)[0] == "repeating"
    conv = [0.5 + 0.1 * 0.5**k for k in range(30)]
    assert _detect_cycle(conv, [0.5**k for k in range(30)], tol, 10) is None
    rng = np.random.default_rng(0)
    noisy = list(0.5 + 0.01 * rng.random(30))
    assert _detect_cycle(noisy, [1.0] * 30, tol, 10)[0] == "oscillating"
    flat = [0.5] * 30
    assert _detect_cycle(flat, [0.1] * 30, tol, 10)[0] == "stagnation"
    assert _detect_cycle(flat, [0.5**k for k in range(30)], tol, 10) is None


# ------------------------------------------------------------------ history
def test_history_contents(table7_default: list) -> None:
    r = table7_default[1]
    h = r.history
    assert h[0].iteration == 0 and h[0].algorithm in ("clarabel", "ipm", "ipm+crossover+simplex")
    assert h[0].load_factor == pytest.approx(r.associative_load_factor)
    assert [rec.iteration for rec in h] == list(range(len(h)))
    assert len(h) == r.iterations + 1
    assert all(rec.status == "optimal" for rec in h)
    assert all(rec.seconds > 0 for rec in h)
    warm = [rec for rec in h[2:] if rec.algorithm == "simplex-warm"]
    assert len(warm) == len(h) - 2
    # warm starts: far fewer simplex iterations than the first (cold) LP on average
    assert np.mean([rec.simplex_iterations for rec in warm]) < h[1].simplex_iterations
    # the sequence stopped on a settled, certified iterate
    assert h[-1].certificate == "certified"
    assert max(abs(rec.load_factor / h[-1].load_factor - 1) for rec in h[-3:]) <= 1e-3
    assert r.status in STATUSES
    json.dumps(r.summary())


def test_vertex_start() -> None:
    r = solve_nonassociative(wall(1.0, 1 / 3), start="vertex")
    assert r.history[0].algorithm == "ipm+crossover+simplex"
    assert r.governing.last_load_factor <= r.associative_load_factor * (1 + 1e-7)
    assert abs(r.governing.last_load_factor / 0.68 - 1) <= 0.05


# ------------------------------------------------------------------ inputs
@pytest.mark.parametrize(
    "kw, word",
    [
        (dict(scheme="c"), "scheme"),
        (dict(relaxation=0.0), "relaxation"),
        (dict(relaxation=1.5), "relaxation"),
        (dict(relaxation=True), "relaxation"),
        (dict(max_iterations=1), "max_iterations"),
        (dict(window=2), "window"),
        (dict(directions="up"), "directions"),
        (dict(start="warm"), "start"),
        (dict(lambda_tol=0.0), "lambda_tol"),
        (dict(alpha0=1e-4, alpha_min=1e-3), "alpha_min"),
        (dict(alpha_factor=2.0), "alpha_factor"),
        (dict(time_limit=-1.0), "time_limit"),
        (dict(settle_tol=1.0), "settle_tol"),
        (dict(settle_window=1), "settle_window"),
        (dict(state_solver="gurobi"), "state_solver"),
    ],
)
def test_bad_inputs(kw: dict, word: str) -> None:
    with pytest.raises(ValueError, match=word):
        solve_nonassociative(wall(1.0, 1 / 3, rows=6), **kw)


# ---------------------------------------------------------------------- CLI
def test_cli_json(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75",
                 "--friction", "nonassociative", "--scheme", "a", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    for key in ("iterations", "converged", "status", "history", "load_factor", "lambda_band"):
        assert key in out
    assert out["converged"] is True and out["status"] == "converged"
    assert out["history"][0]["iteration"] == 0
    assert len(out["history"]) == out["iterations"] + 1
    assert abs(out["load_factor"] / 0.68 - 1) <= 0.05


def test_cli_plot(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:  # type: ignore[no-untyped-def]
    png = tmp_path / "mech.png"
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75",
                 "--friction", "nonassociative", "--plot", str(png), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["plot"] == str(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_cycling_exit_code(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["micro", "--t", "1", "--m", "1", "--rows", "12", "--f", "0.75",
                 "--friction", "nonassociative", "--relaxation", "1", "--no-certify", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 1
    assert out["converged"] is False and out["status"] == "cycling" and out["load_factor"] is None


@pytest.mark.parametrize("extra", [["--scheme", "c"], ["--relaxation", "0"], ["--max-iterations", "x"],
                                   ["--solver", "clarabel"]])
def test_cli_bad_options(extra: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "6", "--f", "0.75",
                 "--friction", "nonassociative", *extra])
    assert code == 2
    assert "xcheck: error:" in capsys.readouterr().err


def test_time_budget_is_not_converged() -> None:
    r = solve_nonassociative(wall(1.0, 1.0), relaxation=1.0, max_seconds=1e-3)
    assert r.status == MAX_ITERATIONS and r.governing.stop_reason == "time_budget"
    assert math.isnan(r.load_factor) and r.lambda_band is not None
    with pytest.raises(ValueError, match="max_seconds"):
        solve_nonassociative(wall(1.0, 1.0), max_seconds=0)


# ------------------------------------------- independent collapse-state check
@pytest.mark.parametrize("kw, relaxation", [(dict(t=1.0, m=1 / 3), 0.6), (dict(t=1.0, m=1 / 2), 0.6),
                                            (dict(t=2.0, m=1.0, rows=6, f=0.6), 0.6),
                                            (dict(t=0.75, m=1 / 2, rows=6), 1.0)])
def test_converged_states_are_collapse_states(kw: dict, relaxation: float) -> None:
    """Converged (and certified) states satisfy every non-associative collapse
    condition, checked from the forces and the mechanism alone."""
    from micro.nonassociative import verify_collapse_state

    w = wall(**kw)
    r = solve_nonassociative(w, relaxation=relaxation)
    assert r.converged, r.message
    lp = micro.assemble(w)
    for d in r.directions:
        v = verify_collapse_state(lp, d)
        assert v["equilibrium"] <= 1e-7
        assert v["coulomb"] <= 2e-6
        assert v["interpenetration"] <= 1e-8
        assert v["dilatancy"] <= 1e-8
        assert v["slip_off_yield"] <= 2e-6
        assert v["friction_direction"] <= 1e-9
        assert v["energy"] <= 1e-6
        assert v["slipping_points"] > 0


@pytest.mark.parametrize("relaxation", [1.0, 0.6])
def test_scheme_b_certified_states_are_collapse_states(relaxation: float) -> None:
    """Regression: scheme (b)'s mechanisms may interpenetrate (its n columns
    enter the friction rows); such a mechanism is never certified (seen: a
    "certified" state with a dilatancy residual of 0.5 on this wall)."""
    from micro.nonassociative import verify_collapse_state

    w = wall(0.5, 1 / 3, rows=6, f=0.6)
    r = solve_nonassociative(w, scheme="b", relaxation=relaxation)
    lp = micro.assemble(w)
    for d in r.directions:
        if d.converged and d.stop_reason == "certified":
            v = verify_collapse_state(lp, d)
            assert v["interpenetration"] <= 1e-8 and v["dilatancy"] <= 1e-8, v
            assert d.dilatancy_residual <= 1e-8
    # and the test the certificate applies: a mechanism run backwards closes
    # every opening joint, which no force field can make a collapse state
    from micro.nonassociative import _Sequence

    a = solve_nonassociative(w)
    vel = np.asarray(a.governing.mechanism.velocities).ravel()
    for scheme in ("a", "b"):
        seq = _Sequence(lp, 1, a.options | {"scheme": scheme})
        assert seq._pattern(vel) is not None
        assert seq._pattern(-vel) is None


def test_certified_stop() -> None:
    """Set 14: the LPs' own forces never satisfy Coulomb (the plain sequence
    cycles), but a settled iterate's mechanism admits an exact collapse state
    at its load factor; the band of such states contains it."""
    w = wall(1.0, 1.0)
    r = solve_nonassociative(w)
    assert r.governing.stop_reason == "certified" and r.converged
    assert r.history[-1].certificate == "certified"
    assert r.history[-1].certificate_iterations > 0
    assert r.coulomb_residual <= 1e-9
    lo, hi = r.mechanism_band
    assert lo <= r.load_factor <= hi
    assert hi <= r.associative_load_factor * (1 + 1e-7)
    # without the certificate the same sequence does not converge
    assert not solve_nonassociative(w, certify=False).converged


def test_certificate_rejects_wrong_load_factor() -> None:
    """The certificate can fail: no state of the final mechanism lies far outside its band."""
    from micro.nonassociative import _Sequence

    w = wall(1.0, 1.0)
    r = solve_nonassociative(w)
    lp = micro.assemble(w)
    seq = _Sequence(lp, 1, r.options)
    v = np.asarray(r.governing.mechanism.velocities).ravel()
    lo, hi = r.mechanism_band
    assert seq._certify(v, lo * 0.98, time_limit=60.0)[0] is None
    assert seq._certify(v, hi * 1.02, time_limit=60.0)[0] is None
    found = seq._certify(v, 0.5 * (lo + hi), time_limit=60.0)[0]
    assert found is not None
    n, s = found
    assert np.max(np.abs(s) - lp.mu * n) <= 1e-9 * n.max()


def test_not_converged_state_violates_yield() -> None:
    """The check can fail: the last iterate of a cycling sequence slips off the yield line."""
    from micro.nonassociative import verify_collapse_state

    w = wall(1.0, 1.0)
    r = solve_nonassociative(w, relaxation=1.0, certify=False)
    assert r.status == CYCLING
    v = verify_collapse_state(micro.assemble(w), r.governing)
    assert v["slip_off_yield"] > 1e-3 or v["coulomb"] > 1e-3


def test_certificate_agrees_between_interior_point_solvers() -> None:
    """Clarabel and HiGHS IPM solve the certificate LPs: the same sequence,
    the same certified load factor, and mechanism bands whose ends agree to
    the interior points' accuracy (the ends are load factors of feasible
    states, so a band can only come out narrower)."""
    w = wall(1.0, 1 / 3)
    a = solve_nonassociative(w, state_solver="clarabel")
    b = solve_nonassociative(w, state_solver="highs")
    assert a.converged and b.converged
    assert a.load_factor == b.load_factor  # same warm-started LPs, same stop
    assert a.mechanism_band == pytest.approx(b.mechanism_band, rel=1e-4)
    for r in (a, b):
        assert r.mechanism_band[0] <= r.load_factor <= r.mechanism_band[1]


def test_certificate_only_ends_the_sequence_earlier() -> None:
    """The certificate does not change the path of the sequence: with and
    without it the LPs are the same up to the certified stop."""
    for t, m, _ in TABLE7:
        w = wall(t, m)
        cert = solve_nonassociative(w)
        plain = solve_nonassociative(w, certify=False)
        assert cert.converged
        assert plain.iterations >= cert.iterations
        k = cert.iterations
        assert [h.load_factor for h in plain.history[: k + 1]] == [h.load_factor for h in cert.history]
