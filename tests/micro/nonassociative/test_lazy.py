"""The lazy selection: each iterate takes the optimal force field closest to ``nbar``."""

from __future__ import annotations

import numpy as np
import pytest

import micro
from comparison.wall import WallSpec
from micro.nonassociative import (
    NonAssociativeOptions,
    Tuning,
    recipe_for,
    solve_nonassociative,
    verify_collapse_state,
)
from micro.nonassociative.iteration import LPSequence
from micro.nonassociative.model import IterationModel, restart
from micro.nonassociative.tuning import LAZY_WEIGHT


def wall(t: float, m: float, rows: int = 12, f: float = 0.75) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=1).to_micro()


@pytest.mark.parametrize("t, m", [(1.0, 1 / 3), (1.0, 1.0)])  # Table 7, Sets 12 and 14
def test_lazy_sequences_end_in_exact_states(t: float, m: float) -> None:
    """A lazy sequence ends certified, in a state that passes every collapse
    condition, inside its mechanism band and below the associative load."""
    w = wall(t, m)
    r = solve_nonassociative(w, tuning=Tuning(selection="lazy"), lowest=False)
    assert r.converged, r.message
    lp = micro.assemble(w)
    for d in r.directions:
        assert d.sequence is not None and d.sequence.stop_reason == "certified"
        v = verify_collapse_state(lp, d)
        assert v["equilibrium"] <= 1e-9 and v["coulomb"] <= 1e-9 and v["interpenetration"] <= 1e-9
        assert v["dilatancy"] <= 1e-9 and v["slip_off_yield"] <= 1e-9 and v["energy"] <= 1e-9
        lo, hi = d.sequence.mechanism_band
        assert lo - 1e-7 <= d.load_factor <= hi + 1e-7
        assert d.load_factor <= d.sequence.associative_load_factor + 1e-9


def test_vertex_sequence_first_by_default() -> None:
    """The default runs Gilbert et al.'s vertex iteration first, which converges on Set 12 (its pinned value)."""
    assert Tuning().resolved_selection == "vertex+proximal"
    r = solve_nonassociative(wall(1.0, 1 / 3), lowest=False)
    assert r.sequence.selection == "vertex" and r.sequence.vertex_attempt is None
    assert r.load_factor == pytest.approx(0.708622, abs=2e-6)


def _models(w: micro.BlockWall) -> tuple[micro.LimitLP, IterationModel, IterationModel, np.ndarray]:
    lp = micro.assemble(w)
    vertex = IterationModel(lp, 1, "a", 0.3)
    lazy = IterationModel(lp, 1, "a", 0.3, lazy=True)
    # nbar: the forces of the first vertex iterate from the associative forces
    a = micro.solve_associative(w, solver="clarabel", directions="+x")
    assert a.normal is not None
    n0 = np.maximum(a.normal / lp.force_scale, 0.0)
    vertex.set_capacity(n0, 0.0, 0.0, 0.0)
    out = restart(vertex.model)
    nbar = np.maximum(vertex.forces(out.x)[0], 0.0) * 0.97 + 0.03 * n0
    return lp, vertex, lazy, nbar


def test_plain_lazy_model_is_gilberts_lp() -> None:
    """With the selection's cost off, the lazy model is Gilbert's LP at the same ``nbar``."""
    _, vertex, lazy, nbar = _models(wall(1.0, 1 / 2))
    vertex.set_capacity(nbar, 0.0, 0.0, 0.0)
    lazy.set_capacity(nbar, 0.0, 0.0, 0.0)
    lazy.set_lazy(False)
    a, b = restart(vertex.model), restart(lazy.model)
    assert vertex.load_factor(a.x) == pytest.approx(lazy.load_factor(b.x), rel=1e-9)


