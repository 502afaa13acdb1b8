"""Is a state a genuine collapse state of the wall it names? Every condition, and what could not be checked.

GENUINE means, for a file: (1) the structure is the wall the file names (where it names one: its ``wall``,
or a version-1 file's paper parameters given by the caller), block by block (:mod:`micro.state.rebuild`);
(2) the structure is consistent (:mod:`micro.state.outlines`): every contact point lies on both its bodies'
outlines, facing the way its normal says; every pair of edges that touch carries its contact points at
both ends of the segment they share; the loads follow from the outlines, the unit weight, the
thicknesses and the floor loads; (3) the forces and the mechanism satisfy every condition of the flow
rule (:mod:`micro.state.mechanics`), each residual relative to the body or point it is at. A state at rest
is not one (``mechanism``), nor a state whose contact forces are all zero (no body's weight is then in
equilibrium).

WHAT IT CANNOT KNOW. Without the wall (another program's file names none) the structure is checked as it
stands: that it is the wall the user meant, and the friction coefficient of its joints, are not known.
A genuine state is a collapse state at its load factor, not the lowest one: the non-associative problem
has many, and only a closed global search (:mod:`micro.global_search`) proves a lower bound. Rates are
checked relative to the fastest body of each group of touching bodies, so that a violation below 1e-3 of
that (the simplex duals' noise) passes. What a file of version 1 cannot give is named in
:attr:`StateCheck.unchecked`.

The tolerances are named below; ``docs/files.md`` lists them, and the residuals of the report's walls
they were set against are on the research page on collapse state files (``docs/research/``).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from micro.columns import json_number
from micro.geometry import BlockWall
from micro.hold import HeldWall
from micro.nonassociative.config import INTERPENETRATION
from micro.state import outlines
from micro.state.data import CollapseStateData
from micro.state.file import read_state
from micro.state.mechanics import mechanics
from micro.state.rebuild import compare_with_wall

#: The structure is the wall's: outlines and points within this share of a body's size, loads of its
#: weight (the builder's coordinates are exact copies: rounding only).
WALL_TOL = 1e-9
#: Contact points on their outlines: distance over the body's size.
GEOMETRY_TOL = outlines.LENGTH_TOL
#: Loads against the outlines, unit weight, thicknesses and floor loads: over the body's weight (moments
#: over its weight times its size).
LOADS_TOL = 1e-9
#: Equilibrium: a body's unbalanced force over its own load (moment over its load times its size); the
#: states the suite writes leave at most 3e-9 (the research page).
EQUILIBRIUM_TOL = 1e-6
#: No tension and Coulomb: largest violation over the point's load.
FORCE_TOL = 1e-6
#: Compatibility: the file's rates against those of its velocities, over ``R`` (rounding only).
COMPATIBILITY_TOL = 1e-9
#: Interpenetration: closing rate (associative: below the dilatancy) over ``R``: the certificate's and
#: the descent's reading of the simplex duals' noise (``micro.nonassociative.config.INTERPENETRATION``),
#: so that every state they certify passes. A closing point that carries force fails ``opening`` and
#: ``power`` at their tolerances.
INTERPENETRATION_TOL = INTERPENETRATION
#: Dilatancy where sliding: ``|dn - delta|`` at pressed slipping points, over ``R``. An interior point's
#: mechanism misses it by its complementarity gap over ``n``, hence ``PRESSED`` and this tolerance,
#: ten times the largest seen on the report's walls (the research page of the module docstring).
DILATANCY_TOL = 1e-4
#: Opening only where ``n = 0``: ``n |dn - delta|`` over ``max(n, F_p) R`` (a loaded point's opening rate over
#: ``R``; a lightly loaded one's weighted by its share of its blocks' load). The certified states of the
#: report's walls reach 9.7e-7 (an interior point's mechanism, the three-storey example's 1,230 blocks).
OPENING_TOL = 1e-5
#: Friction against the slip at the yield line: ``|s ds + mu n |ds||`` over ``max(n, F_p) R`` (as ``opening``).
FRICTION_TOL = 1e-5
#: Power balance of a group of touching bodies: work of the loads minus the friction law's dissipation,
#: over the largest of the three: the descent's acceptance of a state's energy balance (``EXACT_TOL``).
POWER_TOL = 1e-6
#: The mechanism: the live load's work at least this share of its bodies' absolute works.
MECHANISM_TOL = 1e-6

#: The tolerance of each residual (``mechanism``: a lower bound; ``touching_edges``, ``contact_states``:
#: counts).
TOLERANCES = {
    "wall": WALL_TOL, "contact_geometry": GEOMETRY_TOL, "touching_edges": 0.0, "loads": LOADS_TOL,
    "equilibrium": EQUILIBRIUM_TOL, "no_tension": FORCE_TOL, "coulomb": FORCE_TOL,
    "compatibility": COMPATIBILITY_TOL, "interpenetration": INTERPENETRATION_TOL, "dilatancy": DILATANCY_TOL,
    "opening": OPENING_TOL, "friction": FRICTION_TOL, "power": POWER_TOL, "mechanism": MECHANISM_TOL,
    "contact_states": 0.0,
}
#: What each residual checks (one line each, the order of :attr:`StateCheck.residuals`).
MEANINGS = {
    "wall": "the blocks, loads and contact points are those of the wall the file names, block by block",
    "contact_geometry": "every contact point lies on an edge of both its blocks, facing the way its normal says",
    "touching_edges": "every segment where two blocks (or a block and the ground) touch has a contact point at "
                      "each end (count of those that do not)",
    "loads": "the weights, dead and live loads follow from the outlines, the unit weight, the thicknesses and "
             "the floor loads",
    "equilibrium": "every block in equilibrium under its loads and contact forces",
    "no_tension": "no normal force below zero",
    "coulomb": "every shear force within mu times its normal force",
    "compatibility": "the rates are those of the block velocities",
    "interpenetration": "no point closes (associative: opens at least mu |slip rate|)",
    "dilatancy": "no dilatancy where a pressed point slides (associative: exactly mu |slip rate|)",
    "opening": "opening only where the normal force is zero",
    "friction": "where a point slips, its shear force is mu n against the slip",
    "power": "the work of the loads equals the dissipation of the friction law (each group of touching blocks)",
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
        where: the block or point where the value is reached, and what differs there (``""``: nowhere
            in particular).
    """

    name: str
    value: float
    tolerance: float
    at_least: bool = False
    where: str = ""

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
        """``name value <= tolerance (meaning)``, ``>`` where it fails, and where."""
        op = (">=" if self.passed else "<") if self.at_least else ("<=" if self.passed else ">")
        at = f": {self.where}" if self.where and not self.passed else ""
        return f"{self.name} {self.value:.3g} {op} {self.tolerance:.3g} ({self.meaning}){at}"


