"""The reduced wall: collapse states of a large wall found on models of its mechanism's rigid parts.

WHY. On a wall of square blocks the collapse mechanism is a wedge that rocks as one rigid body over a
crack, with a strip of single blocks along the crack moving on their own, and the rest of the wall at
rest (Set 10's: a wedge of about 900 of its 3,630 blocks). The iterated LP of the whole wall carries every
force of the wedge's inside and of the part at rest, and its warm dual simplex wanders through their
statically indeterminate fields: Set 10 cost 54 LPs and 8 to 15 minutes fused with the continuation. Its
mechanism needs a few hundred unknowns, not 11,000.

HOW. The associative mechanism (Clarabel's interior point, as the iterated LP's start) names the parts:
:func:`~micro.nonassociative.fusion.rigid_bodies` joins the blocks linked by contacts that move less than
``tol`` of the largest rate into bodies, the blocks joined to the ground into the ground, with no band of
single blocks (the coarsest model). The wall's own chain of sequences (vertex, then proximal) runs on the
LP of these bodies (:func:`~micro.nonassociative.fusion.fuse`), each LP a few milliseconds, and the
descent (:mod:`micro.nonassociative.descent.lowest`) runs on the same model from its state. Every
mechanism they reach is spread to the blocks and LIFTED: the least ``lambda`` of the wall's collapse states
with that mechanism, the certificate's lower band end
(:meth:`~micro.nonassociative.certificate.Certificate.state_lp`, Clarabel on the whole wall). A lifted
state is an exact collapse state of the wall, whatever the model that proposed its mechanism. Where no
mechanism of a model lifts, the blocks that touch a moving contact of its last mechanism are made single
bodies (:func:`refined`) and the model runs again, at most :data:`REFINE_ROUNDS` times. This is done for
each rigidity tolerance of :data:`REDUCE_TOLS`; the lowest lifted state is the direction's (the first one
below the options' ``stop_below``, where one is given: the search stops there).

WHERE. On walls of more than :data:`~micro.nonassociative.config.REDUCE_BLOCKS` blocks whose associative
mechanism has a dominant rigid part: its largest body holds at least :data:`DOMINANT_SHARE` of the moving blocks
(:func:`dominant_share`). Square-block walls have one (0.44-0.80 measured); walls of flatter blocks, whose
mechanism is a fan of single rocking blocks (Sets 2, 9 and 15-17), do not (0.10-0.29), and there no
mechanism of such a model lifts (measured): the wall's own chain runs. The measurements, per wall, are on
the research page on the reduced wall (``docs/research/``).

What comes out is a certified state of the wall, the lowest this search lifted: the descent afterwards
only checks it (``searched``). No decision reads the clock, and no step calls BLAS (Clarabel's QDLDL,
HiGHS, CHOLMOD's simplicial code in the descent's refinement): the same state on every machine.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from micro.backends.roles import ANY_FAILURE, solve_interior
from micro.limit_result import DIR_NAME, DirectionResult
from micro.lp import LimitLP
from micro.nonassociative import final_checks
from micro.nonassociative.certificate import Certificate, StateTriple
from micro.nonassociative.config import EQUILIBRIUM_RESIDUAL, LPProgress, Resolved
from micro.nonassociative.descent.lowest import is_exact, lowest_state
from micro.nonassociative.descent.states import restricted_columns
from micro.nonassociative.fusion import FusedLP, fuse, rigid_bodies
from micro.nonassociative.nonassociative_result import CONVERGED, SOLVER_FAILURE, FusionDiagnostics
from micro.nonassociative.pipeline import Solved, run_stages, solve_chain

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The rigidity tolerances tried, in order (a contact is rigid below this fraction of the largest rate of
#: the associative mechanism): each gives a model, and its states are lifted.
REDUCE_TOLS = (1e-3, 3e-4, 3e-3)
#: The reduced wall is tried where the associative mechanism's largest rigid body, at the first tolerance,
#: holds at least this share of its moving blocks.
DOMINANT_SHARE = 0.4
#: Rounds of refinement per tolerance (:func:`refined`), the first model included.
REFINE_ROUNDS = 3
#: Cap on the LPs of each sequence on a model (the vertex one, then the proximal one).
MODEL_LPS = 60
#: Cap on the LPs of the descent on a model.
MODEL_DESCENT_LPS = 100


def dominant_share(body: IntArray) -> float:
    """The largest body's share of the moving blocks (``body >= 0``; 0 when nothing moves)."""
    moving = body[body >= 0]
    return float(np.bincount(moving).max() / moving.size) if moving.size else 0.0


