"""Is a state a genuine collapse state? Every condition checked from the state's own data.

Notation (:class:`~micro.state.data.CollapseStateData`): at point ``p`` the normal force ``n``, the
shear force ``s``, the friction coefficient ``mu``, the opening rate ``dn`` and slip rate ``ds``; per
block the dead load ``D``, the live load ``L`` (as applied) and the velocity ``y``; the load factor
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
dilatancy (friction dissipates; an opening point dissipates nothing) and ``0`` for the associative law
(the normal force's work against the dilatancy ``mu n |ds|`` returns what friction dissipates). So the
work of the loads must equal that dissipation: the balance follows from the pointwise conditions, and
checks them summed at the scale of the whole state; a load factor raised by a fraction ``e`` breaks it
by ``e`` of the live load's work. The mechanism must be one: the live load does positive work, a
share of the sum of its blocks' absolute works (a state at rest satisfies every other condition).

SCALES. Each residual is relative to the state's own scale, so a state in any units checks alike:
``F`` the largest force (normal force, a block's dead load, ``|lambda|`` times a block's live load),
``l`` the largest block (the diagonal of its bounding box; moments by ``F l``),
``R`` the largest rate (opening or slip, from the velocities), and ``W`` the largest of the power
balance's three terms. A point is pressed when ``n > PRESSED * F`` and slips when
``|ds| > SLIPPING * R``. The tolerances are named below; ``docs/files.md`` lists them, and the residuals
of the report's walls they were set against are on the research page
the research page on collapse state files (``docs/research/``).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.mechanism import CONTACT_STATE_TOL
from micro.nonassociative.config import INTERPENETRATION
from micro.state.data import CollapseStateData
from micro.state.file import read_state

FloatArray = NDArray[np.float64]

#: Equilibrium: largest unbalanced force of a block over ``F`` (moment over ``F l``); the iterated LP's
#: bound on a final state (``EQUILIBRIUM_RESIDUAL``, block weights, and ``F`` is at least one).
EQUILIBRIUM_TOL = 1e-6
#: No tension and Coulomb: largest violation over ``F``.
FORCE_TOL = 1e-6
#: Compatibility: the file's rates against those of its velocities, over ``R`` (rounding only).
COMPATIBILITY_TOL = 1e-9
#: Interpenetration: closing rate (associative: below the dilatancy) over ``R``: the certificate's and
#: the descent's reading of the simplex duals' noise (``micro.nonassociative.config.INTERPENETRATION``),
#: so that every state they certify passes. A closing point that carries force fails ``opening`` and
#: ``power`` at their tolerances.
INTERPENETRATION_TOL = INTERPENETRATION
#: Dilatancy where sliding: ``|dn - delta|`` at pressed slipping points, over ``R``. An interior point's
#: mechanism misses it by its complementarity gap over ``n``, hence :data:`PRESSED` and this tolerance,
#: ten times the largest seen on the report's walls (the research page of the module docstring).
DILATANCY_TOL = 1e-4
#: Opening only where ``n = 0``: ``n |dn - delta|`` over ``F R``.
OPENING_TOL = 1e-6
#: Friction against the slip at the yield line: ``|s ds + mu n |ds||`` over ``F R``.
FRICTION_TOL = 1e-6
#: Power balance: work of the loads minus the friction law's dissipation, over ``W``: the descent's
#: acceptance of a state's energy balance (``EXACT_TOL``). A load factor raised by 1 % breaks it by 1e-2.
POWER_TOL = 1e-6
#: The mechanism: the live load's work at least this share of its blocks' absolute works.
MECHANISM_TOL = 1e-6
#: A point is pressed when its normal force exceeds this share of ``F`` (for ``dilatancy``; ``opening``
#: weighs every point by its normal force).
PRESSED = 1e-4
#: A point slips when its slip rate exceeds this share of ``R``.
SLIPPING = 1e-6
#: A point's declared state agrees with its rates when it is their classification
#: (:func:`micro.mechanism.classify_rates`) at some threshold in this band (times ``R``) around
#: :data:`~micro.mechanism.CONTACT_STATE_TOL`, the writer's
#: (:func:`micro.mechanism.classify_rates`).
STATE_BAND = (CONTACT_STATE_TOL / 10.0, CONTACT_STATE_TOL * 10.0)
#: Floor of the scales.
TINY = 1e-300

#: The tolerance of each residual (``mechanism``: a lower bound; ``contact_states``: a count).
TOLERANCES = {
    "equilibrium": EQUILIBRIUM_TOL, "no_tension": FORCE_TOL, "coulomb": FORCE_TOL,
    "compatibility": COMPATIBILITY_TOL, "interpenetration": INTERPENETRATION_TOL, "dilatancy": DILATANCY_TOL,
    "opening": OPENING_TOL, "friction": FRICTION_TOL, "power": POWER_TOL, "mechanism": MECHANISM_TOL,
    "contact_states": 0.0,
}
#: What each residual checks (one line each, the order of :attr:`StateCheck.residuals`).
MEANINGS = {
    "equilibrium": "every block in equilibrium under its loads and contact forces",
    "no_tension": "no normal force below zero",
    "coulomb": "every shear force within mu times its normal force",
    "compatibility": "the rates are those of the block velocities",
    "interpenetration": "no point closes (associative: opens at least mu |slip rate|)",
    "dilatancy": "no dilatancy where a pressed point slides (associative: exactly mu |slip rate|)",
    "opening": "opening only where the normal force is zero",
    "friction": "where a point slips, its shear force is mu n against the slip",
    "power": "the work of the loads equals the dissipation of the friction law",
    "mechanism": "the live load does positive work (a share of its blocks' absolute works)",
    "contact_states": "every point's declared state agrees with its rates (count of those that do not)",
}


@dataclass(frozen=True)
class Residual:
    """One condition's residual against its tolerance.

    Attributes:
        name: the condition (:data:`MEANINGS`).
        value: the residual (relative; ``contact_states``: a count).
        tolerance: its named tolerance.
        at_least: ``True`` when the value must be at least the tolerance (``mechanism``), else at most.
    """

    name: str
    value: float
    tolerance: float
    at_least: bool = False

    @property
    def passed(self) -> bool:
        """The value is within its tolerance (a NaN never is)."""
        return bool(self.value >= self.tolerance) if self.at_least else bool(self.value <= self.tolerance)

    @property
    def excess(self) -> float:
        """How far past its tolerance: ``value / tolerance`` (``tolerance / value`` for an ``at_least``
        one); above 1 fails. The worst residual has the largest."""
        if math.isnan(self.value):
            return math.inf
        num, den = (self.tolerance, self.value) if self.at_least else (self.value, self.tolerance)
        if den <= 0:
            return math.inf if num > 0 else 0.0
        return num / den

    @property
    def meaning(self) -> str:
        """What it checks."""
        return MEANINGS[self.name]

    def describe(self) -> str:
        """``name value <= tolerance (meaning)``, ``>`` where it fails."""
        op = (">=" if self.passed else "<") if self.at_least else ("<=" if self.passed else ">")
        return f"{self.name} {self.value:.3g} {op} {self.tolerance:.3g} ({self.meaning})"


@dataclass(frozen=True)
class StateCheck:
    """The check of a collapse state (:func:`verify_state`).

    Attributes:
        friction: the friction law checked against.
        load_factor: the state's ``lambda``.
        direction: its load direction.
        blocks, points: its size.
        residuals: every condition, in the order of :data:`MEANINGS`.
        scales: ``force``, ``length``, ``rate``, ``power`` (the module docstring's ``F``, ``l``, ``R``, ``W``).
    """

    friction: str
    load_factor: float
    direction: str
    blocks: int
    points: int
    residuals: tuple[Residual, ...]
    scales: dict[str, float]

    @property
    def passed(self) -> bool:
        """Every residual within its tolerance: a genuine collapse state."""
        return all(r.passed for r in self.residuals)

    @property
    def worst(self) -> Residual:
        """The residual with the largest :attr:`Residual.excess`; ``contact_states`` (a count, tolerance 0)
        only when it alone fails: the declared states describe the rates, which the conditions check."""
        mechanics = [r for r in self.residuals if r.name != "contact_states"]
        if all(r.passed for r in mechanics) and not self.passed:
            return self.residual("contact_states")
        return max(mechanics, key=lambda r: r.excess)

    @property
    def failed(self) -> tuple[Residual, ...]:
        """The residuals past their tolerances."""
        return tuple(r for r in self.residuals if not r.passed)

    def residual(self, name: str) -> Residual:
        """The residual ``name``.

        Raises:
            KeyError: no such residual.
        """
        for r in self.residuals:
            if r.name == name:
                return r
        raise KeyError(name)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (non-finite values as ``None``)."""
        def num(x: float) -> float | None:
            return float(x) if math.isfinite(x) else None

        return {
            "passed": self.passed, "worst": self.worst.name, "friction": self.friction,
            "load_factor": num(self.load_factor), "direction": self.direction, "blocks": self.blocks,
            "points": self.points, "scales": {k: num(v) for k, v in self.scales.items()},
            "residuals": [{"name": r.name, "value": num(r.value), "tolerance": r.tolerance,
                           "bound": "min" if r.at_least else "max", "passed": r.passed, "meaning": r.meaning}
                          for r in self.residuals],
        }


def verify_state(state: CollapseStateData | str | os.PathLike[str]) -> StateCheck:
    """Check a collapse state against the conditions of its friction law (module docstring).

    Args:
        state: a :class:`~micro.state.data.CollapseStateData`, or the path of a state file
            (:func:`micro.read_state` reads it).

    Returns:
        The :class:`StateCheck`; :attr:`StateCheck.passed` when every residual is within its tolerance.

    Raises:
        micro.StateFileError: a path to a malformed file (one line naming the file and the field or line).
    """
    if not isinstance(state, CollapseStateData):
        state = read_state(state)
    with np.errstate(all="ignore"):  # numbers that overflow give residuals that are not finite: they fail
        values, scales = _residuals(state)
    residuals = tuple(Residual(name, values[name], TOLERANCES[name], at_least=name == "mechanism")
                      for name in MEANINGS)
    return StateCheck(friction=state.friction, load_factor=state.load_factor, direction=state.direction,
                      blocks=state.n_blocks, points=state.n_points, residuals=residuals, scales=scales)


def _residuals(st: CollapseStateData) -> tuple[dict[str, float], dict[str, float]]:
    """Every residual of :data:`MEANINGS` and the scales (module docstring); all NaN where a scale
    overflows."""
    n, s, mu, lam = st.normal_force, st.shear_force, st.mu, st.load_factor
    Bn, Bs = st.equilibrium_matrices()
    y = st.velocities.ravel()
    dn, ds = Bn.T @ y, Bs.T @ y
    F = max(float(np.max(np.abs(n), initial=0.0)), _largest_force(st.dead), abs(lam) * _largest_force(st.live), TINY)
    ell = max(max((_size(v) for v in st.vertices), default=0.0), TINY)
    R = max(float(np.max(np.abs(dn), initial=0.0)), float(np.max(np.abs(ds), initial=0.0)), TINY)
    delta = mu * np.abs(ds) if st.friction == "associative" else np.zeros_like(ds)
    live_work = float(st.live.ravel() @ y)
    dead_work = float(st.dead.ravel() @ y)
    dissipation = float(np.sum(mu * n * np.abs(ds))) if st.friction == "nonassociative" else 0.0
    W = max(abs(lam * live_work), abs(dead_work), abs(dissipation), TINY)
    scales = {"force": F, "length": ell, "rate": R, "power": W}
    if not all(math.isfinite(x) for x in scales.values()):
        return dict.fromkeys(MEANINGS, math.nan), scales
    r = (Bn @ n + Bs @ s + st.dead.ravel() + lam * st.live.ravel()).reshape(-1, 3)
    eq = max(float(np.max(np.abs(r[:, :2]), initial=0.0)) / F, float(np.max(np.abs(r[:, 2]), initial=0.0)) / (F * ell))
    pressed_slip = (np.abs(ds) > SLIPPING * R) & (n > PRESSED * F)
    absolute = float(np.sum(np.abs((st.live * st.velocities).sum(axis=1))))
    values = {
        "equilibrium": eq,
        "no_tension": max(0.0, float(np.max(-n, initial=0.0))) / F,
        "coulomb": max(0.0, float(np.max(np.abs(s) - mu * n, initial=0.0))) / F,
        "compatibility": max(float(np.max(np.abs(st.opening_rate - dn), initial=0.0)),
                             float(np.max(np.abs(st.slip_rate - ds), initial=0.0))) / R,
        "interpenetration": max(0.0, float(np.max(delta - dn, initial=0.0))) / R,
        "dilatancy": float(np.max(np.abs(dn - delta)[pressed_slip], initial=0.0)) / R,
        "opening": float(np.max(np.abs(n * (dn - delta)), initial=0.0)) / (F * R),
        "friction": float(np.max(np.abs(s * ds + mu * n * np.abs(ds)), initial=0.0)) / (F * R),
        "power": abs(lam * live_work + dead_work - dissipation) / W,
        "mechanism": live_work / absolute if absolute > 0 else 0.0,
        "contact_states": float(_state_mismatches(st.contact_state, dn, ds, R)),
    }
    return values, scales


def _largest_force(loads: FloatArray) -> float:
    """The largest force ``|(F_x, F_y)|`` of a block's load."""
    return float(np.max(np.hypot(loads[:, 0], loads[:, 1]), initial=0.0))


def _size(vertices: FloatArray) -> float:
    """The diagonal of the block's bounding box (between its diameter and 1.4 times it; linear in the
    number of vertices)."""
    return float(np.hypot(*(np.max(vertices, axis=0) - np.min(vertices, axis=0))))


def _state_mismatches(declared: tuple[str, ...], dn: FloatArray, ds: FloatArray, R: float) -> int:
    """Points whose declared state is not the classification of their rates
    (:func:`micro.mechanism.classify_rates`) at any threshold ``t`` in :data:`STATE_BAND` times ``R``:
    sliding needs ``|ds| > t``, opening ``|ds| <= t < |dn|``, closed ``|dn|, |ds| <= t``."""
    lo, hi = STATE_BAND[0] * R, STATE_BAND[1] * R
    an, as_ = np.abs(dn), np.abs(ds)
    floor = np.maximum(as_, lo)
    ok = {"sliding": as_ > lo, "opening": (floor < an) & (floor <= hi), "closed": np.maximum(an, as_) <= hi}
    code = np.array(declared, dtype=object)
    good = np.zeros(an.size, dtype=bool)
    for name, allowed in ok.items():
        good |= (code == name) & allowed
    return int((~good).sum())