@dataclass(frozen=True)
class StateCheck:
    """The check of a collapse state (:func:`verify_state`).

    Attributes:
        friction: the friction law checked against.
        load_factor: the state's ``lambda``.
        direction: its load direction.
        blocks, points: its size.
        residuals: every condition checked, in the order of :data:`MEANINGS`.
        scales: the largest ``force`` (a body's load), ``length`` (a body's size), ``rate`` and ``power``
            (of a group's balance); each residual is relative to its own body's or point's.
        version: the file format's version.
        wall: how the structure was compared with a wall (``""``: it was not).
        unchecked: what could not be checked, and why (one line each).
    """

    friction: str
    load_factor: float
    direction: str
    blocks: int
    points: int
    residuals: tuple[Residual, ...]
    scales: dict[str, float]
    version: int = 2
    wall: str = ""
    unchecked: tuple[str, ...] = field(default=())

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
        num = json_number
        return {
            "passed": self.passed, "worst": self.worst.name, "friction": self.friction,
            "load_factor": num(self.load_factor), "direction": self.direction, "blocks": self.blocks,
            "points": self.points, "version": self.version, "wall": self.wall or None,
            "unchecked": list(self.unchecked), "scales": {k: num(v) for k, v in self.scales.items()},
            "residuals": [{"name": r.name, "value": num(r.value), "tolerance": r.tolerance,
                           "bound": "min" if r.at_least else "max", "passed": r.passed, "meaning": r.meaning,
                           "where": r.where or None}
                          for r in self.residuals],
        }


