"""Contact-state patterns: the two LPs of a fixed pattern, and the check of a state.

A PATTERN says, for every contact point, whether it may open, and for every
interface in which sense it may slip (``0``: it sticks; ``+1`` / ``-1``:
slip rate ``>= 0`` / ``<= 0``; the two points of a straight interface share
one slip rate). With the pattern fixed, the non-associative collapse
conditions are linear and split into two independent LPs:

* FORCES: equilibrium with ``n = 0`` at the points that may open and the
  friction force at the yield line, against the slip, at the points of an
  interface that may slip (``s = -mu n`` for slip ``+1``, i.e. the generator
  ``g+`` is 0; ``s = +mu n`` for ``-1``, ``g-`` is 0); Coulomb elsewhere.
  Its least (greatest) load factor is the lower (upper) end of the pattern's
  band of collapse load factors;
* MECHANISM: block velocities with zero opening rate at the points that may
  not open, non-negative at the others, and slip rates of the allowed sense.
  It exists when the largest live-load work with every rate in ``[-1, 1]``
  is positive.

Any force field of the first with any mechanism of the second is an exact
collapse state: complementarity holds because the forces vanish (or sit at
the yield line against the slip) wherever the pattern lets the mechanism
move. :func:`collapse_residuals` checks a state against the collapse
conditions from the forces and the mechanism alone, as
``micro.nonassociative.verify_collapse_state`` does for the iterated LP.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.global_search import highs as gh
from micro.global_search.global_types import Pattern
from micro.lp import LimitLP
from micro.nonassociative.final_checks import state_residuals

FloatArray = NDArray[np.float64]

#: Largest live-load work (rates in ``[-1, 1]``) below which a pattern has no
#: mechanism: the work of a genuine mechanism is of the order of the block
#: weights (1 in scaled units) times the rates.
LIVE_WORK_TOL = 1e-9
#: Largest residual (relative, see :func:`collapse_residuals`) of a state
#: accepted as an exact collapse state.
CHECK_TOL = 1e-7
#: Largest equilibrium residual (block weights) of an LP state.
EQUILIBRIUM_TOL = 1e-8


def force_state(lp: LimitLP, direction: int, pattern: Pattern,
                sense: float = 1.0) -> tuple[FloatArray, FloatArray, float] | None:
    """Least (``sense=+1``) or greatest (``-1``) load factor of the pattern's force fields.

    Returns:
        ``(n, s, lambda)`` (scaled), or ``None`` when no field exists (or the
        LP's state misses equilibrium by more than :data:`EQUILIBRIUM_TOL`).
    """
    P = lp.n_points
    mu_pos = lp.mu > 0.0
    slip_p = np.repeat(pattern.slip, 2)
    up_p = lp.col_upper[:P].copy()
    up_m = lp.col_upper[P : 2 * P].copy()
    up_p[pattern.opening | ((slip_p > 0) & mu_pos)] = 0.0
    up_m[pattern.opening | ((slip_p < 0) & mu_pos)] = 0.0
    A = lp.A.tocsc(copy=True)
    A[:, lp.lam_col] = A[:, lp.lam_col] * float(direction)
    cost = np.zeros(lp.n_cols)
    cost[lp.lam_col] = float(sense)
    upper = np.concatenate([up_p, up_m, [np.inf]])
    out = gh.run(gh.tight_lp(gh.build(cost, A, (lp.rhs, lp.rhs), (lp.col_lower, upper))))
    if not out.optimal or out.x is None:
        return None
    n, s = lp.forces(out.x)
    lam = float(out.x[lp.lam_col])
    if lp.primal_residual(n, s, lam * direction) > EQUILIBRIUM_TOL:
        return None
    return n, s, lam


def mechanism(lp: LimitLP, direction: int, pattern: Pattern) -> FloatArray | None:
    """A mechanism that follows ``pattern``, with unit live-load work.

    Maximises the live-load work over the block velocities whose rates obey
    the pattern and lie in ``[-1, 1]``.

    Returns:
        ``(3 n_blocks,)`` velocities normalised to unit live work, or ``None``
        when the largest work is at most :data:`LIVE_WORK_TOL`.
    """
    P = lp.n_points
    open_up = np.where(pattern.opening, 1.0, 0.0)
    slip_lo = np.where(pattern.slip < 0, -1.0, 0.0)
    slip_up = np.where(pattern.slip > 0, 1.0, 0.0)
    rows = sp.vstack([lp.Bn.T, lp.Bs.T.tocsr()[np.arange(0, P, 2)]]).tocsc()
    lower = np.concatenate([np.zeros(P), slip_lo])
    upper = np.concatenate([open_up, slip_up])
    nv = lp.n_eq
    h = gh.tight_lp(gh.build(-float(direction) * lp.live, rows, (lower, upper),
                             (np.full(nv, -np.inf), np.full(nv, np.inf))))
    out = gh.run(h)
    if not out.optimal or out.x is None or -out.objective <= LIVE_WORK_TOL:
        return None
    return out.x / -out.objective


def collapse_residuals(lp: LimitLP, direction: int, n: FloatArray, s: FloatArray, lam: float,
                       v: FloatArray) -> dict[str, float]:
    """Residuals of a state against the non-associative collapse conditions.

    Computed from the forces and the mechanism alone (scaled units), with
    ``rate`` the largest relative velocity and ``nmax`` the largest normal force.

    Returns:
        ``equilibrium`` (block weights), ``coulomb`` (``max(|s| - mu n)`` /
        ``nmax``), ``interpenetration`` (``-min opening rate`` / ``rate``),
        ``dilatancy`` (``max |n * opening rate|`` / (``nmax rate``)),
        ``slip_off_yield`` (``max ||s| - mu n|`` at slipping points /
        ``nmax``), ``friction_direction`` (``max(s * slip rate)`` /
        (``nmax rate``), positive when friction would drive the slip),
        ``energy`` (``|lambda W_L + W_D - dissipation|`` with the live work
        ``W_L`` normalised to 1, relative to ``lambda``), ``live_work`` (``W_L``
        before normalisation, / ``rate``: must be positive). One computation with
        :func:`micro.nonassociative.final_checks.state_residuals`.
    """
    res = state_residuals(lp, direction, n, s, lam, lp.Bn.T @ v, lp.Bs.T @ v, float(direction) * float(lp.live @ v),
                          float(lp.dead @ v), CHECK_TOL)
    res.pop("slipping_points")
    return res


def is_collapse_state(residuals: dict[str, float], tol: float = CHECK_TOL) -> bool:
    """True when every residual is within ``tol`` and the live work is positive."""
    worst = max(v for k, v in residuals.items() if k != "live_work")
    return bool(worst <= tol and residuals["live_work"] > LIVE_WORK_TOL)
