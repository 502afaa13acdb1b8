"""The ``normal-ipm`` back end (:mod:`micro.backends.normal_ipm`): the suite's own
interior point on the normal equations, factorised by CHOLMOD.

It must agree with the pinned vertex references, return exactly admissible
forces and a mechanism in the shared convention, honour its settings, and
never return a number it did not converge to: a run that stops short is
solved again by ``clarabel`` and says so.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from micro_walls import three_storey_wall

import micro
from comparison.domain.wall import WallSpec
from micro.backends import Status, make_backend
from micro.backends import normal_ipm as nipm
from micro.backends.normal_matrix import NormalMatrix, NotPositiveDefinite, cholmod_options

REFERENCE = json.loads((Path(__file__).parents[1] / "associative_reference.json").read_text())["walls"]
#: The vertex references of the walls of up to 1,230 blocks (the larger ones
#: are the benchmarks'). Measured: within 8e-9 (the 1,230-block wall: 1.7e-8).
VERTEX = [k for k, v in REFERENCE.items() if v["method"] == "vertex" and v["blocks"] <= 1230]
REL = 1e-7


def _wall(entry: dict) -> micro.BlockWall:
    return WallSpec.from_paper(**entry["paper"]).to_micro(first_course=entry["first_course"],
                                                          head_joints=entry["head_joints"],
                                                          ends=entry.get("ends", "closers"))


@pytest.mark.parametrize("key", VERTEX)
def test_agrees_with_the_vertex_references(key: str) -> None:
    entry = REFERENCE[key]
    lp = micro.assemble(_wall(entry))
    backend = make_backend(lp, "normal-ipm")
    for direction, ref in entry["directions"].items():
        out = backend.solve(int(direction))
        assert out.ok and "fallback" not in out.info, out.info
        assert out.load_factor == pytest.approx(ref["load_factor"], rel=REL)
        assert out.info["primal_residual"] <= 1e-9  # the projection onto equilibrium
        assert out.load_factor == pytest.approx(out.info["kinematic_load_factor"], rel=1e-7)


def test_the_mechanism_is_in_the_shared_convention() -> None:
    """Live work +1, dead work -lambda, and an associative flow rule that holds
    up to the interior point's tolerance (``A_g^T u >= 0``)."""
    lp = micro.assemble(three_storey_wall())
    be = make_backend(lp, "normal-ipm")
    for d in (1, -1):
        out = be.solve(d)
        assert out.ok and out.duals is not None
        assert d * float(lp.live @ out.duals) == pytest.approx(1.0, abs=1e-12)
        assert float(lp.dead @ out.duals) == pytest.approx(-out.load_factor, rel=1e-7)
        opening = lp.A[:, : lp.lam_col].T @ out.duals
        assert float(np.min(opening[lp.active_generators()])) >= -1e-8 * float(np.max(np.abs(out.duals)))


def test_each_setting_does_what_it_says() -> None:
    """The stopping tolerances hold at the answer; Gondzio's correctors save iterations; the projection
    onto equilibrium lowers the primal residual by orders of magnitude; the iteration cap stops a run,
    which the back end then hands to ``clarabel`` and says so (three-storey wall, 96 blocks)."""
    lp = micro.assemble(three_storey_wall())
    A_g = nipm.NormalIpmBackend(lp).A_g

    def run(**changes: object) -> nipm.IpmResult:
        return nipm.NormalIpm(A_g, lp.live, lp.rhs, dataclasses.replace(nipm.NORMAL_IPM, **changes)).run(1)

    st, default = nipm.NORMAL_IPM, run()
    assert default.converged and default.gap <= st.gap_tol and default.primal <= st.primal_tol
    assert default.dual <= st.dual_tol
    assert run(correctors=0).iterations > default.iterations
    unprojected = run(projections=0)
    assert unprojected.converged and unprojected.primal > 100 * default.primal
    capped = run(max_iter=2)
    assert capped.reason == "iteration limit" and capped.iterations == 2
    out = nipm.NormalIpmBackend(lp, settings=dataclasses.replace(st, max_iter=2)).solve(1)
    assert out.ok and out.info["fallback"] == "normal-ipm: iteration limit after 2 iterations; solved by clarabel"
    assert out.load_factor == pytest.approx(default.lam, rel=1e-7)


@pytest.mark.parametrize(("field", "value"), [("gap_tol", 0.0), ("primal_tol", float("nan")), ("dual_tol", -1e-9),
                                              ("regularization", -1.0), ("step_fraction", 1.0), ("max_iter", 0),
                                              ("correctors", 1.5), ("projections", True)])
def test_bad_settings_name_the_field(field: str, value: object) -> None:
    with pytest.raises(ValueError, match=f"^{field} must be"):
        dataclasses.replace(nipm.NORMAL_IPM, **{field: value})


