"""The comparison record: one method's typed result on one wall, with its failure mode."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from comparison.domain.failure import FailureMode
from comparison.domain.wall_mechanism import LocalRecord
from comparison.runner.macro_record import MacroRecord
from comparison.runner.methods import Method
from micro.records import AssociativeRecord, NonAssociativeRecord

#: The typed result record of each method kind.
ResultRecord = MacroRecord | AssociativeRecord | NonAssociativeRecord
RESULT_TYPES: dict[str, type[ResultRecord]] = {
    "macro": MacroRecord,
    "micro-assoc": AssociativeRecord,
    "micro-nonassoc": NonAssociativeRecord,
}

#: Why a record holds no result: the micro wall cannot be built, or the report left the method out.
Skip = Literal["", "not_applicable", "not_run"]


@dataclass(frozen=True)
class MechanismRecord:
    """The collapse mechanism of a micro record, for the figures.

    Attributes:
        velocities: ``(n_blocks, 3)`` block velocities ``(u, v, omega)``.
        direction: the live-load direction it belongs to, ``"+x"`` or ``"-x"``.
    """

    velocities: NDArray[np.float64]
    direction: str


@dataclass(frozen=True)
class Record:
    """One method's result on one wall.

    Attributes:
        wall: the wall's name.
        method: the method.
        seconds: wall time of the computation (as computed, also when read from the cache).
        result: the typed record of the result (``None`` when skipped).
        failure: the micro mechanism read in the macro model's terms (``None``
            for the macro model, a failed solve, or a mechanism that could not be read).
        skipped: ``"not_applicable"`` (the micro wall cannot be built) or
            ``"not_run"`` (left out of the report), else ``""``.
        message: why it was skipped, or why the mechanism could not be read.
        cached: True when read from the cache.
        local: the sliver's local mechanism that governs the micro result, and the held wall's value beside it
            (:func:`comparison.domain.wall_mechanism.solve_wall_mechanism`; ``None`` when nothing local governs).
    """

    wall: str
    method: Method
    seconds: float
    result: ResultRecord | None = None
    failure: FailureMode | None = None
    skipped: Skip = ""
    message: str = ""
    cached: bool = False
    local: LocalRecord | None = None

    @property
    def load_factor(self) -> float:
        """The result's load factor, the value to quote (NaN when skipped or failed): for the
        non-associative method the lowest certified collapse state where the descent found one,
        else the iterated LP's (:attr:`iterated_load_factor`)."""
        return math.nan if self.result is None else self.result.load_factor

    @property
    def iterated_load_factor(self) -> float:
        """The non-associative iterated LP's own load factor (NaN for the other methods, or when it failed)."""
        return self.result.iterated_load_factor if isinstance(self.result, NonAssociativeRecord) else math.nan

    @property
    def status(self) -> str:
        """The result's status, or why it was skipped."""
        return self.skipped if self.result is None else self.result.status

    @property
    def micro(self) -> AssociativeRecord | NonAssociativeRecord | None:
        """The micro result, if any."""
        return self.result if isinstance(self.result, (AssociativeRecord, NonAssociativeRecord)) else None

    @property
    def nonassoc(self) -> NonAssociativeRecord | None:
        """The non-associative result, if any."""
        return self.result if isinstance(self.result, NonAssociativeRecord) else None

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (the typed parts by their own ``to_dict``)."""
        return {
            "wall": self.wall,
            "method": asdict(self.method),
            "seconds": self.seconds,
            "result": None if self.result is None else self.result.to_dict(),
            "failure": None if self.failure is None else self.failure.to_dict(),
            "skipped": self.skipped,
            "message": self.message,
            "local": None if self.local is None else self.local.to_dict(),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any], *, cached: bool = False) -> Record:
        """The record :meth:`to_dict` wrote."""
        m = d["method"]
        method = Method(**{**m, "tuning": tuple(tuple(pair) for pair in m.get("tuning", ()))})
        result = None if d["result"] is None else RESULT_TYPES[method.kind].from_dict(d["result"])
        failure = None if d["failure"] is None else FailureMode.from_dict(d["failure"])
        local = None if d.get("local") is None else LocalRecord.from_dict(d["local"])
        return cls(d["wall"], method, d["seconds"], result, failure, d["skipped"], d["message"], cached, local)
