"""Result types shared by the associative and the non-associative analyses, and the load directions.

:class:`DirectionResult` is the ONE per-direction type: the associative LP
fills its common fields and ``native_status``/``info``; a method with
diagnostics of its own adds them as ``sequence`` (the iterated
non-associative LP: :class:`micro.nonassociative.nonassociative_result.SequenceDiagnostics`,
read through :func:`micro.nonassociative.nonassociative_result.diagnostics`). This module
knows no method: the field's type is the method's business.
:class:`LimitResult` is the associative analysis (governing direction first).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from micro.backends.base import Status
from micro.columns import record_of
from micro.mechanism import CONTACT_STATE_NAMES, Mechanism
from micro.records import AssociativeDirection, AssociativeRecord, check_success

FloatArray = NDArray[np.float64]

#: Name of a load direction (``+1``: live load in ``+x``).
DIR_NAME = {1: "+x", -1: "-x"}
#: Values of the ``directions`` option.
DIRECTIONS = ("auto", "both", "+x", "-x")
Directions = Literal["auto", "both", "+x", "-x"]


def check_directions(directions: str) -> None:
    """Raise ``ValueError`` unless ``directions`` is one of :data:`DIRECTIONS`."""
    if not isinstance(directions, str) or directions not in DIRECTIONS:
        raise ValueError(f"directions must be 'auto', 'both', '+x' or '-x', got {directions!r}")


def load_directions(directions: str, mirror_symmetric: bool) -> tuple[int, ...]:
    """The directions to solve: ``"auto"`` is both unless the wall is
    mirror-symmetric (then ``+x`` alone), ``"both"``, ``"+x"`` or ``"-x"``.

    Raises:
        ValueError: an unknown value.
    """
    check_directions(directions)
    if directions == "auto":
        return (1,) if mirror_symmetric else (1, -1)
    if directions == "both":
        return (1, -1)
    return (1,) if directions == "+x" else (-1,)


def direction_sign(name: str) -> int:
    """``+1`` for ``"+x"``, ``-1`` for ``"-x"``."""
    return 1 if name == "+x" else -1


@dataclass(frozen=True)
class ContactCounts:
    """How many contacts of a mechanism stay closed, open and slide (0 each without a mechanism)."""

    closed: int = 0
    opening: int = 0
    sliding: int = 0

    @classmethod
    def of(cls, mechanism: Mechanism | None) -> ContactCounts:
        """The counts of ``mechanism`` (zeros for ``None``)."""
        return cls() if mechanism is None else cls(**mechanism.state_counts())


class RecordSources:
    """What a result's record (:mod:`micro.records`) reads beside the result's own fields, the same for
    both analyses: ``lambda`` per direction and the governing mechanism's contact states."""

    def direction_load_factors(self) -> dict[str, float]:
        """The load factor of each direction solved."""
        raise NotImplementedError

    @property
    def governing_mechanism(self) -> Mechanism | None:
        """The mechanism of the governing direction (``None`` without one)."""
        raise NotImplementedError

    @property
    def load_factor_plus(self) -> float:
        """``lambda`` of the ``+x`` direction (NaN when not solved)."""
        return self.direction_load_factors().get("+x", math.nan)

    @property
    def load_factor_minus(self) -> float:
        """``lambda`` of the ``-x`` direction (NaN when not solved, e.g. a mirror-symmetric wall)."""
        return self.direction_load_factors().get("-x", math.nan)

    @property
    def mechanism_contacts(self) -> ContactCounts:
        """The governing mechanism's contact states."""
        return ContactCounts.of(self.governing_mechanism)


@dataclass(frozen=True, eq=False)
class DirectionResult:
    """The analysis for one direction of the live load.

    Attributes:
        direction: ``"+x"`` or ``"-x"``.
        status: ``"optimal"`` / ``"converged"`` or the failure
            (:class:`micro.Status` values for the associative LP,
            :data:`micro.nonassociative.STATUSES` for the iterated one).
        load_factor: ``lambda`` (NaN unless it succeeded).
        iterations: solver iterations (associative LP) or non-associative
            LPs solved (iterated LP).
        seconds: wall time of the solve(s).
        normal, shear: final point forces (dimensional), or ``None``.
        mechanism: the collapse mechanism, or ``None``.
        message: a one-line explanation when it did not succeed.
        native_status: the back end's own status (associative LP).
        info: back-end facts (residual, raw load factor, ...; associative LP).
        sequence: a method's own diagnostics (the iterated LP's; ``None`` for the associative LP).
    """

    direction: str
    status: str
    load_factor: float
    iterations: int
    seconds: float
    normal: FloatArray | None = field(default=None, repr=False)
    shear: FloatArray | None = field(default=None, repr=False)
    mechanism: Mechanism | None = field(default=None, repr=False)
    message: str = ""
    native_status: str = ""
    info: Mapping[str, Any] = field(default_factory=dict, repr=False)
    sequence: Any = field(default=None, repr=False)

    def __post_init__(self) -> None:
        check_success(f"DirectionResult {self.direction}", self.status, self.load_factor)

    @property
    def converged(self) -> bool:
        """True when the iterated LP converged."""
        return self.status == "converged"

    @property
    def contact_states(self) -> tuple[str, ...] | None:
        """Contact state names of the mechanism (``None`` without one)."""
        if self.mechanism is None:
            return None
        return tuple(CONTACT_STATE_NAMES[i] for i in self.mechanism.contact_state)


