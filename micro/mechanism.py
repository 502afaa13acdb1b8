"""Collapse mechanism from the duals of the equilibrium rows.

By LP duality the multipliers of the equilibrium rows are generalised block
velocities ``(u, v, omega)`` (``omega`` counter-clockwise, about the block
centroid). ``B_n^T v`` and ``B_s^T v`` are then the normal (opening > 0) and
tangential relative velocities of block ``b`` with respect to block ``a`` at
every contact point. Velocities are given in the LP's scaled units (lengths in
block heights, forces in reference block weights) and normalised so that the
live load does unit work; the dead load then does work ``-lambda`` and, with
associative friction, the dissipation is zero (virtual work balances).

Interior-point back ends (``normal-ipm``, ``highs-ipm`` without crossover, ``clarabel``,
``cvxpy``) return a maximally complementary dual: when several collapse
mechanisms share the optimal load factor it is a blend of them, with many
contacts moving slightly. ``highs-simplex`` returns a vertex (one mechanism).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from micro.exact import exact_dot
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Contact states (values of :attr:`Mechanism.contact_state`).
CLOSED, OPENING, SLIDING = 0, 1, 2
CONTACT_STATE_NAMES = ("closed", "opening", "sliding")

#: A relative velocity counts as non-zero above this fraction of the largest one, in the decisions of
#: the iterated LP (its certificate and states, on the rates of a vertex).
STATE_TOL = 1e-6
#: A contact is classified opening or sliding (:attr:`Mechanism.contact_state`, and the counts every
#: record reports) when its opening or slip rate exceeds this fraction of the largest rate: ten times
#: the accuracy of an interior point's duals, about the square root of its duality-gap tolerance
#: (``normal-ipm``: 1e-8, so 1e-4 of the largest rate). The associative mechanism is an interior
#: point's blend of every optimal mechanism, its rates spread over every decade from 1e-10 to 1, and
#: those below 1e-4 are the solver's noise: between three OpenBLAS kernels the rates of Table 9's
#: Set 17 (7,575 blocks) differed by up to 2.5e-5 of the largest, and with :data:`STATE_TOL` its count
#: of sliding contacts was 10,761, 10,740 and 10,707; at this tolerance it is 7,225 on all three (and
#: Sets 15, 16 and Ref the same on all three). A vertex's rates (the iterated LP's) are clean, and
#: slower contacts than this fraction are counted closed there too.
CONTACT_STATE_TOL = 1e-3


@dataclass(frozen=True, eq=False)
class Mechanism:
    """A collapse mechanism.

    Attributes:
        velocities: ``(n_blocks, 3)`` block velocities ``(u, v, omega)``.
        opening_rate: ``(n_points,)`` normal relative velocity (opening > 0).
        slip_rate: ``(n_points,)`` tangential relative velocity.
        contact_state: ``(n_contacts,)`` :data:`CLOSED`, :data:`OPENING`
            (separation or rocking about one end, no slip) or :data:`SLIDING`,
            rates below :data:`CONTACT_STATE_TOL` of the largest counting as zero.
        live_work: work of the live load (``1`` after normalisation).
        dead_work: work of the dead load (``-lambda`` at collapse).
    """

    velocities: FloatArray = field(repr=False)
    opening_rate: FloatArray = field(repr=False)
    slip_rate: FloatArray = field(repr=False)
    contact_state: IntArray = field(repr=False)
    live_work: float
    dead_work: float

    def virtual_work_residual(self, load_factor: float) -> float:
        """``lambda * live_work + dead_work`` (zero for associative friction)."""
        return float(load_factor * self.live_work + self.dead_work)

    def state_counts(self) -> dict[str, int]:
        """Number of contacts in each state."""
        c = np.bincount(self.contact_state, minlength=3)
        return {name: int(c[i]) for i, name in enumerate(CONTACT_STATE_NAMES)}


def mechanism_from_duals(
    lp: LimitLP, velocities: FloatArray, direction: int, *, state_tol: float = CONTACT_STATE_TOL
) -> Mechanism:
    """Normalise the dual velocities and classify every contact.

    Args:
        lp: the LP the duals belong to.
        velocities: duals of the equilibrium rows in the shared convention
            (:class:`micro.Outcome`), length ``3 * n_blocks``.
        direction: ``+1`` or ``-1``, the live load direction solved.
        state_tol: a relative velocity counts as non-zero above this fraction
            of the largest one.

    Returns:
        The :class:`Mechanism` with the live load doing unit work.
    """
    y = np.asarray(velocities, dtype=float)
    live_work = float(direction) * exact_dot(lp.live, y)  # the same on every BLAS kernel: it scales y
    if live_work != 0.0 and np.isfinite(live_work):
        y = y / live_work
    dn = lp.Bn.T @ y
    ds = lp.Bs.T @ y
    scale = max(float(np.max(np.abs(dn), initial=0.0)), float(np.max(np.abs(ds), initial=0.0)))
    tol = state_tol * scale if scale > 0 else 0.0
    state = classify_rates(np.abs(dn).reshape(-1, 2).max(axis=1), np.abs(ds).reshape(-1, 2).max(axis=1), tol)
    return Mechanism(
        velocities=y.reshape(-1, 3),
        opening_rate=dn,
        slip_rate=ds,
        contact_state=state,
        live_work=float(direction) * exact_dot(lp.live, y),
        dead_work=exact_dot(lp.dead, y),
    )


def classify_rates(opening: FloatArray, slip: FloatArray, tol: float) -> IntArray:
    """:data:`SLIDING` where ``|slip| > tol``, else :data:`OPENING` where ``|opening| > tol``, else
    :data:`CLOSED` (of contacts, from their points' largest rates, or of single points)."""
    state = np.full(np.shape(opening), CLOSED, dtype=np.int64)
    state[np.abs(opening) > tol] = OPENING
    state[np.abs(slip) > tol] = SLIDING
    return state