def refined(lp: LimitLP, body: IntArray, velocities: FloatArray) -> tuple[IntArray, int]:
    """``body`` with every block that touches a contact moving in ``velocities`` (a vertex's mechanism of the
    blocks: rates below :data:`~micro.mechanism.STATE_TOL` of the largest are zero) a body of its own."""
    from micro.mechanism import STATE_TOL

    w = lp.wall
    rate = np.maximum(np.abs(lp.Bn.T @ velocities), np.abs(lp.Bs.T @ velocities)).reshape(-1, 2).max(axis=1)
    moving = rate > STATE_TOL * max(float(rate.max(initial=0.0)), 1e-300)
    touch = np.zeros(w.n_blocks, dtype=bool)
    for side in (w.contact_a, w.contact_b):
        touch[side[moving & (side >= 0)]] = True
    new = body.copy()
    new[touch] = body.max(initial=-1) + 1 + np.arange(int(touch.sum()))
    # renumber the moving bodies 0, 1, ... in the order of their first block
    keep = new >= 0
    _, first, inverse = np.unique(new[keep], return_index=True, return_inverse=True)
    out = np.full(w.n_blocks, -1, dtype=np.int64)
    out[keep] = np.argsort(np.argsort(first))[inverse]
    return out, int(first.size)


@dataclass
class _Search:
    """The lowest lifted state so far and the work spent (the search's own state)."""

    lp: LimitLP
    d: int
    resolved: Resolved
    best: StateTriple | None = None
    best_v: FloatArray | None = None
    best_model: tuple[FusedLP, DirectionResult] | None = None
    model_lps: int = 0
    lifts: int = 0
    seconds: float = 0.0

    def lift(self, v: FloatArray, seen: set[bytes]) -> bool:
        """Lift the mechanism ``v`` (block velocities) onto the wall: the least ``lambda`` of the wall's collapse
        states with it; keep it when it is the lowest. A pattern lifted before is not lifted again.

        Returns:
            Whether ``v`` has a state on the wall that passes :meth:`exact`.
        """
        key = restricted_columns(self.lp, v)
        if key is None or key.tobytes() in seen:
            return False
        seen.add(key.tobytes())
        state, out = Certificate(self.lp, self.d, "a").state_lp(v, 1.0, self.resolved.options.user_limit)
        self.lifts += 1
        self.seconds += out.seconds
        kept = state is not None and self.exact(v, state)
        if kept and state is not None and (self.best is None or state[2] < self.best[2]):
            self.best, self.best_v = state, v
        # the lowest state of the wall so far (NaN before one): what the progress display shows after a lift
        self.resolved.tell(LPProgress(DIR_NAME[self.d], "reduced lift", self.lifts,
                                      math.nan if self.best is None else self.best[2], math.nan, "clarabel",
                                      float(out.seconds)))
        return kept

    def exact(self, v: FloatArray, state: StateTriple) -> bool:
        """Whether the lifted state passes the checks the descent keeps a state by
        (:func:`~micro.nonassociative.descent.lowest.is_exact`): the certificate's interior point gives
        the field, the model's simplex the mechanism, and on some walls their power balance is off by more
        than the check allows (1.6e-6 on the error map's t = 1, 48-row wall): such a state is not kept."""
        n, s, lam = state
        return is_exact(self.lp, self.d, lam, n, s, v)

    @property
    def on_target(self) -> bool:
        """A state below the options' ``stop_below`` was lifted: the search ends there."""
        return self.best is not None and self.resolved.options.below_target(self.best[2])

    def model(self, fused: FusedLP, seen: set[bytes]) -> tuple[bool, FloatArray | None]:
        """Run the chain and the descent on the model ``fused`` and lift their mechanisms.

        Returns:
            ``(whether one lifted, the last mechanism of the blocks or None)``.
        """
        t = self.resolved.tuning
        capped = dataclasses.replace(
            self.resolved, fuse=False, continuation=False, max_lps=MODEL_LPS,
            options=dataclasses.replace(self.resolved.options, lowest_budget=MODEL_DESCENT_LPS,
                                        tuning=dataclasses.replace(t, retry_iterations=MODEL_LPS)))
        r, model = run_stages(fused.lp, self.d, capped, fused_retry=False)
        self.model_lps += r.iterations
        mechanisms = [] if r.mechanism is None else [r.mechanism.velocities.ravel()]
        if r.converged:
            low = lowest_state(fused.lp, r, capped, model, proposals=model is not None)
            self.model_lps += low.lps
            if low.state is not None and low.state.mechanism is not None:
                mechanisms.append(low.state.mechanism.velocities.ravel())
        lifted = False
        for v in mechanisms[::-1]:  # the descent's first: the lowest of the model
            before = self.best
            if self.lift(fused.velocities(v), seen):
                lifted = True
                if self.best is not before:
                    self.best_model = (fused, r)
        return lifted, fused.velocities(mechanisms[-1]) if mechanisms else None


