"""One load direction of the global search: bounds, model, branch and bound, checks.

The MIP's own solution is never reported as it stands: its binaries (the
contact pattern) are rounded and the state is rebuilt by the two LPs of the
pattern (:func:`micro.global_search.pattern.force_state` and
:func:`~micro.global_search.pattern.mechanism`), then checked by
:func:`~micro.global_search.pattern.collapse_residuals`. The rebuilt load factor is
the least of the pattern, so it is at most the MIP's (up to HiGHS'
feasibility tolerances on the big-M rows, which it removes).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from micro.global_search import highs as gh
from micro.global_search.big_m import BoundError, big_m
from micro.global_search.global_types import BigM, GlobalOptions, Pattern, default_node_limit
from micro.global_search.model import Layout, build_mip, pattern_of, solution_vector
from micro.global_search.pattern import collapse_residuals, force_state, is_collapse_state, mechanism
from micro.lp import LimitLP
from micro.mechanism import STATE_TOL, Mechanism, mechanism_from_duals

FloatArray = NDArray[np.float64]

#: HiGHS' absolute MIP gap: far below any relative gap asked for (load
#: factors are of order 0.1-1).
MIP_ABS_GAP = 1e-10
#: HiGHS' integrality and primal feasibility tolerances in the MIP (defaults
#: 1e-6 and 1e-7). With 1e-6 a binary at 1 - 1e-6 lets an "open" point carry
#: 1e-6 N_p, and HiGHS' optimum sat 4e-6 (relative) below the exact load
#: factor of its own pattern (5-block wall, lambda = 0.25).
MIP_FEASIBILITY = 1e-9
#: Relative slack between the rebuilt state's gap and the requested one
#: (the rebuilt load factor differs from HiGHS' by its tolerances).
GAP_SLACK = 1e-8
#: HiGHS' threads in the branch and bound. HiGHS sizes its thread pool by the machine's cores, and its
#: search takes another path with another count (a 3,000-node budget on a 10-block wall: 3,036 nodes
#: run on two cores, 3,000 on one): one thread, the same path on every machine.
MIP_THREADS = 1
#: HiGHS model statuses that mean "a limit stopped the search", with ours (HiGHS reports its node limit as
#: "Solution limit reached").
_LIMITS = {"Time limit reached": "time_limit", "Node limit reached": "node_limit",
           "Solution limit reached": "node_limit"}


@dataclass(frozen=True, eq=False)
class Incumbent:
    """An exact collapse state rebuilt from a contact pattern (scaled units).

    Attributes:
        pattern: the pattern.
        n, s: forces of the pattern's least load factor.
        load_factor: that load factor.
        v: a mechanism of the pattern with unit live-load work.
    """

    pattern: Pattern = field(repr=False)
    n: FloatArray = field(repr=False)
    s: FloatArray = field(repr=False)
    load_factor: float
    v: FloatArray = field(repr=False)

    @classmethod
    def from_pattern(cls, lp: LimitLP, direction: int, pattern: Pattern) -> Incumbent | None:
        """The least-``lambda`` state of ``pattern`` (``None`` if the pattern has none)."""
        forces = force_state(lp, direction, pattern)
        if forces is None:
            return None
        v = mechanism(lp, direction, pattern)
        if v is None:
            return None
        return cls(pattern, forces[0], forces[1], forces[2], v)

    @classmethod
    def from_state(cls, lp: LimitLP, direction: int, velocities: FloatArray) -> Incumbent | None:
        """The least-``lambda`` state of the pattern a known mechanism follows
        (rates below :data:`micro.mechanism.STATE_TOL` of the largest count as zero)."""
        v = np.asarray(velocities, dtype=float).ravel()
        dn, ds = lp.Bn.T @ v, lp.Bs.T @ v
        rate = max(float(np.max(np.abs(dn), initial=0.0)), float(np.max(np.abs(ds), initial=0.0)))
        if rate == 0.0:
            return None
        return cls.from_pattern(lp, direction, Pattern.from_rates(dn, ds, STATE_TOL * rate))

    def residuals(self, lp: LimitLP, direction: int) -> dict[str, float]:
        """Its check against the collapse conditions."""
        return collapse_residuals(lp, direction, self.n, self.s, self.load_factor, self.v)

    def mechanism(self, lp: LimitLP, direction: int) -> Mechanism:
        """Its mechanism with rates and contact states."""
        return mechanism_from_duals(lp, self.v, direction)


@dataclass(frozen=True, eq=False)
class SearchOutcome:
    """What :func:`search_direction` found (fields as in ``GlobalDirection``)."""

    status: str
    state: Incumbent | None = field(repr=False)
    lower_bound: float
    band: tuple[float, float] | None
    residuals: dict[str, float] = field(repr=False)
    bounds: BigM | None = field(repr=False)
    binaries: int = 0
    node_limit: int = 0
    nodes: int = 0
    mip_seconds: float = 0.0
    message: str = ""


def _configure(h: gh.Model, opts: GlobalOptions, node_limit: int) -> None:
    """HiGHS' options of the branch and bound: the gap, the tolerances, the seed, and the limits: the node
    budget always, a time limit only where the user gave one."""
    h.setOptionValue("output_flag", bool(opts.log))
    h.setOptionValue("mip_rel_gap", float(opts.mip_gap))
    h.setOptionValue("mip_abs_gap", MIP_ABS_GAP)
    h.setOptionValue("random_seed", int(opts.seed))
    h.setOptionValue("threads", MIP_THREADS)
    h.setOptionValue("mip_feasibility_tolerance", MIP_FEASIBILITY)
    h.setOptionValue("primal_feasibility_tolerance", MIP_FEASIBILITY)
    if opts.direction_time_limit is not None:
        h.setOptionValue("time_limit", float(opts.direction_time_limit))
    h.setOptionValue("mip_max_nodes", int(node_limit))


def _solve(h: gh.Model, lp: LimitLP, layout: Layout, inc: Incumbent | None, opts: GlobalOptions,
           node_limit: int) -> gh.MipOutcome:
    """The branch and bound by HiGHS, or by SCIP on the same model (``opts.solver``)."""
    start = None if inc is None else solution_vector(lp, layout, inc.pattern, inc.n, inc.s, inc.load_factor, inc.v)
    if opts.solver == "scip":
        from micro.global_search import scip

        m, xs = scip.from_model(h)
        if start is not None:
            scip.set_start(m, xs, start)
        return scip.run(m, xs, node_limit=node_limit, time_limit=opts.direction_time_limit, mip_gap=opts.mip_gap,
                               abs_gap=MIP_ABS_GAP, feasibility=MIP_FEASIBILITY, seed=opts.seed, log=opts.log)
    if start is not None:
        gh.set_start(h, start)
    return gh.run(h, mip=True)


def search_direction(lp: LimitLP, direction: int, opts: GlobalOptions, inc: Incumbent | None) -> SearchOutcome:
    """Bounds, model and branch and bound in one load direction.

    Args:
        lp: the LP of the wall.
        direction: ``+1`` or ``-1``.
        opts: the options.
        inc: a verified collapse state to start from, or ``None``.

    Returns:
        The :class:`SearchOutcome`.
    """
    try:
        bounds = big_m(lp, direction, lambda_upper=inc.load_factor if inc else math.inf, policy=opts.bounds)
    except BoundError as e:
        return SearchOutcome("solver_error", None, math.nan, None, {}, None, message=f"big-M bounds: {e}")
    h, layout = build_mip(lp, direction, bounds, energy_cut=opts.energy_cut)
    budget = opts.node_limit if opts.node_limit is not None else default_node_limit(layout.binaries)
    _configure(h, opts, budget)
    t0 = time.perf_counter()
    out = _solve(h, lp, layout, inc, opts, budget)
    secs = time.perf_counter() - t0
    found = Incumbent.from_pattern(lp, direction, pattern_of(layout, out.x)) if out.x is not None else None
    best = min((c for c in (found, inc) if c is not None), key=lambda c: c.load_factor, default=None)
    bound = out.dual_bound if math.isfinite(out.dual_bound) else bounds.lambda_lower
    common = dict(bounds=bounds, binaries=layout.binaries, node_limit=budget, nodes=out.nodes, mip_seconds=secs)
    if out.status == "Infeasible" and inc is None:
        return SearchOutcome("infeasible", None, math.inf, None, {}, **common,  # type: ignore[arg-type]
                             message=f"no collapse state with lambda in [{bounds.lambda_lower:.6g}, "
                                     f"{bounds.lambda_upper:.6g}] (the associative load factor)")
    status, msg = _status(out, best, found, bound, opts, budget)
    if best is None:
        return SearchOutcome(status, None, bound, None, {}, **common, message=msg)  # type: ignore[arg-type]
    res = best.residuals(lp, direction)
    if not is_collapse_state(res):
        worst = max((k for k in res if k != "live_work"), key=lambda k: res[k])
        return SearchOutcome("solver_error", None, bound, None, res, **common,  # type: ignore[arg-type]
                             message=f"the best state fails the collapse check ({worst} = {res[worst]:.2e})")
    top = force_state(lp, direction, best.pattern, sense=-1.0)
    band = (best.load_factor, top[2] if top is not None else math.nan)
    return SearchOutcome(status, best, min(bound, best.load_factor), band, res, **common,  # type: ignore[arg-type]
                         message=msg)


def _status(out: gh.MipOutcome, best: Incumbent | None, found: Incumbent | None, bound: float,
            opts: GlobalOptions, budget: int) -> tuple[str, str]:
    """Status and message from the solver's outcome and the rebuilt states."""
    if out.status in _LIMITS:
        status = _LIMITS[out.status]
        if status == "time_limit":
            return status, (f"stopped by the time limit given, {opts.direction_time_limit:g} s per direction, after "
                            f"{out.nodes} nodes: a wall-clock limit, so its bound and state depend on the machine")
        return status, (f"stopped at its budget of {budget:,} nodes ({out.nodes:,} run): the same on every "
                        "machine")
    if out.status != "Optimal":
        return "solver_error", f"HiGHS ended with status {out.status!r}"
    if found is None:
        return "solver_error", "the pattern of HiGHS' optimum admits no exact collapse state"
    assert best is not None
    gap = max(best.load_factor - bound, 0.0) / max(abs(best.load_factor), 1e-12)
    if gap > opts.mip_gap + GAP_SLACK:
        return "solver_error", (f"HiGHS' optimum rebuilt exactly gives lambda = {best.load_factor:.9g}, "
                                f"a gap of {gap:.2e} to its bound {bound:.9g}")
    return "optimal", ""
