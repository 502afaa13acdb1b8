"""The reduced wall (``micro.nonassociative.reduced``): where the associative mechanism has a dominant rigid
part, states found on models of its rigid parts and lifted onto the wall; elsewhere the wall's own chain."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import micro
from comparison.domain.wall import WallSpec
from comparison.report.tables import selection_cell
from micro.backends.base import Status
from micro.backends.roles import InteriorLP
from micro.nonassociative.config import REDUCE_BLOCKS, resolve
from micro.nonassociative.final_checks import verify_collapse_state
from micro.nonassociative.fusion import rigid_bodies
from micro.nonassociative.reduced import DOMINANT_SHARE, dominant_share, refined, solve_reduced

#: Table 7's Set 13 (78 blocks, m = 1/2): a rigid wedge holds 56 % of the moving blocks.
SET13 = WallSpec.from_paper(t=1, m=1 / 2, rows=12, f=0.75)
#: 36 rows of m = 1/3 (450 blocks): a fan of single rocking blocks, its largest rigid part 11 %.
FAN = WallSpec.from_paper(t=1, m=1 / 3, rows=36, f=0.6)
REDUCE = micro.Tuning(reduce=True)


def _bodies(spec: WallSpec) -> tuple[micro.LimitLP, np.ndarray]:
    lp = micro.assemble(spec.to_micro())
    assoc = InteriorLP(lp).solve(1)
    assert assoc.duals is not None
    return lp, rigid_bodies(lp, np.asarray(assoc.duals[: lp.n_eq]), 1e-3, single_band=False)[0]


def test_the_default_tries_it_on_large_walls_only() -> None:
    assert not resolve(REDUCE_BLOCKS).reduce and resolve(REDUCE_BLOCKS + 1).reduce
    assert not resolve(REDUCE_BLOCKS + 1, micro.NonAssociativeOptions(tuning=micro.Tuning(scheme="b"))).reduce
    assert resolve(10, micro.NonAssociativeOptions(tuning=REDUCE)).reduce


def test_a_wedge_is_dominant_and_a_fan_is_not() -> None:
    assert dominant_share(_bodies(SET13)[1]) >= DOMINANT_SHARE > dominant_share(_bodies(FAN)[1])
    assert dominant_share(np.full(4, -1)) == 0.0


def test_refined_makes_the_blocks_at_moving_contacts_single() -> None:
    lp, body = _bodies(SET13)
    v = np.zeros(lp.n_eq)
    wedge = np.flatnonzero(body == np.bincount(body[body >= 0]).argmax())
    v[3 * wedge] = 1.0  # the wedge slides as one body: its contacts with the rest move
    new, n = refined(lp, body, v)
    assert n > int(body.max()) + 1
    assert np.all(new[body >= 0] >= 0)  # no moving block joins the ground
    sizes = np.bincount(new[new >= 0])
    assert sizes.max() < np.bincount(body[body >= 0]).max()  # the wedge lost its boundary blocks


def test_set13_reduced_state_is_exact_and_the_descent_only_checks_it() -> None:
    wall = SET13.to_micro()
    r = micro.solve_nonassociative(wall, tuning=REDUCE)
    (d,) = r.directions
    assert d.converged and d.sequence.reduced and d.sequence.stop_reason == "certified"
    assert d.sequence.fusion is not None and d.sequence.fusion.wall_certificate == "certified"
    (low,) = r.lowest
    assert (low.lps, low.stop, low.origin) == (0, "finished", "iterated")
    assert r.load_factor == r.iterated_load_factor == low.load_factor <= r.associative_load_factor
    assert low.band is not None and low.band[0] == low.load_factor <= low.band[1]
    residuals = verify_collapse_state(micro.assemble(wall), low.state)  # type: ignore[arg-type]
    assert max(v for k, v in residuals.items() if k != "slipping_points") < 1e-9
    # the wall's own chain and descent reach 0.4894591 (test_lowest); the reduced wall a state 2e-5 below
    assert r.load_factor == pytest.approx(0.4894487, abs=1e-7)
    rec = r.to_record()  # the record says which model the state came from, and the report's table names it
    assert rec.reduced and rec.fused_bodies == d.sequence.fusion.bodies > 0
    assert selection_cell(rec).endswith(f", reduced wall ({rec.fused_bodies:,} bodies)")


def test_a_fan_gives_no_reduced_state_and_the_chain_runs() -> None:
    wall = FAN.to_micro()
    lp = micro.assemble(wall)
    assert solve_reduced(lp, 1, resolve(wall.n_blocks, micro.NonAssociativeOptions(tuning=REDUCE))) is None


def test_a_lifted_state_is_kept_only_when_it_passes_the_descents_checks() -> None:
    """The certificate's field with a model's mechanism can miss the power balance (1.6e-6 on the error
    map's t = 1, 48-row wall): the search keeps a lifted state only where every residual of
    ``verify_collapse_state`` is within the descent's tolerance. Set 13's reduced state passes; the same
    field with its mechanism disturbed by 1e-4 of its largest rate does not."""
    from micro.nonassociative.reduced import _Search

    wall = SET13.to_micro()
    lp = micro.assemble(wall)
    resolved = resolve(wall.n_blocks, micro.NonAssociativeOptions(tuning=REDUCE))
    d = solve_reduced(lp, 1, resolved)
    assert d is not None and d.mechanism is not None and d.normal is not None and d.shear is not None
    v = np.asarray(d.mechanism.velocities, dtype=float).ravel()
    state = (d.normal / lp.force_scale, d.shear / lp.force_scale, d.load_factor)
    search = _Search(lp, 1, resolved)
    assert search.exact(v, state)
    noise = np.random.default_rng(0).standard_normal(v.size) * 1e-4 * float(np.max(np.abs(v)))
    assert not search.exact(v + noise, state)


def test_the_reduced_walls_start_is_retried_where_clarabel_fails(
        monkeypatch: pytest.MonkeyPatch, failing_solver: Callable[..., type]) -> None:
    """The reduced wall's associative LP goes through ``solve_interior``: where ``InteriorLP`` fails on it,
    HiGHS' interior point names the parts, and Set 13 still gets its reduced state (the same one: its parts
    are read at tolerances far above the two solvers' difference); with both failing the wall's own chain
    runs. Only the wall's own LP fails here: the certificate's restricted LPs are solved as always."""
    import micro.backends.roles as roles

    wall = SET13.to_micro()
    lp = micro.assemble(wall)
    resolved = resolve(wall.n_blocks, micro.NonAssociativeOptions(tuning=REDUCE))
    d = solve_reduced(lp, 1, resolved)
    assert d is not None
    real: Any = roles.InteriorLP
    real_retry: Any = roles.InteriorLPRetry
    failing = failing_solver(Status.INACCURATE)
    retried: list[object] = []

    def interior(model: object, *args: object, **kwargs: object) -> object:
        return (failing if model is lp else real)(model, *args, **kwargs)

    def retry(model: object, *args: object, **kwargs: object) -> object:
        retried.append(model)
        return real_retry(model, *args, **kwargs)

    monkeypatch.setattr(roles, "InteriorLP", interior)
    monkeypatch.setattr(roles, "InteriorLPRetry", retry)
    again = solve_reduced(lp, 1, resolved)
    assert retried and retried[0] is lp, "the reduced wall's start was not solved through solve_interior"
    assert again is not None, "the reduced wall gave up where HiGHS' interior point would have solved its start"
    assert again.load_factor == pytest.approx(d.load_factor, rel=1e-6)
    monkeypatch.setattr(roles, "InteriorLPRetry", failing)
    assert solve_reduced(lp, 1, resolved) is None