def solve_direction(lp: LimitLP, direction: int, resolved: Resolved) -> Solved:
    """One load direction: the reduced wall first where ``resolved.reduce`` asks for it (walls of more than
    :data:`~micro.nonassociative.config.REDUCE_BLOCKS` blocks), and where it gives no state (or is not asked
    for) :func:`~micro.nonassociative.pipeline.solve_chain`."""
    if resolved.reduce:
        reduced = solve_reduced(lp, direction, resolved)
        if reduced is not None:
            return reduced, None  # its models are of the bodies: no model of the wall for the descent
    return solve_chain(lp, direction, resolved)


def solve_reduced(lp: LimitLP, direction: int, resolved: Resolved) -> DirectionResult | None:
    """One load direction on the reduced wall (module docstring).

    Returns:
        The direction's certified state (the lowest lifted, at the lower end of its band on the wall; its
        ``sequence.fusion`` says how), or ``None`` where the associative mechanism has no dominant rigid
        part or no mechanism lifted: the wall's own chain runs instead.
    """
    t0 = time.perf_counter()
    assoc, _ = solve_interior(lp, direction, retry_on=ANY_FAILURE, time_limit=resolved.options.time_limit)
    if not assoc.ok or assoc.duals is None:
        return None
    v_assoc = np.asarray(assoc.duals[: lp.n_eq])
    first = rigid_bodies(lp, v_assoc, REDUCE_TOLS[0], single_band=False)
    if first[1] == 0 or dominant_share(first[0]) < DOMINANT_SHARE:
        return None
    search = _Search(lp, direction, resolved)
    seen: set[bytes] = set()
    for k, tol in enumerate(REDUCE_TOLS):
        body, n_bodies = first if k == 0 else rigid_bodies(lp, v_assoc, tol, single_band=False)
        for _ in range(REFINE_ROUNDS):
            if n_bodies == 0 or search.on_target:
                break
            lifted, last = search.model(fuse(lp, body, n_bodies), seen)
            if lifted or last is None:
                break
            body, n_bodies = refined(lp, body, last)
    if search.best is None or search.best_v is None or search.best_model is None:
        return None
    return _result(lp, direction, resolved, search, float(assoc.load_factor), time.perf_counter() - t0)


def _result(lp: LimitLP, d: int, resolved: Resolved, search: _Search, lam_assoc: float,
            seconds: float) -> DirectionResult:
    """The lowest lifted state as the direction's result: forces at all the wall's points, the mechanism of all
    its blocks, its band on the wall (one more LP, its upper end) and residuals."""
    assert search.best is not None and search.best_v is not None and search.best_model is not None
    n, s, lam = search.best
    v = search.best_v
    fused, r = search.best_model
    hi, _ = Certificate(lp, d, "a").state_lp(v, -1.0, resolved.options.user_limit)
    band = (lam, hi[2] if hi is not None else math.nan)
    state = final_checks.final_state(lp, d, v, n, s, lam)
    fusion = FusionDiagnostics(
        bodies=fused.n_bodies, single_bodies=fused.single_bodies, blocks_at_rest=fused.blocks_at_rest,
        points=fused.lp.n_points, wall_points=lp.n_points, rigid_tol=REDUCE_TOLS[0], seconds=seconds,
        wall_certificate="certified", certificate_seconds=search.seconds)
    assert r.sequence is not None
    ok = state.equilibrium <= EQUILIBRIUM_RESIDUAL
    seq = dataclasses.replace(
        r.sequence, stop_reason="certified" if ok else "equilibrium_residual", last_load_factor=lam,
        lambda_band=None, mechanism_band=band if ok else None, associative_load_factor=lam_assoc,
        coulomb_residual=state.coulomb, dilatancy_residual=state.dilatancy, equilibrium_residual=state.equilibrium,
        sliding_points=state.sliding_points, fusion=fusion, reduced=True)
    fs = lp.force_scale
    return DirectionResult(
        direction=DIR_NAME[d], status=CONVERGED if ok else SOLVER_FAILURE, load_factor=lam if ok else math.nan,
        iterations=search.model_lps + search.lifts + 1, seconds=seconds, normal=n * fs, shear=s * fs,
        mechanism=state.mechanism,
        message="" if ok else f"equilibrium residual {state.equilibrium:.2e} block weights on the wall",
        sequence=seq)


