"""The lowest certified collapse state: a descent from the iterated LP's fixed point.

With non-associative friction the collapse load is not unique: the final
mechanism of the iterated LP admits exact collapse states over a band of load
factors, and other mechanisms admit others. The descent looks for the lowest
exact state it can reach, and certifies every state it keeps.

Why these moves. For a statically admissible field ``(n, s)`` at ``lambda``
and a mechanism ``v`` (unit live-load work), virtual work gives
``lambda = lift(v) - n . dn(v) - s . ds(v) <= L(v, n) = lift(v) + sum mu n |ds(v)|``,
with equality exactly when ``(n, s, v)`` is a collapse state. The lowest
collapse load is therefore ``min lambda`` over admissible fields and
mechanisms with ``L(v, n) <= lambda``, a bilinear problem, and:

* with ``v`` fixed it is the LP of the band's LOWER END
  (:class:`~micro.nonassociative.descent.states.ForceLP`);
* with ``n`` fixed, ``min_v L(v, n)`` is the dual of Gilbert's LP
  ``|s| <= mu nbar`` with ``nbar = n``. At the lower end ``(n_lo, lambda_lo)``
  it returns ``lambda_lo`` itself: the lower end is a fixed point of the
  iterated LP, whose next LP cannot move it. Its optimal mechanisms are the
  mechanisms compatible with ``n_lo``.

Alternating the two is the convex-concave procedure on this problem. POLISH
(:meth:`Descent.polish`) does it with a choice: among the mechanisms
compatible with the current state it takes the one
(:class:`~micro.nonassociative.descent.states.MechanismLP`) that restricts least of
the columns whose reduced cost says they would lower ``lambda``. The next
lower end is never higher (the current state is one of its fields); polish
stops at a state that no compatible mechanism improves.

Such a stop is local. A PROPOSAL (:meth:`Descent.propose`) jumps to other
mechanisms: :data:`PROPOSAL_STEPS` relaxed steps of Gilbert's LP from the
current normal forces with the friction of the head joints released (their
shear capacity set to zero). The head joints carry shear that the mechanism
does not fix: they make the band wide, and with frictionless head joints it
shrinks to a point. Every distinct mechanism of the steps is polished into an
exact state; the lowest is accepted when it is strictly lower. The descent
stops when no proposal is (a relative decrease below :data:`LOWEST_TOL`
counts as none) or after :data:`LOWEST_MAX_MOVES` accepted proposal.
Releasing the bed joints, random halves of the head joints or the head joints
of one part of the wall (left, right, top, bottom, moving blocks) was tried on
the walls of ``xcheck stability`` and found lower states on 3 of 16 walls,
by 0.05 % at most but one (0.9 %), at three to four times the cost.

WARM LPs. Every LP starts from a basis, none from scratch but where a warm
one fails: the descent takes over the iterated LP's own model of the
direction after its last LP (:func:`lowest_state`'s ``model``), so that the
proposals' Gilbert steps are warm dual-simplex runs of it, and a force LP
starts from the basis of the Gilbert LP whose mechanism it asks about,
carried over to the generator columns
(:meth:`~micro.nonassociative.model.IterationModel.generator_basis`): its
vertex is near a field of the pattern, so a short primal simplex finishes
it. The polish's later rounds and the band's upper end start from the last
force LP's vertex, a field of their pattern. A proposal's force LP whose
warm run fails is not redone cold (its candidate is dropped); the lower end
of the iterated LP's state and the band are.

A FUSED WALL. Where the iterated LP ran on the fused wall (its model is the
bodies' LP, none is handed over), the descent takes the lower end of the
certified state's own mechanism band (and its polish) and makes no proposal:
on Set 10 (3,630 blocks) each Gilbert step on the unfused wall ran into the
warm cap and then cold, and each force LP into the primal cap, the reason the
wall is fused (measured on the warm descent's research page, ``docs/research/``).

THE BUDGET. A descent may solve at most ``lowest_budget`` LPs per direction
(:class:`~micro.nonassociative.config.NonAssociativeOptions`; then one more
for the band of the state it returns). It counts LPs, not seconds, so it
stops at the same state on every machine; one that spends its budget returns
the lowest certified state found so far with ``stop="budget"``
(``"finished"``: it ended by its own rules).

Every state the descent keeps is checked by
:func:`~micro.nonassociative.final_checks.verify_collapse_state` (every residual at
most :data:`EXACT_TOL`); a state that fails is discarded. The start, the
iterated LP's own converged state, is a candidate too, so the lowest state is
never above the iterated LP's load factor. No decision depends on time: the
same wall gives the same state on every machine.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.backends.base import Outcome
from micro.geometry import HEAD
from micro.limit_result import DIR_NAME, DirectionResult, direction_sign
from micro.lp import LimitLP
from micro.mechanism import mechanism_from_duals
from micro.nonassociative.config import INTERPENETRATION, LPProgress, Resolved
from micro.nonassociative.descent.lowest_direction import BUDGET, FAILED, FINISHED, FOUND, TARGET, LowestDirection
from micro.nonassociative.descent.states import (
    Basis,
    ForceField,
    ForceLP,
    MechanismLP,
    PersistentRuns,
    restricted_columns,
)
from micro.nonassociative.final_checks import verify_collapse_state
from micro.nonassociative.model import IterationModel

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: A relative decrease of ``lambda`` below this counts as no decrease.
LOWEST_TOL = 1e-6
#: Cap on accepted proposals (moves between mechanisms) per direction: on the
#: 178 walls of ``xcheck stability --lowest`` no descent ever accepted a
#: second one (the proposal after an accepted move found nothing lower on
#: every wall), and it cost as much as the first.
LOWEST_MAX_MOVES = 1
#: Cap on polish rounds (force LP + mechanism LP) per start.
POLISH_ROUNDS = 20
#: Relaxed Gilbert steps per proposal (``nbar = beta n_k + (1 - beta) n_(k-1)``);
#: on the walls of ``xcheck stability`` the accepted ones came from steps 1-6.
PROPOSAL_STEPS = 6
#: Contact kinds whose friction a proposal releases.
RELEASED_KINDS = (HEAD,)
#: Largest residual of :func:`verify_collapse_state` (every entry but the
#: slipping-point count and the closing rates, :meth:`Descent.exact`) of a
#: state the descent keeps.
EXACT_TOL = 1e-6
@dataclass(frozen=True, eq=False)
class CollapseState:
    """An exact collapse state of one direction (scaled units).

    Attributes:
        load_factor: its ``lambda``.
        n, s: normal and shear forces.
        v: block velocities (unit live-load work).
        origin: how it was found (``"iterated"``, ``"lower end"``,
            ``"release head joints, step 2"``, each ``", polish"`` when the
            polish lowered it).
        basis: the force LP's basis at its field (``None`` for the iterated
            LP's own state): the band's upper end starts from it.
    """

    load_factor: float
    n: FloatArray = field(repr=False)
    s: FloatArray = field(repr=False)
    v: FloatArray = field(repr=False)
    origin: str
    basis: Any = field(default=None, repr=False)


def exact_residuals(residuals: dict[str, float]) -> bool:
    """Whether the residuals of :func:`verify_collapse_state` are those of a state the descent keeps: every one
    at most :data:`EXACT_TOL`, but the closing rates, read as the simplex duals' noise up to
    :data:`~micro.nonassociative.config.INTERPENETRATION` of the largest rate."""
    return all(v <= (INTERPENETRATION if k == "interpenetration" else EXACT_TOL)
               for k, v in residuals.items() if k != "slipping_points")


def state_result(lp: LimitLP, direction: int, load_factor: float, n: FloatArray, s: FloatArray,
                 v: FloatArray) -> DirectionResult:
    """The state ``(n, s, lambda)`` (scaled units) with the mechanism ``v`` (velocities of the blocks) as a
    :class:`~micro.limit_result.DirectionResult` (dimensional forces, status ``found``)."""
    fs = lp.force_scale
    return DirectionResult(direction=DIR_NAME[direction], status=FOUND, load_factor=load_factor, iterations=0,
                           seconds=0.0, normal=n * fs, shear=s * fs,
                           mechanism=mechanism_from_duals(lp, v, direction))


def is_exact(lp: LimitLP, direction: int, load_factor: float, n: FloatArray, s: FloatArray,
             v: FloatArray) -> bool:
    """Whether the state passes the checks a state is kept by: :func:`verify_collapse_state`'s residuals read
    by :func:`exact_residuals`. The one test of the descent's states and of the reduced wall's lifted ones."""
    return exact_residuals(verify_collapse_state(lp, state_result(lp, direction, load_factor, n, s, v)))


class Descent:
    """The descent in one load direction (module docstring).

    Args:
        lp: the wall's LP.
        direction: ``+1`` or ``-1``.
        resolved: what the iterated LP ran with (the relaxation of the proposals' steps,
            ``time_limit`` per LP, the progress callback).
        budget: the most LPs the descent may solve (``None``: no limit).
        model: the iterated LP's own model of this direction after its last
            LP (scheme (a), on ``lp``), taken over with its basis: the
            proposals' Gilbert steps run warm in it, and its basis, carried
            over to the force LP, starts the first lower end. ``None``: a
            model of its own, solved cold once.
        proposals: whether the descent moves to other mechanisms (``False``:
            the lower end of the start's own mechanism band and its polish
            only).
        searched: the start is already the lowest state a search found, at
            the lower end of its band (the reduced wall's,
            :mod:`micro.nonassociative.reduced`): it is checked and returned
            with that band, and no LP runs.
    """

    def __init__(self, lp: LimitLP, direction: int, resolved: Resolved, budget: int | None = None,
                 model: IterationModel | None = None, *, proposals: bool = True, searched: bool = False) -> None:
        self.lp, self.d, self.resolved, self.budget, self.proposals = lp, direction, resolved, budget, proposals
        self.searched = searched
        self.known_band: tuple[float, float] | None = None
        self.forces = ForceLP(lp, direction, resolved.options.user_limit)
        self.mechanisms = MechanismLP(lp, direction, resolved.options.user_limit)
        self.forces.report = self.mechanisms.report = self._progress
        self.forces.gate = self.mechanisms.gate = self.may_run
        self.gilbert: tuple[IterationModel, PersistentRuns] | None = None
        if model is not None and model.lp is lp and model.scheme == "a":  # a basis generator_basis carries over
            self.gilbert = self._runs(model, warm=True)
        self.seen: set[bytes] = set()
        self.out_of_budget = False
        #: a state below the options' ``stop_below`` was found: no more LPs
        self.on_target = False

    def _runs(self, model: IterationModel, *, warm: bool) -> tuple[IterationModel, PersistentRuns]:
        """``model`` with the runner of the proposals' steps (warm: from its basis)."""
        runs = PersistentRuns(model.model, self.resolved.options.user_limit)
        runs.cold = not warm
        runs.report, runs.gate = self._progress, self.may_run
        return model, runs

    def may_run(self) -> bool:
        """Whether one more LP fits in the budget (the runners' gate: a refused
        LP fails, and the step that asked for it finds nothing); a refusal is
        remembered in :attr:`out_of_budget`. None runs once a state below the
        options' ``stop_below`` is found (:attr:`on_target`)."""
        if self.on_target:
            return False
        if self.budget is not None and self.lps >= self.budget:
            self.out_of_budget = True
            return False
        return True

    def spent(self) -> bool:
        """Whether the budget is spent (:meth:`may_run` refuses)."""
        return not self.may_run()

    def _progress(self, out: Outcome, algorithm: str) -> None:
        """Tell the caller's progress callback about one LP of the descent."""
        self.resolved.tell(LPProgress(DIR_NAME[self.d], "lowest", self.lps + 1, math.nan, math.nan, algorithm,
                               float(out.seconds)))

    @property
    def lps(self) -> int:
        """LPs solved so far."""
        return self.forces.lps + self.mechanisms.lps + (self.gilbert[1].lps if self.gilbert is not None else 0)

    # ------------------------------------------------------------ checks
    def as_result(self, state: CollapseState) -> DirectionResult:
        """``state`` as a :class:`~micro.limit_result.DirectionResult` (dimensional forces)."""
        return state_result(self.lp, self.d, state.load_factor, state.n, state.s, state.v)

    def exact(self, state: CollapseState) -> bool:
        """Every residual of :func:`verify_collapse_state` is at most :data:`EXACT_TOL`, but the closing
        rates, read as the simplex duals' noise up to
        :data:`~micro.nonassociative.config.INTERPENETRATION` of the largest rate as the certificate
        reads them (the iterated LP's certified state of Table 5's Set 3 closes at 1.6e-6)."""
        ok = is_exact(self.lp, self.d, state.load_factor, state.n, state.s, state.v)
        if ok and self.resolved.options.below_target(state.load_factor):
            self.on_target = True  # a certified state below the target: the search ends (``stop_below``)
        return ok

    # ------------------------------------------------------------ polish
    def settle(self, f: ForceField, v: FloatArray, origin: str) -> CollapseState | None:
        """The field ``f`` (the lower end of ``v``'s pattern) with a mechanism
        exactly compatible with it, or else with ``v`` itself; ``None``
        unless the state passes :meth:`exact`.

        On large walls the mechanisms of the LPs move by up to 1e-6 of their
        largest rate at points their pattern reads as closed; a field that
        loads such a point admits no exactly compatible mechanism, and the
        state with ``v`` is kept when its residuals are within
        :data:`EXACT_TOL`."""
        clean = self.mechanisms.compatible(f)
        for mech in (clean, v) if clean is not None else (v,):
            state = CollapseState(f.load_factor, f.n, f.s, mech, origin, f.basis)
            if self.exact(state):
                return state
        return None

    def lower_end(self, v: FloatArray, start: Basis | None = None, *, primal: bool = False,
                  cold: bool = True) -> ForceField | None:
        """The lower end of the band of ``v`` (``None`` if it has no state);
        ``start``, ``primal``, ``cold``: how its LP runs (:meth:`ForceLP.solve`)."""
        restricted = restricted_columns(self.lp, v)
        return None if restricted is None else self.forces.solve(restricted, start=start, primal=primal, cold=cold)

    def polish(self, v: FloatArray, origin: str, start: Basis | None = None, *, cold: bool = True
               ) -> CollapseState | None:
        """The lower end of ``v``'s band (its LP from ``start``, the basis of
        the Gilbert LP whose mechanism ``v`` is, carried over), then the
        convex-concave rounds (module docstring) until no compatible
        mechanism lowers it. A round's force LP starts from the last one's
        vertex, a field of the new pattern (the compatible mechanism keeps
        every column it carries), by the primal simplex. ``cold=False``: a
        force LP whose warm run fails is not redone cold (a proposal's
        candidate is dropped instead: on the 1,230-block wall such a run
        was a pattern with no field twice in three).

        Returns:
            The last exact state, or ``None`` when ``v`` gave none.
        """
        f = self.lower_end(v, start, cold=cold)
        state = self.settle(f, v, origin) if f is not None else None
        for _ in range(POLISH_ROUNDS):
            if state is None or state.v is v or self.spent():
                break  # no compatible mechanism: the same pattern again would give the same field
            v = state.v
            f = self.lower_end(v, primal=True, cold=cold)
            if f is None or f.load_factor >= state.load_factor * (1.0 - LOWEST_TOL):
                break
            better = self.settle(f, state.v, origin if origin.endswith("polish") else f"{origin}, polish")
            if better is None:
                break
            state = better
        return state

    # --------------------------------------------------------- proposals
    def released(self) -> BoolArray:
        """The points whose friction a proposal releases (:data:`RELEASED_KINDS`)."""
        return np.isin(self.lp.point_kinds(), RELEASED_KINDS) & (self.lp.mu > 0.0)

    def gilbert_model(self, n: FloatArray) -> tuple[IterationModel, PersistentRuns]:
        """The model of the proposals' Gilbert steps: the iterated LP's own
        (taken over in the constructor), else one of the descent's own,
        solved once cold at ``nbar = n`` so that it holds a basis."""
        if self.gilbert is None:
            self.gilbert = self._runs(IterationModel(self.lp, self.d, "a", 0.0), warm=False)
            self.gilbert[0].set_capacity(n, 0.0, 0.0, 0.0)
            self.gilbert[1].run()
        return self.gilbert

    def propose(self, state: CollapseState, released: BoolArray) -> CollapseState | None:
        """Relaxed Gilbert steps from ``state``'s normal forces with the
        friction of the ``released`` points set to zero (warm dual simplex
        runs of one model); the lowest polished exact state of the steps'
        distinct mechanisms, each lower end started from its step's basis
        (``None`` if none)."""
        model, runs = self.gilbert_model(state.n)
        beta = self.resolved.tuning.beta
        n_prev = n_prev2 = state.n
        best: CollapseState | None = None
        for k in range(PROPOSAL_STEPS):
            if self.spent():
                break
            nbar = beta * n_prev + (1.0 - beta) * n_prev2 if k else state.n
            model.set_capacity(np.where(released, 0.0, nbar), 0.0, 0.0, 0.0)
            out = runs.run()
            if out.x is None or out.duals is None:
                break
            n_prev2, n_prev = n_prev, model.forces(out.x)[0]
            v = out.duals[: self.lp.n_eq]
            restricted = restricted_columns(self.lp, v)
            if restricted is None or restricted.tobytes() in self.seen:
                continue
            self.seen.add(restricted.tobytes())
            cand = self.polish(v, f"release head joints, step {k + 1}", model.generator_basis(), cold=False)
            if cand is not None and (best is None or cand.load_factor < best.load_factor):
                best = cand
        return best

    # -------------------------------------------------------------- run
    def run(self, start: DirectionResult) -> LowestDirection:
        """Descend from the converged direction ``start`` of the iterated LP."""
        t0 = time.perf_counter()
        assert start.normal is not None and start.shear is not None and start.mechanism is not None
        fs = self.lp.force_scale
        v0 = np.asarray(start.mechanism.velocities, dtype=float).ravel()
        lam0 = start.sequence.last_load_factor if start.sequence is not None else start.load_factor
        it = CollapseState(lam0, start.normal / fs, start.shear / fs, v0, "iterated")
        best = it if self.exact(it) else None
        path = [] if best is None else [best.load_factor]
        if self.searched:  # its band is the start's own (no LP)
            self.known_band = start.sequence.mechanism_band if start.sequence is not None else None
            return self._finish(best, tuple(path), (), t0)
        start_basis = self.gilbert_model(it.n)[0].generator_basis() if self.proposals else None
        lower = self.polish(v0, "lower end", start_basis)
        if lower is not None and (best is None or lower.load_factor < best.load_factor * (1.0 - LOWEST_TOL)):
            best = lower
            path.append(best.load_factor)
        moves: list[str] = []
        released = self.released() if self.proposals else np.zeros(0, dtype=bool)
        while best is not None and released.any() and len(moves) < LOWEST_MAX_MOVES and not self.spent():
            new = self.propose(best, released)
            if new is None or new.load_factor >= best.load_factor * (1.0 - LOWEST_TOL):
                break
            best = new
            moves.append(new.origin)
            path.append(new.load_factor)
        return self._finish(best, tuple(path), tuple(moves), t0)

    def _band(self, best: CollapseState) -> tuple[float, float]:
        """The band of ``best``'s mechanism: its upper end one LP beyond the budget."""
        restricted = restricted_columns(self.lp, best.v)
        self.budget = None
        top = None
        if restricted is not None:
            if best.basis is not None:  # its lower end's vertex is a field of the pattern: the primal simplex
                self.forces.model.set_basis(best.basis)
            top = self.forces.solve(restricted, sense=-1.0, primal=best.basis is not None)
        return best.load_factor, top.load_factor if top is not None else math.nan

    def _finish(self, best: CollapseState | None, path: tuple[float, ...], moves: tuple[str, ...],
                t0: float) -> LowestDirection:
        """The band of the lowest state's mechanism and the result."""
        name = DIR_NAME[self.d]
        budget = -1 if self.budget is None else self.budget
        stop = TARGET if self.on_target else BUDGET if self.out_of_budget else FINISHED
        if best is None:
            return LowestDirection(name, FAILED, math.nan, None, path, moves, self.lps, budget, stop,
                                   time.perf_counter() - t0, None, {},
                                   message="no collapse state passed the check, the iterated LP's included")
        band = (best.load_factor, self.known_band[1]) if self.known_band is not None else self._band(best)
        result = self.as_result(best)
        return LowestDirection(name, FOUND, best.load_factor, band, path, moves, self.lps, budget, stop,
                               time.perf_counter() - t0, result, verify_collapse_state(self.lp, result),
                               origin=best.origin)


def lowest_state(lp: LimitLP, start: DirectionResult, resolved: Resolved,
                 model: IterationModel | None = None, *, proposals: bool = True,
                 searched: bool = False) -> LowestDirection:
    """The lowest certified state reached from a converged direction of the iterated LP.

    Args:
        lp: the wall's LP.
        start: a converged direction (its final forces and mechanism).
        resolved: what the iterated LP ran with (its options' ``lowest_budget``).
        model: the iterated LP's model of the direction after its last LP,
            taken over (:class:`Descent`); ``None``: the descent builds one.
        proposals: whether the descent moves to other mechanisms (:class:`Descent`).
        searched: the start is already the lowest state a search found (:class:`Descent`).

    Returns:
        The :class:`LowestDirection`.

    Raises:
        ValueError: ``start`` has no final state.
    """
    if start.normal is None or start.shear is None or start.mechanism is None:
        raise ValueError(f"direction {start.direction} has no final state ({start.status})")
    return Descent(lp, direction_sign(start.direction), resolved, resolved.options.lowest_budget, model,
                   proposals=proposals, searched=searched).run(start)