@dataclass(frozen=True, eq=False)
class LimitResult(RecordSources):
    """Result of an associative limit analysis (governing direction first).

    Attributes:
        load_factor: governing (smallest) ``lambda``; NaN when any solve failed.
        direction: governing direction, ``"+x"`` or ``"-x"`` (``""`` on failure).
        status: ``"optimal"`` or the first failing direction's status.
        solver: back end name (e.g. ``"highs-ipm"``).
        build_seconds: wall time of the LP assembly plus the back end's setup.
        solve_seconds: wall time of all solves.
        blocks, contacts, points, variables, rows, nnz: problem sizes.
        iterations: solver iterations of the governing direction (of the
            first failing direction when a solve failed).
        total_iterations: solver iterations summed over the directions.
        normal, shear: point forces of the governing direction (dimensional,
            point ``2c + k`` is end ``k`` of contact ``c``).
        velocities: ``(blocks, 3)`` block velocities ``(u, v, omega)`` of the
            governing mechanism (scaled units; live work = 1).
        contact_state: ``(contacts,)`` state names ``closed``/``opening``/``sliding``.
        mirror_symmetric: the wall is its own mirror image (one direction solved).
        directions: per-direction results.
        message: a one-line explanation when the status is not optimal.
    """

    load_factor: float
    direction: str
    status: str
    solver: str
    build_seconds: float
    solve_seconds: float
    blocks: int
    contacts: int
    points: int
    variables: int
    rows: int
    nnz: int
    iterations: int
    total_iterations: int
    normal: FloatArray | None = field(repr=False)
    shear: FloatArray | None = field(repr=False)
    velocities: FloatArray | None = field(repr=False)
    contact_state: tuple[str, ...] | None = field(repr=False)
    mirror_symmetric: bool
    directions: tuple[DirectionResult, ...] = field(repr=False)
    message: str = ""

    def __post_init__(self) -> None:
        check_success("LimitResult", self.status, self.load_factor)

    @property
    def ok(self) -> bool:
        """True when the solve was optimal and ``load_factor`` is a number."""
        return self.status == Status.OPTIMAL.value and math.isfinite(self.load_factor)

    @property
    def mechanism(self) -> Mechanism | None:
        """The governing mechanism."""
        for d in self.directions:
            if d.direction == self.direction:
                return d.mechanism
        return None

    def by_direction(self, direction: str) -> DirectionResult:
        """The result for ``"+x"`` or ``"-x"``; for a mirror-symmetric wall
        ``"-x"`` is the mirror image of ``"+x"`` (same load factor).

        Raises:
            KeyError: that direction was not solved.
        """
        for d in self.directions:
            if d.direction == direction:
                return d
        if self.mirror_symmetric and self.directions:
            d = self.directions[0]
            return DirectionResult(direction=direction, status=d.status, load_factor=d.load_factor, iterations=0,
                                   seconds=0.0, native_status=d.native_status, info={"mirror_of": d.direction})
        raise KeyError(direction)

    def direction_load_factors(self) -> dict[str, float]:
        """The load factor of each direction solved."""
        return {d.direction: d.load_factor for d in self.directions}

    @property
    def governing_mechanism(self) -> Mechanism | None:
        """The governing mechanism (:attr:`mechanism`)."""
        return self.mechanism

    def to_record(self) -> AssociativeRecord:
        """The flat record of this result: a read-only mapping of its fields; ``.to_dict()`` is its JSON form
        (see :mod:`micro.records`)."""
        return record_of(AssociativeRecord, self)

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary: the record (:meth:`to_record`, whose ``*_contacts``
        keys are the mechanism's contact states, 0 without one) with the
        directions as a nested object."""
        record = self.to_record()
        return {**record.to_dict(),
                "directions": {d.direction: record_of(AssociativeDirection, d).to_dict() for d in self.directions}}
