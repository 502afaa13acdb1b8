"""The mechanical conditions of a collapse state, each residual relative to the body or point it is at.

Notation (:class:`~micro.state.data.CollapseStateData`): at point ``p`` the normal force ``n``, the
shear force ``s``, the friction coefficient ``mu``, the opening rate ``dn`` and slip rate ``ds``; per
body the dead load ``D``, the live load ``L`` (as applied) and the velocity ``y``; the load factor
``lambda``. ``B_n``, ``B_s`` are the equilibrium columns of the state's contact geometry
(:func:`micro.lp.point_columns`).

THE CONDITIONS. Equilibrium ``B_n n + B_s s + D + lambda L = 0``; compatibility ``dn = B_n^T y``,
``ds = B_s^T y``; and at every point, with the flow rule's dilatancy ``delta = 0`` (non-associative,
zero dilatancy) or ``delta = mu |ds|`` (associative: normality to the Coulomb cone)::

    n >= 0                       no tension
    |s| <= mu n                  Coulomb
    dn >= delta                  no interpenetration (associative: at least the dilatancy)
    dn = delta where n > 0       no dilatancy where sliding (associative: exactly mu |ds|)
    n (dn - delta) = 0           opening only where the normal force is zero
    s ds = -mu n |ds|            where a point slips, friction at the yield line against the slip

THE POWER BALANCE. Virtual work with equilibrium gives, for the state's own velocities,
``lambda L.y + D.y = -sum(n dn + s ds)``. With the conditions above the right-hand side is the
dissipation of the friction law, ``sum mu n |ds| - sum n delta``: ``sum mu n |ds|`` for zero
dilatancy and ``0`` for the associative law. So the work of the loads must equal that dissipation; it
is checked for each group of bodies that touch one another (below). The mechanism must be one: the live
load does positive work, a share of the sum of its bodies' absolute works (a state at rest satisfies
every other condition).

SCALES, BODY BY BODY. A residual is relative to the body or the point it is at, never to the largest
number in the file (one heavy block far away, or one vertex at 1e9, would otherwise set a scale under
which the rest of the wall goes unchecked): a body's forces over its own load ``F_i`` (the largest of its
weight, its dead load and lambda times its live load), its moments over ``F_i l_i`` (``l_i`` the diagonal
of its outline's bounding box); a point's forces over ``F_p``, the larger of its two bodies' ``F_i``
(its products of a force and a rate over ``max(n, F_p) R``: a point's own force).
Rates are relative to ``R``, the largest rate within the point's group of touching bodies (the bodies
joined through contact points other than the ground's): velocities are defined up to a factor, and a
group at rest beside a moving one is only a mechanism up to the solvers' noise (an interior point's
"resting" blocks move at 1e-10 of the fastest), so that a rate cannot be relative to its own body's
speed; a body far away that touches nothing of the wall is a group of its own. The power balance of a
group is relative to the largest of its three terms. A point slips when ``|ds| > SLIPPING * R``, and is
pressed when ``n > PRESSED`` times the largest force of its group (a body's load or a normal force: a
classification, not a residual): an interior point's mechanism misses
the flow rule at a sliding point by its complementarity gap over ``n``, which only a point carrying a
share of its group's loads keeps small (``opening`` checks every point, weighted by its force).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components

from micro.mechanism import CONTACT_STATE_TOL
from micro.state.data import CollapseStateData
from micro.state.outlines import sizes

FloatArray = NDArray[np.float64]

#: A point is pressed when its normal force exceeds this share of the largest force of its group (for
#: ``dilatancy``; ``opening`` weighs every point by its normal force).
PRESSED = 1e-4
#: A point slips when its slip rate exceeds this share of ``R``.
SLIPPING = 1e-6
#: A point's declared state agrees with its rates when it is their classification
#: (:func:`micro.mechanism.classify_rates`) at some threshold in this band (times the largest rate of the
#: state, as the writer classifies) around :data:`~micro.mechanism.CONTACT_STATE_TOL`.
STATE_BAND = (CONTACT_STATE_TOL / 10.0, CONTACT_STATE_TOL * 10.0)
#: Floor of the rate and power scales (a group at rest).
TINY = 1e-300


def _worst(values: FloatArray, label: str) -> tuple[float, str]:
    """The largest of ``values`` and where (``label[k]``); ``(0, "")`` when there are none."""
    if values.size == 0:
        return 0.0, ""
    k = int(np.argmax(np.where(np.isnan(values), np.inf, values)))
    v = float(values[k])
    return (v, f"{label}[{k}]") if v > 0 or math.isnan(v) else (v, "")


def groups(state: CollapseStateData) -> NDArray[np.int64]:
    """The group of each body: bodies joined by contact points other than the ground's."""
    both = (state.point_a >= 0) & (state.point_b >= 0)
    n = state.n_blocks
    graph = sp.coo_matrix((np.ones(int(both.sum())), (state.point_a[both], state.point_b[both])), shape=(n, n))
    return connected_components(graph, directed=False)[1].astype(np.int64)