def test_lazy_lp_trades_lambda_for_closeness() -> None:
    """The lazy LP's optimum: its ``-lambda + w |n - nbar|_1`` is no more than
    the vertex's, it stays at least as close to ``nbar``, and its ``lambda``
    falls short of Gilbert's LP by at most ``w`` times the vertex's distance."""
    _, vertex, lazy, nbar = _models(wall(1.0, 1 / 2))
    vertex.set_capacity(nbar, 0.0, 0.0, 0.0)
    lazy.set_capacity(nbar, 0.0, 0.0, 0.0)
    a, b = restart(vertex.model), restart(lazy.model)
    lam_v, lam_l = vertex.load_factor(a.x), lazy.load_factor(b.x)
    dist_v = float(np.abs(vertex.forces(a.x)[0] - nbar).sum())
    dist_l = float(np.abs(lazy.forces(b.x)[0] - nbar).sum())
    assert dist_l <= dist_v + 1e-9 / LAZY_WEIGHT  # the two objectives agree to ~1e-9
    assert -lam_l + LAZY_WEIGHT * dist_l <= -lam_v + LAZY_WEIGHT * dist_v + 1e-9
    assert lam_v - LAZY_WEIGHT * dist_v - 1e-9 <= lam_l <= lam_v + 1e-9
    assert dist_l < 0.5 * dist_v  # the point of it (measured: 113 against 305 block weights, the same lambda)


def test_lazy_needs_scheme_a() -> None:
    with pytest.raises(ValueError, match="selection 'lazy' needs scheme 'a'"):
        Tuning(scheme="b", selection="lazy")
    with pytest.raises(ValueError, match="selection must be one of vertex, lazy"):
        Tuning(selection="closest")  # type: ignore[arg-type]


def test_vertex_then_lazy_retries_a_failed_direction() -> None:
    """``vertex+lazy``: Set 12's vertex sequence stopped at a cap of 4 LPs is
    run again lazily from its last normal forces, and certified within the
    cap; the result is that lazy sequence's, exact, with the vertex attempt
    and the LPs of both."""
    w = wall(1.0, 1 / 3)
    lp = micro.assemble(w)
    r = solve_nonassociative(w, tuning=Tuning(selection="vertex+lazy", retry_iterations=4), max_iterations=4,
                             lowest=False)
    vertex = solve_nonassociative(w, tuning=Tuning(selection="vertex"), max_iterations=4, lowest=False)
    assert vertex.status == "max_iterations" and vertex.governing.normal is not None
    lazy_options = recipe_for(w.n_blocks, NonAssociativeOptions(max_iterations=4, lowest=False),
                              Tuning(selection="lazy"))
    lazy = LPSequence(lp, 1, lazy_options, start=vertex.governing.normal / lp.force_scale).run()
    assert lazy.converged
    assert r.converged and r.load_factor == pytest.approx(lazy.load_factor, rel=1e-12)
    # not the lazy sequence from the associative forces (0.7117, measured), nearer the vertex one (0.7086)
    assert solve_nonassociative(w, tuning=Tuning(selection="lazy"), lowest=False).load_factor > r.load_factor + 1e-3
    q = r.sequence
    assert q.selection == "lazy" and q.vertex_attempt is not None
    assert q.vertex_attempt.stop_reason == "max_iterations" and q.vertex_attempt.selection == "vertex"
    assert r.iterations == vertex.iterations + lazy.iterations and len(r.history) == lazy.iterations + 1
    v = verify_collapse_state(lp, r.governing)
    assert max(v[k] for k in ("equilibrium", "coulomb", "interpenetration", "dilatancy", "slip_off_yield",
                              "energy")) <= 1e-9
    rec = r.to_record()
    assert rec.selection == "lazy" and rec.vertex_stop_reason == "max_iterations"
    assert rec.vertex_lambda_band == vertex.lambda_band
    assert type(rec).from_dict(rec.to_dict()) == rec


def test_vertex_then_lazy_keeps_a_converged_vertex_sequence() -> None:
    """Where the vertex sequence converges, ``vertex+lazy`` is the vertex result (no lazy run)."""
    w = wall(1.0, 1 / 3)
    r = solve_nonassociative(w, tuning=Tuning(selection="vertex+lazy"), lowest=False)
    assert r.converged and r.load_factor == pytest.approx(0.708622, abs=1e-6)
    assert r.sequence.selection == "vertex" and r.sequence.vertex_attempt is None
    rec = r.to_record()
    assert rec.selection == "vertex" and rec.vertex_stop_reason == "" and rec.vertex_lambda_band is None


def test_vertex_then_lazy_needs_scheme_a() -> None:
    with pytest.raises(ValueError, match="selection 'vertex\\+lazy' needs scheme 'a'"):
        Tuning(scheme="b", selection="vertex+lazy")
