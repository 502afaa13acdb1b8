"""A collapse state as data (:class:`CollapseStateData`), and the state behind a result of this library.

Everything is dimensional, in the units of the wall (any consistent units). The state holds its own
structure (bodies, outlines, loads, contact points) and, where it knows it, the wall it is of
(:class:`~micro.state.structure.WallParameters`): a state built from another program's output is the same
type, without the wall.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall
from micro.hold import HeldWall
from micro.limit_result import DirectionResult, LimitResult, direction_sign
from micro.lp import point_columns, point_geometry
from micro.mechanism import CONTACT_STATE_NAMES, CONTACT_STATE_TOL, classify_rates
from micro.nonassociative import NonAssociativeResult
from micro.state.structure import WallParameters, analysed_wall, structure_of

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Values of :attr:`CollapseStateData.friction`.
FRICTIONS = ("associative", "nonassociative")
#: Values of :attr:`CollapseStateData.direction`.
DIRECTIONS = ("+x", "-x")
#: The version of the file format this library writes (:mod:`micro.state.file`).
VERSION = 2


def _frozen(a: Any, dtype: Any) -> np.ndarray:
    out = np.array(a, dtype=dtype)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class CollapseStateData:
    """A collapse state: a structure of rigid bodies, the load factor, the friction law, the contact forces
    and the mechanism (dimensional; arrays read-only).

    The structure. Body ``i`` has its outline ``vertices[i]`` (``(k, 2)``), a reference point
    ``centroid[i]`` about which its loads' moments and its angular velocity are taken, its self
    ``weight[i]``, its ``dead[i]`` load and ``live[i]`` load per unit load factor, both ``(F_x, F_y, M)``.
    Version 2 also gives what the loads follow from: the ``unit_weight``, each body's ``members`` (the
    numbers of the wall's blocks it is made of: more than one where blocks are held to their host),
    ``thickness`` (or its ``parts``, each an outline and a thickness, where its blocks differ), the floor
    loads (``floor_block``, ``floor_position``, ``floor_load``: vertical forces at points, whose masses
    the live load pushes too), and the blocks ``fixed`` to the ground. Contact point ``p`` joins body
    ``point_a[p]`` to body ``point_b[p]`` (``-1``: the ground, fixed) at ``position[p]``, with the unit
    ``normal[p]`` pointing from ``a`` into ``b``, a unit ``tangent[p]`` orthogonal to it, and the
    friction coefficient ``mu[p]`` of its interface.

    The state. The live load acts as given, multiplied by ``load_factor`` (``direction`` names its
    sense: ``live`` holds the load as applied, not a ``+x`` load to be turned). The force on body ``b``
    at point ``p`` is ``normal_force[p] * normal[p] + shear_force[p] * tangent[p]``, on body ``a`` its
    opposite. ``velocities[i]`` is ``(u, v, omega)`` of body ``i``'s reference point, ``omega``
    counter-clockwise; ``opening_rate[p]`` and ``slip_rate[p]`` are the velocity of ``b`` relative to
    ``a`` at the point along the normal (opening > 0) and the tangent; ``contact_state[p]`` is
    ``"closed"``, ``"opening"`` or ``"sliding"``.

    Attributes:
        friction: ``"associative"`` or ``"nonassociative"`` (zero dilatancy): the flow rule the state is
            checked against.
        load_factor: ``lambda``.
        direction: ``"+x"`` or ``"-x"``.
        vertices: per body, its outline.
        centroid, weight, dead, live: per body (see above).
        point_a, point_b, position, normal, tangent, mu: per contact point (see above).
        normal_force, shear_force: per contact point.
        velocities: ``(n_blocks, 3)``.
        opening_rate, slip_rate: per contact point.
        contact_state: per contact point.
        source: where the state comes from (free JSON data: program, method, wall).
        version: the file format's version it was read from (2 for a state made here).
        unit_weight: the blocks' specific weight (NaN: not given, version 1).
        members: per body, the wall's blocks it is made of (empty: not given, version 1).
        thickness: per body (NaN where ``parts`` gives it; empty: not given, version 1).
        parts: body -> ``((outline, thickness), ...)`` for the bodies whose blocks differ in thickness.
        floor_block, floor_position, floor_load: the floor loads.
        fixed_members, fixed_vertices: the wall's blocks held to the ground, each with its outline.
        wall: the wall the state is of (``None``: not given).
    """

    friction: str
    load_factor: float
    direction: str
    vertices: tuple[FloatArray, ...] = field(repr=False)
    centroid: FloatArray = field(repr=False)
    weight: FloatArray = field(repr=False)
    dead: FloatArray = field(repr=False)
    live: FloatArray = field(repr=False)
    point_a: IntArray = field(repr=False)
    point_b: IntArray = field(repr=False)
    position: FloatArray = field(repr=False)
    normal: FloatArray = field(repr=False)
    tangent: FloatArray = field(repr=False)
    mu: FloatArray = field(repr=False)
    normal_force: FloatArray = field(repr=False)
    shear_force: FloatArray = field(repr=False)
    velocities: FloatArray = field(repr=False)
    opening_rate: FloatArray = field(repr=False)
    slip_rate: FloatArray = field(repr=False)
    contact_state: tuple[str, ...] = field(repr=False)
    source: Mapping[str, Any] = field(default_factory=dict, repr=False)
    version: int = VERSION
    unit_weight: float = math.nan
    members: tuple[tuple[int, ...], ...] = field(default=(), repr=False)
    thickness: FloatArray = field(default_factory=lambda: np.zeros(0), repr=False)
    parts: Mapping[int, tuple[tuple[FloatArray, float], ...]] = field(default_factory=dict, repr=False)
    floor_block: IntArray = field(default_factory=lambda: np.zeros(0, dtype=np.int64), repr=False)
    floor_position: FloatArray = field(default_factory=lambda: np.zeros((0, 2)), repr=False)
    floor_load: FloatArray = field(default_factory=lambda: np.zeros(0), repr=False)
    fixed_members: tuple[tuple[int, ...], ...] = field(default=(), repr=False)
    fixed_vertices: tuple[FloatArray, ...] = field(default=(), repr=False)
    wall: WallParameters | None = None

    def __post_init__(self) -> None:
        ints = ("point_a", "point_b", "floor_block")
        for name, value in self.__dict__.items():
            if isinstance(value, np.ndarray):
                object.__setattr__(self, name, _frozen(value, np.int64 if name in ints else np.float64))
        for name in ("vertices", "fixed_vertices"):
            object.__setattr__(self, name, tuple(_frozen(v, np.float64) for v in getattr(self, name)))
        object.__setattr__(self, "contact_state", tuple(self.contact_state))
        object.__setattr__(self, "members", tuple(tuple(int(k) for k in m) for m in self.members))
        object.__setattr__(self, "fixed_members", tuple(tuple(int(k) for k in m) for m in self.fixed_members))

    @property
    def n_blocks(self) -> int:
        """Number of blocks."""
        return int(self.centroid.shape[0])

    @property
    def n_points(self) -> int:
        """Number of contact points."""
        return int(self.point_a.shape[0])

    def equilibrium_matrices(self) -> tuple[Any, Any]:
        """``(B_n, B_s)``: the equilibrium columns of the normal and shear point forces, from the state's
        own contact geometry (:func:`micro.lp.point_columns`); their transposes map the velocities onto
        the opening and slip rates."""
        xc, yc = self.centroid[:, 0], self.centroid[:, 1]
        args = (self.point_a, self.point_b, self.position[:, 0], self.position[:, 1])
        return (point_columns(*args, self.normal, xc, yc, self.n_blocks),
                point_columns(*args, self.tangent, xc, yc, self.n_blocks))


def collapse_state(result: Any, wall: BlockWall | HeldWall, *,
                   source: Mapping[str, Any] | None = None) -> CollapseStateData:
    """The governing collapse state of a result of this library on ``wall`` (the wall as built, or a held
    wall: then each body is a block with the blocks held to it, named under ``members``).

    Which state: of :func:`micro.solve_associative`, the LP's governing direction; of
    :func:`micro.solve_nonassociative`, the state whose load factor is the value to quote: the lowest
    certified state where the descent found one in every direction, else the iterated LP's final state
    of the governing direction.

    The velocities are the mechanism's, in the wall's units, scaled so that the live load does unit
    work; the rates are computed from them with the wall's contact geometry, and each point's state is
    classified from its own rates (:func:`micro.mechanism.classify_rates`, rates below
    :data:`~micro.mechanism.CONTACT_STATE_TOL` of the largest counting as zero).

    Args:
        result: a :class:`micro.LimitResult` or a :class:`micro.NonAssociativeResult` of ``wall``.
        wall: the wall it was computed on: a :class:`micro.BlockWall`, or the :class:`micro.HeldWall` whose
            ``wall`` it was computed on (the state then says which blocks are held).
        source: more to record under ``source`` (e.g. the wall's parameters); the method is recorded
            under ``"state"``.

    Raises:
        TypeError: ``result`` is not one of the two, or ``wall`` not a :class:`micro.BlockWall` or a
            :class:`micro.HeldWall`.
        ValueError: the result failed (no state), or it is not of ``wall`` (its sizes differ).
    """
    built, wall = wall, analysed_wall(wall)
    direction, lam, friction, what = _governing(result)
    if direction.normal is None or direction.shear is None or direction.mechanism is None:
        raise ValueError(f"the {what} has no forces or mechanism ({direction.status})")
    if direction.normal.shape[0] != wall.n_points or direction.mechanism.velocities.shape[0] != wall.n_blocks:
        raise ValueError(f"the result is not of this wall ({direction.normal.shape[0]} contact points, "
                         f"the wall has {wall.n_points})")
    d = direction_sign(direction.direction)
    a, b, px, py, nrm, tan = point_geometry(wall)
    ls, fs = wall.block_height, wall.reference_weight
    velocities = direction.mechanism.velocities / np.array([fs, fs, fs * ls])  # unit work of the live load
    st = structure_of(built)
    state = CollapseStateData(
        friction=friction, load_factor=float(lam), direction=direction.direction, vertices=st.vertices,
        centroid=st.centroid, weight=st.weight, dead=st.dead, live=d * st.live, point_a=a, point_b=b,
        position=np.column_stack([px, py]), normal=nrm, tangent=tan, mu=np.repeat(wall.mu, 2),
        normal_force=direction.normal, shear_force=direction.shear, velocities=velocities,
        opening_rate=np.zeros(a.size), slip_rate=np.zeros(a.size), contact_state=("closed",) * a.size,
        source={"program": "xcheck-masonry", "state": what, **(source or {})},
        unit_weight=st.unit_weight, members=st.members, thickness=st.thickness, parts=st.parts,
        floor_block=st.floor_block, floor_position=st.floor_position, floor_load=st.floor_load,
        fixed_members=st.fixed_members, fixed_vertices=st.fixed_vertices, wall=WallParameters.of(built),
    )
    return with_rates(state)


def with_rates(state: CollapseStateData) -> CollapseStateData:
    """``state`` with its opening and slip rates computed from its velocities and each point's state
    classified from them (rates below :data:`~micro.mechanism.CONTACT_STATE_TOL` of the largest count
    as zero)."""
    Bn, Bs = state.equilibrium_matrices()
    y = state.velocities.ravel()
    dn, ds = Bn.T @ y, Bs.T @ y
    scale = max(float(np.max(np.abs(dn), initial=0.0)), float(np.max(np.abs(ds), initial=0.0)))
    states = classify_rates(dn, ds, CONTACT_STATE_TOL * scale)
    names = tuple(CONTACT_STATE_NAMES[k] for k in states)
    return dataclasses.replace(state, opening_rate=dn, slip_rate=ds, contact_state=names)


def _governing(result: Any) -> tuple[DirectionResult, float, str, str]:
    """``(direction result, lambda, friction, what)`` of the state to write (:func:`collapse_state`)."""
    if isinstance(result, LimitResult):
        if not result.ok:
            raise ValueError(f"the associative LP failed ({result.status}): no collapse state")
        return result.by_direction(result.direction), result.load_factor, "associative", "associative LP"
    if isinstance(result, NonAssociativeResult):
        if not result.ok:
            raise ValueError(f"the iterated LP did not converge ({result.status}): no collapse state")
        low = result.lowest_state
        if low is not None and low.state is not None:
            return low.state, low.load_factor, "nonassociative", "lowest certified"
        g = result.governing
        lam = g.sequence.last_load_factor if g.sequence is not None else g.load_factor
        if not math.isfinite(lam):
            raise ValueError("the iterated LP has no final load factor: no collapse state")
        return g, lam, "nonassociative", "iterated LP"
    raise TypeError(f"result must be a micro.LimitResult or a micro.NonAssociativeResult, got "
                    f"{type(result).__name__}")
