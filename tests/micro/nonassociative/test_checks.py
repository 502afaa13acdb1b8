"""The independent collapse-state check on converged and non-converged states."""

from __future__ import annotations

import pytest

import micro
from comparison.domain.wall import WallSpec
from micro.nonassociative import CYCLING, Tuning, solve_nonassociative

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey,
#: 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


def wall(t: float, m: float, rows: int = 12, storeys: int = 1, f: float = 0.75, **kw: object) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=storeys).to_micro(**kw)


@pytest.mark.parametrize("kw, relaxation", [(dict(t=1.0, m=1 / 3), 0.6), (dict(t=1.0, m=1 / 2), 0.6),
                                            (dict(t=2.0, m=1.0, rows=6, f=0.6), 0.6),
                                            (dict(t=0.75, m=1 / 2, rows=6), 1.0)])
def test_converged_states_are_collapse_states(kw: dict, relaxation: float) -> None:
    """Converged (and certified) states satisfy every non-associative collapse
    condition, checked from the forces and the mechanism alone."""
    from micro.nonassociative import verify_collapse_state

    w = wall(**kw)
    r = solve_nonassociative(w, tuning=Tuning(relaxation=relaxation))
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


def test_not_converged_state_violates_yield() -> None:
    """The check can fail: the last iterate of a cycling sequence slips off the yield line."""
    from micro.nonassociative import verify_collapse_state

    w = wall(1.0, 1.0)
    r = solve_nonassociative(w, tuning=Tuning(relaxation=1.0, certify=False, selection="vertex"))
    assert r.status == CYCLING
    v = verify_collapse_state(micro.assemble(w), r.governing)
    assert v["slip_off_yield"] > 1e-3 or v["coulomb"] > 1e-3


def test_pattern_check_and_state_check_agree() -> None:
    """The global search's check (from raw velocities) and the iterated LP's
    check (from the stored mechanism) are one computation: on a converged
    state they give the same residuals, and a perturbed state fails both."""
    import numpy as np

    from micro.global_search.pattern import collapse_residuals
    from micro.limit_result import direction_sign
    from micro.nonassociative import verify_collapse_state

    w = wall(1.0, 1 / 3)
    r = solve_nonassociative(w)
    assert r.converged, r.message
    lp = micro.assemble(w)
    d = r.directions[0]
    assert d.normal is not None and d.shear is not None and d.mechanism is not None
    sign = direction_sign(d.direction)
    n, s = d.normal / lp.force_scale, d.shear / lp.force_scale
    v = d.mechanism.velocities.ravel()
    lam = r.sequence.last_load_factor
    a, b = verify_collapse_state(lp, d), collapse_residuals(lp, sign, n, s, lam, v)
    for key in ("equilibrium", "coulomb", "interpenetration", "dilatancy", "friction_direction"):
        assert a[key] == pytest.approx(b[key], rel=1e-9, abs=1e-15), key
    assert a["energy"] <= 1e-6 and b["energy"] <= 1e-6 and b["live_work"] > 0
    bad = collapse_residuals(lp, sign, n, s * 1.01 + 1e-3 * np.sign(s), lam, v)
    assert bad["equilibrium"] > 1e-4 and bad["coulomb"] > 1e-4


def test_cold_resolve_only_after_an_exact_stop(monkeypatch: pytest.MonkeyPatch) -> None:
    """The final iterate is re-solved cold after an exact stop only: not when
    the certificate found the state, nor when the sequence did not converge."""
    import math

    from micro.nonassociative import final_checks
    from micro.nonassociative.final_checks import COLD_CHECKED_STOPS, cold_check_due

    assert cold_check_due("lambda_and_forces") and cold_check_due("lambda_and_coulomb")
    assert not any(cold_check_due(s) for s in ("certified", "oscillating", "repeating", "max_iterations"))
    calls: list[float] = []
    real = final_checks.cold_check

    def counted(*args: object, **kwargs: object) -> final_checks.ColdCheck:
        out = real(*args, **kwargs)  # type: ignore[arg-type]
        calls.append(out.rel_diff)
        return out

    monkeypatch.setattr(final_checks, "cold_check", counted)
    w = wall(1.0, 1 / 3)  # Table 7's Set 12
    certified = solve_nonassociative(w, lowest=False)
    assert certified.sequence.stop_reason == "certified" and not calls
    assert math.isnan(certified.sequence.warm_cold_rel_diff)
    cycling = solve_nonassociative(wall(1.0, 1.0), lowest=False,
                                   tuning=Tuning(relaxation=1.0, certify=False, selection="vertex"))
    assert cycling.status == CYCLING and not calls
    exact = solve_nonassociative(w, lowest=False, tuning=Tuning(certify=False, selection="vertex"))
    assert exact.sequence.stop_reason in COLD_CHECKED_STOPS and len(calls) == 1
    assert exact.sequence.warm_cold_rel_diff == calls[0] <= 1e-6
