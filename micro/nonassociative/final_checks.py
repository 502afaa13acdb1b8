"""Checks of a final state: residuals, the cold re-solve, and the independent collapse-state check."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from micro.exact import exact_dot
from micro.limit_result import DirectionResult, direction_sign
from micro.lp import LimitLP
from micro.mechanism import STATE_TOL, Mechanism, mechanism_from_duals
from micro.nonassociative.config import TINY
from micro.nonassociative.model import IterationModel, restart

FloatArray = NDArray[np.float64]

#: The stops after which the final iterate is re-solved cold (:func:`cold_check`): the exact
#: stops, whose state is the warm LP's own vertex. A certified state
#: (``"certified"``) is not the warm vertex's: the certificate's interior-point
#: LPs, which start from no basis, found it for the iterate's mechanism at its
#: ``lambda``, and it passes the collapse conditions whatever the warm run's
#: objective (and the re-solve cost 14-26 % of the iterated LP); a sequence
#: that did not converge returns no state.
COLD_CHECKED_STOPS = ("lambda_and_forces", "lambda_and_coulomb")

#: A point is in contact when its normal force exceeds this fraction of the
#: largest one (for the dilatancy residual).
CONTACT_FORCE = 1e-9


def cold_check_due(stop: str) -> bool:
    """Whether a sequence that stopped for ``stop`` re-solves its final iterate
    cold (:data:`COLD_CHECKED_STOPS`)."""
    return stop in COLD_CHECKED_STOPS


def coulomb_residual(lp: LimitLP, n: FloatArray, s: FloatArray) -> float:
    """``max(|s| - mu n, 0)`` relative to ``max n``."""
    scale = max(float(np.max(n, initial=0.0)), TINY)
    return float(np.max(np.abs(s) - lp.mu * n, initial=0.0)) / scale


@dataclass(frozen=True, eq=False)
class FinalState:
    """Residuals of a final state (scaled units).

    Attributes:
        mechanism: the mechanism of the duals.
        coulomb: :func:`coulomb_residual`.
        dilatancy: largest ``|opening rate|`` at points that slide while in
            contact, relative to the largest slip rate.
        equilibrium: largest equilibrium violation (block weights).
        sliding_points: points that slide while in contact.
    """

    mechanism: Mechanism
    coulomb: float
    dilatancy: float
    equilibrium: float
    sliding_points: int


def final_state(lp: LimitLP, d: int, v: FloatArray, n: FloatArray, s: FloatArray, lam: float) -> FinalState:
    """The residuals of forces ``(n, s)`` at ``lam`` with the mechanism of the duals ``v``."""
    eq = lp.Bn @ n + lp.Bs @ s + (lam * d) * lp.live - lp.rhs  # the LP column holds d * lambda
    mech = mechanism_from_duals(lp, v, d)
    dn_rate, ds_rate = mech.opening_rate, mech.slip_rate
    scale = max(float(np.max(np.abs(ds_rate), initial=0.0)), float(np.max(np.abs(dn_rate), initial=0.0)))
    nscale = max(float(np.max(n, initial=0.0)), TINY)
    sliding = (np.abs(ds_rate) > STATE_TOL * scale) & (n > CONTACT_FORCE * nscale)
    smax = max(float(np.max(np.abs(ds_rate), initial=0.0)), 1e-300)
    dil = float(np.max(np.abs(dn_rate[sliding]), initial=0.0)) / smax if sliding.any() else 0.0
    return FinalState(mech, coulomb_residual(lp, n, s), dil, float(np.max(np.abs(eq), initial=0.0)),
                      int(sliding.sum()))


@dataclass(frozen=True)
class ColdCheck:
    """The final iterate re-solved cold.

    Attributes:
        load_factor: its ``lambda`` (NaN if the cold solve failed).
        rel_diff: ``|warm - cold| / |cold|`` (NaN if it failed).
        algorithm: ``"ipm"``, ``"simplex"`` (IPX gave up) or
            ``"ipm+crossover+simplex"`` (IPX disagreed).
        native_status: the last cold solve's HiGHS status.
    """

    load_factor: float
    rel_diff: float
    algorithm: str
    native_status: str


def cold_check(model: IterationModel, lam: float, cold_tol: float) -> ColdCheck:
    """Re-solve the model's current LP from a fresh copy (no basis) and compare with ``lam``.

    HiGHS has open reports of wrong objectives after hot starts: the copy is
    solved by interior point; when IPX gives up (seen on scheme (b)'s
    near-degenerate rows) by a dual simplex without basis; when it disagrees
    by more than ``cold_tol`` (IPX without crossover stops at its own
    tolerances, seen: 1.6e-6 from the warm vertex on 7,575 blocks), a cold
    vertex (crossover + dual simplex from the IPX point) settles it.
    """
    cold_model = model.model.cold_copy("ipm")
    out, algorithm = cold_model.run(), "ipm"
    if not out.ok:
        cold_model = model.model.cold_copy("simplex")
        out, algorithm = cold_model.run(), "simplex"
    cold = rel = math.nan
    if out.x is not None:
        cold = model.load_factor(out.x)
        rel = abs(cold - lam) / max(abs(cold), TINY)
    if out.ok and rel > cold_tol and algorithm == "ipm":
        out, algorithm = restart(cold_model), "ipm+crossover+simplex"
        if out.x is not None:
            cold = model.load_factor(out.x)
            rel = abs(cold - lam) / max(abs(cold), TINY)
    return ColdCheck(cold, rel, algorithm, out.native_status)


def verify_collapse_state(lp: LimitLP, result: DirectionResult) -> dict[str, float]:
    """Check a direction's final state against the non-associative collapse
    conditions, independently of how it was found (scaled units).

    Args:
        lp: the LP of the wall (:func:`micro.assemble`).
        result: a direction with forces and a mechanism (of the iterated LP:
            checked at its last iterate's ``lambda``; of the associative LP:
            at its load factor).

    Returns:
        Residuals (0 when exact): ``equilibrium`` (block weights),
        ``coulomb`` (``max(|s| - mu n)`` / ``max n``), ``interpenetration``
        (``-min opening rate`` / largest rate), ``dilatancy``
        (``max |n * opening rate|`` / (``max n`` x largest rate)),
        ``slip_off_yield`` (``max ||s| - mu n|`` over slipping points /
        ``max n``), ``friction_direction`` (``max(s * slip rate)``, positive
        when friction would drive the slip, / (``max n`` x largest rate)),
        ``energy`` (``lambda * live work + dead work - dissipation``
        relative to ``lambda``) and ``slipping_points``.

    Raises:
        ValueError: the result has no forces or mechanism (it failed).
    """
    if result.normal is None or result.shear is None or result.mechanism is None:
        raise ValueError(f"direction {result.direction} has no final state ({result.status})")
    lam = result.sequence.last_load_factor if result.sequence is not None else result.load_factor
    mech = result.mechanism
    res = state_residuals(lp, direction_sign(result.direction), result.normal / lp.force_scale,
                          result.shear / lp.force_scale, lam, mech.opening_rate, mech.slip_rate,
                          mech.live_work, mech.dead_work, STATE_TOL)
    res.pop("live_work")
    return res


def state_residuals(lp: LimitLP, direction: int, n: FloatArray, s: FloatArray, lam: float, dn: FloatArray,
                    ds: FloatArray, live_work: float, dead_work: float, slip_tol: float) -> dict[str, float]:
    """Residuals of a state ``(n, s, lambda)`` with the relative velocities
    ``(dn, ds)`` of its mechanism against the non-associative collapse
    conditions (scaled units; the one computation behind
    :func:`verify_collapse_state` and
    :func:`micro.global_search.pattern.collapse_residuals`).

    Args:
        lp: the LP of the wall.
        direction: ``+1`` or ``-1``.
        n, s: point forces.
        lam: the load factor.
        dn, ds: opening and slip rates at the points.
        live_work, dead_work: the mechanism's work of the live load (per
            unit ``lambda``, in ``direction``) and of the dead load.
        slip_tol: a point slips when ``|ds|`` exceeds this fraction of the
            largest rate.

    Returns:
        The residuals of :func:`verify_collapse_state`, ``energy`` divided by
        ``live_work`` (normalised to unit live work; ``inf`` unless
        ``live_work > 0``), and ``live_work`` itself / the largest rate.
    """
    rate = max(float(np.max(np.abs(dn), initial=0.0)), float(np.max(np.abs(ds), initial=0.0)), 1e-300)
    nsc = max(float(np.max(n, initial=0.0)), 1e-300)
    slip = np.abs(ds) > slip_tol * rate
    eq = lp.Bn @ n + lp.Bs @ s + (lam * direction) * lp.live - lp.rhs
    balance = lam * live_work + dead_work + exact_dot(ds, s)  # work of the loads minus the dissipation
    return {
        "equilibrium": float(np.max(np.abs(eq), initial=0.0)),
        "coulomb": max(float(np.max(np.abs(s) - lp.mu * n, initial=0.0)), 0.0) / nsc,
        "interpenetration": max(-float(np.min(dn, initial=0.0)), 0.0) / rate,
        "dilatancy": float(np.max(np.abs(n * dn), initial=0.0)) / (nsc * rate),
        "slip_off_yield": float(np.max(np.abs(np.abs(s[slip]) - lp.mu[slip] * n[slip]), initial=0.0)) / nsc,
        "friction_direction": max(float(np.max(s[slip] * ds[slip], initial=0.0)), 0.0) / (nsc * rate),
        "energy": abs(balance) / live_work / max(abs(lam), TINY) if live_work > 0 else math.inf,
        "slipping_points": float(slip.sum()),
        "live_work": live_work / rate,
    }