def test_counts_are_per_run() -> None:
    """One model serves both directions; each run reports its own factorisations."""
    lp = micro.assemble(three_storey_wall())
    be = nipm.NormalIpmBackend(lp)
    a, b = be.solve(1), be.solve(-1)
    assert a.ok and b.ok
    assert a.info["factorizations"] == a.ipm_iterations + 1 and b.info["factorizations"] == b.ipm_iterations + 1


def test_lambda_does_not_depend_on_the_blas_thread_count() -> None:
    """CHOLMOD's supernodal BLAS calls sum in a thread-dependent order; the back end
    holds BLAS to one thread, so the answer is bit for bit the same whatever the
    caller set (without it the 1,230-block wall differed in the last digit, the
    7,575-block wall by 8e-9)."""
    import cvxopt.cholmod  # noqa: F401 - cvxopt's BLAS loaded, so the limits reach it
    from threadpoolctl import threadpool_limits

    lp = micro.assemble(WallSpec.from_paper(**REFERENCE["w1230 full frictional"]["paper"]).to_micro())
    answers = []
    for threads in (1, 2):
        with threadpool_limits(limits=threads, user_api="blas"):
            answers.append(make_backend(lp, "normal-ipm").solve(1).load_factor)
    assert answers[0] == answers[1]


def test_the_factorisation_is_supernodal_and_leaves_cvxopt_options_alone() -> None:
    """CHOLMOD's supernodal factorisation is asked for explicitly (simplicial is
    2-7 times slower on walls); the global cvxopt options are restored."""
    from cvxopt import cholmod

    before = dict(cholmod.options)
    seen: list[int] = []
    real = cholmod.symbolic

    def spy(*args: object, **kw: object) -> object:
        seen.append(cholmod.options["supernodal"])
        return real(*args, **kw)

    lp = micro.assemble(three_storey_wall())
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cholmod, "symbolic", spy)
        NormalMatrix(lp.A[:, :10], regularization=1e-14)
    assert seen == [2] and dict(cholmod.options) == before
    with cholmod_options(supernodal=0):
        assert cholmod.options["supernodal"] == 0
    assert dict(cholmod.options) == before


def test_normal_matrix_matches_the_product_and_solves() -> None:
    lp = micro.assemble(three_storey_wall())
    A = lp.A[:, lp.active_generators()]
    rng = np.random.default_rng(1)
    d = 10.0 ** rng.uniform(-6, 6, A.shape[1])
    M = NormalMatrix(A, regularization=0.0)
    M.factor(d)
    dense = A.toarray() @ np.diag(d) @ A.T.toarray()
    rhs = rng.standard_normal((A.shape[0], 2))
    v = M.solve(rhs)
    assert np.allclose(dense @ v, rhs, rtol=0, atol=1e-8 * np.abs(rhs).max())
    assert M.nnz == np.count_nonzero(np.tril(np.abs(A.toarray()) @ np.abs(A.toarray()).T) + np.eye(A.shape[0]))


def test_a_run_that_stops_short_is_solved_by_clarabel_and_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    lp = micro.assemble(three_storey_wall())
    ref = make_backend(lp, "clarabel").solve(1)
    monkeypatch.setattr(nipm, "NORMAL_IPM", dataclasses.replace(nipm.NORMAL_IPM, max_iter=3))
    out = nipm.NormalIpmBackend(lp, settings=nipm.NORMAL_IPM).solve(1)
    assert out.ok and out.load_factor == ref.load_factor
    assert out.info["fallback"].startswith("normal-ipm: iteration limit after 3 iterations; solved by clarabel")


def test_forces_that_fail_the_re_check_fall_back(monkeypatch: pytest.MonkeyPatch) -> None:
    """Stopped early (tolerances 1e-2) and neither projected nor polished, the forces
    miss equilibrium: the answer is clarabel's, not a number that failed the check."""
    loose = dataclasses.replace(nipm.NORMAL_IPM, gap_tol=1e-2, primal_tol=1e-2, dual_tol=1e-2, projections=0)
    lp = micro.assemble(three_storey_wall())
    out = nipm.NormalIpmBackend(lp, settings=loose, polish=False).solve(1)
    assert out.ok and out.load_factor == make_backend(lp, "clarabel").solve(1).load_factor
    assert out.info["fallback"].startswith("normal-ipm: its forces failed the re-check (residual ")
    assert out.info["primal_residual"] <= 1e-6


def test_a_failed_factorisation_falls_back(monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(self: NormalMatrix, d: np.ndarray) -> None:
        raise NotPositiveDefinite("pivot 7")

    monkeypatch.setattr(NormalMatrix, "factor", broken)
    out = make_backend(micro.assemble(three_storey_wall()), "normal-ipm").solve(1)
    assert out.ok and "lost positive definiteness (pivot 7)" in out.info["fallback"]


def test_the_time_limit_is_a_status_not_a_number() -> None:
    out = make_backend(micro.assemble(three_storey_wall()), "normal-ipm", time_limit=1e-9).solve(1)
    assert out.status is Status.TIME_LIMIT and math.isnan(out.load_factor) and out.n is None