def mechanics(state: CollapseStateData) -> tuple[dict[str, tuple[float, str]], dict[str, float]]:
    """Every mechanical residual ``name -> (value, where)`` (module docstring) and the state's scales
    (the largest body load ``force``, the largest body ``length``, the largest ``rate`` and ``power``)."""
    st = state
    n, s, mu, lam = st.normal_force, st.shear_force, st.mu, st.load_factor
    Bn, Bs = st.equilibrium_matrices()
    y = st.velocities.ravel()
    dn, ds = Bn.T @ y, Bs.T @ y
    size = sizes(st)
    F = np.maximum.reduce([st.weight, np.hypot(st.dead[:, 0], st.dead[:, 1]),
                           abs(lam) * np.hypot(st.live[:, 0], st.live[:, 1])])
    body = np.where(st.point_b >= 0, st.point_b, st.point_a)  # every point has one body at least
    Fp = np.maximum(F[body], np.where(st.point_a >= 0, F[np.maximum(st.point_a, 0)], 0.0))
    group = groups(st)
    ng = int(group.max(initial=-1)) + 1
    rate = np.maximum(np.abs(dn), np.abs(ds))
    R_group = np.full(ng, TINY)
    np.maximum.at(R_group, group[body], rate)
    R = R_group[group[body]]
    delta = mu * np.abs(ds) if st.friction == "associative" else np.zeros_like(ds)
    r = (Bn @ n + Bs @ s + st.dead.ravel() + lam * st.live.ravel()).reshape(-1, 3)
    eq = np.maximum(np.abs(r[:, :2]).max(axis=1) / F, np.abs(r[:, 2]) / (F * size))
    F_group = np.zeros(ng)
    np.maximum.at(F_group, group, F)
    np.maximum.at(F_group, group[body], np.abs(n))
    pressed_slip = (np.abs(ds) > SLIPPING * R) & (n > PRESSED * F_group[group[body]])
    live_work = (st.live * st.velocities).sum(axis=1)
    dead_work = (st.dead * st.velocities).sum(axis=1)
    dissipation = mu * n * np.abs(ds) if st.friction == "nonassociative" else np.zeros_like(n)
    terms = [np.bincount(group, weights=lam * live_work, minlength=ng),
             np.bincount(group, weights=dead_work, minlength=ng),
             np.bincount(group[body], weights=dissipation, minlength=ng)]
    W = np.maximum.reduce([np.abs(t) for t in terms] + [np.full(ng, TINY)])
    absolute = float(np.sum(np.abs(live_work)))
    values = {
        "equilibrium": _worst(eq, "blocks"),
        "no_tension": _worst(np.maximum(-n, 0.0) / Fp, "points"),
        "coulomb": _worst(np.maximum(np.abs(s) - mu * n, 0.0) / Fp, "points"),
        "compatibility": _worst(np.maximum(np.abs(st.opening_rate - dn), np.abs(st.slip_rate - ds)) / R, "points"),
        "interpenetration": _worst(np.maximum(delta - dn, 0.0) / R, "points"),
        "dilatancy": _worst(np.where(pressed_slip, np.abs(dn - delta), 0.0) / R, "points"),
        "opening": _worst(np.abs(n * (dn - delta)) / (np.maximum(Fp, n) * R), "points"),
        "friction": _worst(np.abs(s * ds + mu * n * np.abs(ds)) / (np.maximum(Fp, n) * R), "points"),
        "power": _worst(np.abs(terms[0] + terms[1] - terms[2]) / W, "groups"),
        "mechanism": (float(live_work.sum()) / absolute if absolute > 0 else 0.0, ""),
        "contact_states": _mismatches(st.contact_state, dn, ds),
    }
    scales = {"force": float(F.max()), "length": float(size.max()), "rate": float(rate.max(initial=0.0)),
              "power": float(W.max(initial=0.0))}
    return values, scales


def _mismatches(declared: tuple[str, ...], dn: FloatArray, ds: FloatArray) -> tuple[float, str]:
    """Points whose declared state is not the classification of their rates
    (:func:`micro.mechanism.classify_rates`) at any threshold ``t`` in :data:`STATE_BAND` times the largest
    rate: sliding needs ``|ds| > t``, opening ``|ds| <= t < |dn|``, closed ``|dn|, |ds| <= t``."""
    an, as_ = np.abs(dn), np.abs(ds)
    R = max(float(an.max(initial=0.0)), float(as_.max(initial=0.0)), TINY)
    lo, hi = STATE_BAND[0] * R, STATE_BAND[1] * R
    floor = np.maximum(as_, lo)
    ok = {"sliding": as_ > lo, "opening": (floor < an) & (floor <= hi), "closed": np.maximum(an, as_) <= hi}
    code = np.array(declared, dtype=object)
    good = np.zeros(an.size, dtype=bool)
    for name, allowed in ok.items():
        good |= (code == name) & allowed
    bad = np.flatnonzero(~good)
    return float(bad.size), (f"points[{int(bad[0])}]" if bad.size else "")
