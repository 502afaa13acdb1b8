"""The two LPs of a contact pattern on persistent HiGHS models: the least load factor, and a compatible mechanism.

A mechanism ``v`` fixes which generator columns of the associative LP
(generator form, :mod:`micro.lp`: ``n = g+ + g-``, ``s = mu (g+ - g-)``) an
exact non-associative collapse state may use: none at a point that opens, the
one on the far side of the cone at a point that slips (``s = -sign(slip) mu
n``), both at a point that sticks (:mod:`micro.nonassociative.certificate`).
The columns it forbids are its RESTRICTED columns. Two LPs work on a pattern:

* :class:`ForceLP`: the least (or greatest) ``lambda`` over the force fields
  that use no restricted column, the ends of the mechanism band. Beside the
  field it returns the reduced cost of every column: a restricted column with
  a negative reduced cost would lower ``lambda`` if a mechanism let it carry
  force.
* :class:`MechanismLP`: for a force field, a mechanism EXACTLY compatible with
  it (it opens only where ``n = 0``, slips only where the friction force sits
  at the yield line against the slip), with unit live-load work, chosen to
  restrict as little as possible of what lowers ``lambda`` (weights from the
  reduced costs). The field and this mechanism form an exact collapse state
  by construction (equilibrium, Coulomb, no interpenetration, no dilatancy,
  slip only at the yield line and against it); the energy balance follows by
  virtual work.

Both are HiGHS dual-simplex models changed by bounds and costs only, so that
successive patterns warm-start (:class:`~micro.backends.highs.PersistentHighsModel`,
:class:`PersistentRuns`); the first run of each is an interior point with crossover.

Unlike the certificate's classification, :func:`restricted_columns` leaves a
frictionless point (``mu = 0``, frictionless head joints) unrestricted when it
slips: its shear is zero whatever the slip.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.backends.base import Outcome, Status
from micro.backends.normal_matrix import NormalMatrix, NotPositiveDefinite
from micro.backends.roles import PersistentLP
from micro.lp import LimitLP
from micro.nonassociative.certificate import point_states
from micro.nonassociative.config import INTERPENETRATION, STATE_RESIDUAL, TINY

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
#: A basis as status codes of the columns and the rows
#: (:meth:`~micro.backends.highs.PersistentHighsModel.basis_arrays`).
Basis = tuple[NDArray[np.int8], NDArray[np.int8]]

#: A force (a generator, or ``n``) counts as zero below this fraction of the
#: largest normal force when the mechanism LP reads a field's pattern.
FORCE_ZERO = 1e-9
#: Newton steps of :func:`refine`, and the equilibrium residual (block
#: weights) at which it stops.
REFINE_STEPS = 3
REFINED = 1e-12
#: Simplex iterations per row a warm run may take before it is redone cold:
#: after a large change of the pattern a warm dual simplex can cost several
#: times a cold solve (the research page on the re-cut of the non-associative
#: package, ``docs/research/``, "Figures moved from the code").
WARM_ITERATIONS = 2
#: Callbacks beyond one per simplex iteration a primal run may make
#: (:meth:`~micro.backends.highs.PersistentHighsModel.limit_excess_calls`):
#: the runs that solve make few, those that fail many, slowly; the counts are
#: on the research page on the warm descent (``docs/research/``) and
#: the research page on the re-cut of the non-associative package (``docs/research/``).
PRIMAL_EXCESS_CALLS = 200
#: Simplex iterations per row a primal run from a carried-over basis may
#: take: above the runs that solve, below those that did not
#: (the research page on the re-cut of the non-associative package (``docs/research/``)).
PRIMAL_ITERATIONS = 0.5
#: Weight of every restricted column in the mechanism LP beside the
#: reduced-cost weights (normalised to at most 1): among compatible
#: mechanisms, prefer the one that restricts fewest columns.
SPARSITY_WEIGHT = 1e-3


def restricted_columns(lp: LimitLP, v: FloatArray) -> BoolArray | None:
    """The generator columns (``[g+ (P), g- (P)]``) the mechanism ``v`` forbids
    (rates read by :func:`~micro.nonassociative.certificate.point_states`, closing rates up to
    :data:`~micro.nonassociative.config.INTERPENETRATION` as noise).

    Returns:
        The ``(2P,)`` mask, or ``None`` when ``v`` makes points interpenetrate
        beyond :data:`~micro.nonassociative.config.INTERPENETRATION` or
        does no live-load work.
    """
    dn = lp.Bn.T @ v
    ds = lp.Bs.T @ v
    if not (dn.any() or ds.any()):
        return None
    states = point_states(dn, ds, INTERPENETRATION)
    if states is None:
        return None
    opening, slip_pos, slip_neg = states
    friction = lp.mu > 0.0  # s = -mu n at a slipping point: the generator on the slip's side carries nothing
    return np.concatenate([opening | (slip_pos & friction), opening | (slip_neg & friction)])


@dataclass(frozen=True, eq=False)
class ForceField:
    """An optimal force field of a pattern (scaled units).

    Attributes:
        g: ``(2P,)`` generator values ``[g+, g-]``.
        n, s: ``(P,)`` normal and shear forces.
        load_factor: its ``lambda``.
        benefit: ``(2P,)`` how fast ``lambda`` would fall per unit of force
            in each column (minus its reduced cost where negative, else 0).
        basis: the force LP's basis at this field (opaque,
            :meth:`~micro.backends.highs.PersistentHighsModel.get_basis`): a
            later LP of the same pattern starts from it.
    """

    g: FloatArray = field(repr=False)
    n: FloatArray = field(repr=False)
    s: FloatArray = field(repr=False)
    load_factor: float
    benefit: FloatArray = field(repr=False)
    basis: Any = field(default=None, repr=False)


def refine(lp: LimitLP, x: FloatArray) -> FloatArray:
    """A vertex of the generator LP with its equilibrium residual refined away.

    HiGHS's simplex meets its tolerances on the scaled model: on the
    1,230-block wall a vertex with forces up to 570 block weights missed
    equilibrium by 1.8e-5 block weights. Newton steps on the columns in the
    support (least squares: the normal equations ``A^T A dx = A^T r``,
    factorised once by CHOLMOD's simplicial code) bring it to ~1e-13 without
    changing the support; a step that would make a column negative, or does
    not lower the residual, is not taken. The factorisation calls no BLAS:
    the refined field, which the descent compares and reads patterns from,
    is the same under every BLAS kernel (SuperLU, used before, is not;
    the research page on the BLAS-independent descent (``docs/research/``)). Its vertices
    are square systems, on which both give the same step to ~1e-15.

    Args:
        lp: the wall's LP.
        x: the columns ``[g+, g-, d lambda]`` of a vertex.

    Returns:
        The refined columns (negative generators of the vertex clipped to 0).
    """
    x = x.copy()
    x[: 2 * lp.n_points] = np.maximum(x[: 2 * lp.n_points], 0.0)
    cols = np.flatnonzero(x > 0.0)
    cols = np.union1d(cols, [lp.lam_col])
    A = lp.A[:, cols].tocsc()
    normal: NormalMatrix | None = None
    r = lp.rhs - lp.A @ x
    res = float(np.max(np.abs(r), initial=0.0))
    for _ in range(REFINE_STEPS):
        if res <= REFINED:
            break
        if normal is None:
            try:
                normal = NormalMatrix(A.T, regularization=0.0, supernodal=False)
                normal.factor(np.ones(A.shape[0]))
            except NotPositiveDefinite:  # a singular support: the vertex is kept as it is
                break
        step = x.copy()
        step[cols] += normal.solve(A.T @ r)
        if np.any(step[: 2 * lp.n_points] < 0.0) or not np.all(np.isfinite(step)):
            break
        r_step = lp.rhs - lp.A @ step
        res_step = float(np.max(np.abs(r_step), initial=0.0))
        if not res_step < res:
            break
        x, r, res = step, r_step, res_step
    return x


class PersistentRuns:
    """Runs of a persistent simplex model: the first cold (:meth:`_cold`),
    the later ones warm from the last basis, capped at
    :data:`WARM_ITERATIONS` simplex iterations per row; a warm run that hits
    the cap, or neither solved nor proved infeasibility, is redone cold. The
    cap counts iterations, not seconds, so the same runs happen on every
    machine.

    Args:
        model: the model.
        time_limit: seconds per run (``inf``: none).
    """

    def __init__(self, model: PersistentLP, time_limit: float) -> None:
        self.model, self.time_limit = model, time_limit
        if model.stall_guard is None:
            model.guard_stalls()  # a stalled run fails (and is recovered) instead of hanging
        self.cap = WARM_ITERATIONS * model.n_rows
        self.cold = True
        self.lps = 0
        self.seconds = 0.0
        #: called with every run's outcome and algorithm (a progress display; ``None``: nobody)
        self.report: Callable[[Outcome, str], None] | None = None
        #: asked before every run whether it may run (a budget; ``None``: always)
        self.gate: Callable[[], bool] | None = None

    def run(self, start: Basis | None = None, *, primal: bool = False, cold: bool = True) -> Outcome:
        """Run the model (class docstring); a run its :attr:`gate` refuses fails
        at once (status ``ITERATION_LIMIT``, nothing solved).

        Args:
            start: a basis to start from (status codes of
                :meth:`~micro.backends.highs.PersistentHighsModel.basis_arrays`,
                e.g. carried over from the iterated LP's model); the run is then
                a primal simplex from it, capped at :data:`PRIMAL_ITERATIONS`
                per row.
            primal: a primal simplex from the current basis (which the caller
                set or knows to be primal feasible, or nearly) instead of the
                dual one; it runs warm even when the last run failed, since the
                caller vouches for the basis (a failed run leaves none).
            cold: redo a warm or primal run that fails cold; ``False``: return
                its failure (for an LP the caller can do without).
        """
        if self.gate is not None and not self.gate():
            return Outcome(Status.ITERATION_LIMIT, "budget spent")
        out = None
        if start is not None:
            self.model.set_basis_arrays(*start)
            primal = True
        if start is not None or primal or not self.cold:
            out = self._capped(primal)
            if out.status in (Status.OPTIMAL, Status.INFEASIBLE):
                return self._book(out, "simplex-primal" if primal else "simplex-warm")
            if not cold:
                self.model.clear_solver()  # nothing of a failed run is kept for the next one
                return self._book(out, "simplex-primal" if primal else "simplex-warm")
        first = self._cold()
        return self._book(first if out is None else first.plus_seconds(out.seconds), "ipm+crossover+simplex")

    def _capped(self, primal: bool = False) -> Outcome:
        """A warm simplex run, the dual one capped at :attr:`cap` iterations or
        the primal one at :data:`PRIMAL_ITERATIONS` per row."""
        m = self.model
        if primal:
            m.set_algorithm("simplex", primal=True)
            m.limit_excess_calls(PRIMAL_EXCESS_CALLS)
        m.limit_next_run(self.time_limit)
        m.limit_iterations(math.ceil(PRIMAL_ITERATIONS * m.n_rows) if primal else self.cap)
        out = m.run()
        m.limit_iterations(None)
        if primal:
            m.set_algorithm("simplex")
            m.limit_excess_calls(None)
        return out

    def _cold(self) -> Outcome:
        """Interior point + crossover, then a capped dual-simplex clean-up
        from the crossover basis. Unlike the iterated LP's
        :func:`~micro.nonassociative.model.restart`, an interior point that
        neither solves nor proves infeasibility (seen on patterns with no
        force field) is not followed by a cold dual simplex (minutes on
        1,230 blocks): the run fails."""
        m = self.model
        m.clear_solver()
        m.set_algorithm("ipm", crossover=True)
        m.limit_next_run(self.time_limit)
        first = m.run()
        m.set_algorithm("simplex")
        if first.status is not Status.OPTIMAL:
            return first
        return self._capped().plus_seconds(first.seconds)

    def _book(self, out: Outcome, algorithm: str) -> Outcome:
        if self.report is not None:
            self.report(out, algorithm)
        self.cold = out.status not in (Status.OPTIMAL, Status.INFEASIBLE)
        self.lps += 1
        self.seconds += out.seconds
        return out


class ForceLP(PersistentRuns):
    """Least or greatest ``lambda`` over the force fields of a pattern (module docstring).

    Args:
        lp: the wall's LP.
        direction: ``+1`` or ``-1``.
        time_limit: seconds per run (``inf``: none).
    """

    def __init__(self, lp: LimitLP, direction: int, time_limit: float = math.inf) -> None:
        super().__init__(PersistentLP.of(lp, direction, algorithm="simplex"), time_limit)
        self.lp, self.d = lp, direction
        self._cols = np.arange(2 * lp.n_points)
        self._gen = lp.A[:, : 2 * lp.n_points].tocsc()

    def solve(self, restricted: BoolArray, sense: float = 1.0, *, start: Basis | None = None,
              primal: bool = False, cold: bool = True) -> ForceField | None:
        """The field of least (``sense=+1``) or greatest (``-1``) ``lambda``
        that uses no restricted column; ``None`` when there is none (or the
        LP failed, or its field misses equilibrium by more than
        :data:`~micro.nonassociative.config.STATE_RESIDUAL`). ``start``,
        ``primal``, ``cold``: how it runs (:meth:`PersistentRuns.run`)."""
        lp, P = self.lp, self.lp.n_points
        upper = np.where(restricted, 0.0, lp.col_upper[: 2 * P])
        self.model.set_col_bounds(self._cols, np.zeros(2 * P), upper)
        self.model.set_cost(lp.lam_col, float(sense) * self.d)  # the column holds d * lambda
        out = self.run(start, primal=primal, cold=cold)
        if out.x is None or out.duals is None:
            return None
        x = refine(lp, out.x)
        g = x[: 2 * P]
        n, s = lp.forces(g)
        lam = float(x[lp.lam_col]) * self.d
        if lp.primal_residual(n, s, lam * self.d) > STATE_RESIDUAL:
            return None
        # HiGHS: cost = A^T y + z with y = -duals (shared sign); generators cost nothing
        # (the benefit is read at the lower end only)
        benefit = np.maximum(-(self._gen.T @ out.duals), 0.0) if sense > 0 else np.zeros(2 * P)
        return ForceField(g, n, s, lam, benefit, self.model.get_basis())


class MechanismLP(PersistentRuns):
    """A mechanism exactly compatible with a force field (module docstring).

    Columns ``[v (3 blocks), q+ (P), q- (P)]``; rows: the opening rates
    ``B_n^T v`` in ``[0, inf)`` (``[0, 0]`` where ``n > 0``), the slip rates
    ``B_s^T v - q+ + q- = 0`` (``q+`` fixed at 0 where ``g+ > 0``, ``q-``
    where ``g- > 0``, at points with friction), and the live-load work
    ``d f_L . v = 1``. Cost: the weighted opening and slip rates.

    Args:
        lp: the wall's LP.
        direction: ``+1`` or ``-1``.
        time_limit: seconds per run (``inf``: none).
    """

    def __init__(self, lp: LimitLP, direction: int, time_limit: float = math.inf) -> None:
        P, ne = lp.n_points, lp.n_eq
        eye = sp.identity(P, format="csc")
        zero = sp.csc_matrix((P, 2 * P))
        A = sp.vstack([
            sp.hstack([lp.Bn.T, zero]),
            sp.hstack([lp.Bs.T, -eye, eye]),
            sp.hstack([sp.csc_matrix(direction * lp.live.reshape(1, -1)), sp.csc_matrix((1, 2 * P))]),
        ], format="csc")
        lower = np.concatenate([np.full(ne, -np.inf), np.zeros(2 * P)])
        upper = np.full(ne + 2 * P, np.inf)
        row_lo = np.concatenate([np.zeros(2 * P), [1.0]])
        row_up = np.concatenate([np.full(P, np.inf), np.zeros(P), [1.0]])
        model = PersistentLP(A, np.zeros(ne + 2 * P), lower, upper, row_lo, row_up, algorithm="simplex")
        super().__init__(model, time_limit)
        self.lp, self.d = lp, direction
        self._q = ne + np.arange(2 * P)
        self._rows = np.arange(P)
        self._all = np.arange(ne + 2 * P)

    def compatible(self, f: ForceField) -> FloatArray | None:
        """Velocities (``3 n_blocks``, unit live-load work) of a mechanism
        exactly compatible with ``f``, restricting as few columns of positive
        benefit as it can; ``None`` when ``f`` admits no mechanism."""
        lp, P, ne = self.lp, self.lp.n_points, self.lp.n_eq
        zero = FORCE_ZERO * max(float(np.max(f.n, initial=0.0)), TINY)
        friction = lp.mu > 0.0
        carries = f.g > zero
        closed = f.n > zero
        self.model.set_row_bounds(self._rows, np.zeros(P), np.where(closed, 0.0, np.inf))
        q_up = np.where(carries & np.concatenate([friction, friction]), 0.0, np.inf)
        self.model.set_col_bounds(self._q, np.zeros(2 * P), q_up)
        top = float(np.max(f.benefit, initial=0.0))
        w = SPARSITY_WEIGHT + (f.benefit / top if top > 0 else np.zeros(2 * P))
        w_p, w_m = w[:P], w[P:]
        # an opening restricts both columns of a point, a slip the one it forbids
        cost = np.concatenate([lp.Bn @ (w_p + w_m), np.where(friction, w_p, 0.0), np.where(friction, w_m, 0.0)])
        self.model.set_costs(self._all, cost)
        out = self.run()
        if out.status is not Status.OPTIMAL or out.x is None:
            return None
        return np.asarray(out.x[:ne])