def verify_state(state: CollapseStateData | str | os.PathLike[str], *, wall: BlockWall | HeldWall | None = None,
                 wall_name: str = "the wall given") -> StateCheck:
    """Check a collapse state: the wall it names, its geometry and loads, and the conditions of its
    friction law (module docstring).

    Args:
        state: a :class:`~micro.state.data.CollapseStateData`, or the path of a state file
            (:func:`micro.read_state` reads it).
        wall: a wall to compare it with, block by block, besides the file's own ``wall`` (built again),
            e.g. the wall a version-1 file's paper parameters describe. A version-1 state's bodies are
            compared with the wall's blocks in order.
        wall_name: what ``wall`` is, for :attr:`StateCheck.wall`.

    Returns:
        The :class:`StateCheck`; :attr:`StateCheck.passed` when every residual is within its tolerance.

    Raises:
        micro.StateFileError: a path to a malformed file (one line naming the file and the field or line).
    """
    if not isinstance(state, CollapseStateData):
        state = read_state(state)
    unchecked: list[str] = []
    values: dict[str, tuple[float, str]] = {}
    how: list[str] = []
    with np.errstate(all="ignore"):  # numbers that overflow give residuals that are not finite: they fail
        walls: list[BlockWall | HeldWall] = [] if wall is None else [wall]
        if wall is not None:
            how.append(f"compared block by block with {wall_name}")
        if state.wall is not None:
            try:
                walls.append(state.wall.build())
                how.append("built again from the file's wall parameters and compared block by block")
            except ValueError as exc:
                values["wall"] = (math.inf, f"the file's wall cannot be built ({exc})")
        for w in walls:
            found = compare_with_wall(state, w)
            if "wall" not in values or not found[0] <= values["wall"][0]:
                values["wall"] = found
        if not walls and "wall" not in values:
            unchecked.append("wall: the file names no wall, so its structure is checked as it stands (that it "
                             "is the wall meant, and its joints' friction coefficient, are not known)")
        if (state.point_a < 0).any() and not state.fixed_vertices and outlines.base_line(state) is None:
            unchecked.append("the ground: its contact points lie at several heights and no block is fixed to it, "
                             "so its outline is not known (its points are checked on their blocks' outlines)")
        values["contact_geometry"] = outlines.contact_geometry(state)
        values["touching_edges"] = outlines.touching_edges(state)
        values["loads"] = outlines.loads(state)
        mech, scales = mechanics(state)
        values.update(mech)
    if state.version < 2:
        unchecked += ["loads: a version-1 file gives no unit weight, thickness or floor loads: the live loads are "
                      "checked against the dead loads, the dead loads against the weights (at the outlines' "
                      "centroids where no floor load acts), not the weights against the areas",
                      "held blocks: a version-1 file does not say which blocks a body holds"]
    residuals = tuple(Residual(name, values[name][0], TOLERANCES[name], at_least=name == "mechanism",
                               where=values[name][1]) for name in MEANINGS if name in values)
    return StateCheck(friction=state.friction, load_factor=state.load_factor, direction=state.direction,
                      blocks=state.n_blocks, points=state.n_points, residuals=residuals, scales=scales,
                      version=state.version, wall="; ".join(how), unchecked=tuple(unchecked))
