"""The flat record of a macro result: what a table, a cache or a JSON file keeps of it.

A frozen dataclass that reads as a mapping of its fields (``rec["hinge_storey"]``,
``dict(rec)``); :meth:`MacroRecord.to_dict` gives its JSON form.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import asdict, dataclass, fields
from typing import Any


def _json_number(x: float) -> float | None:
    return x if math.isfinite(x) else None


def _number(x: float | None) -> float:
    return math.nan if x is None else float(x)


@dataclass(frozen=True)
class MacroRecord(Mapping[str, Any]):
    """A :class:`macro.MacroResult` without its wall and its per-storey terms: flat, frozen, a read-only
    mapping of its fields (``rec["load_factor"]``); :meth:`to_dict` is its JSON form.

    Attributes:
        load_factor: the least of ``rocking_load_factor``, ``f`` and ``overturning_load_factor``.
        rocking_load_factor: minimum of Eq. (10).
        sliding_load_factor: ``lambda_s`` of Eq. (12) at the optimum crack.
        overturning_load_factor: rigid overturning above a storey's base (:mod:`macro.bounds`).
        tan_alpha_c: crack slope at the optimum; ``alpha_c_deg`` the angle.
        tan_alpha_c_star: slope of the stepped crack (Eq. 9); ``alpha_c_star_deg`` the angle.
        alpha_b_deg: ``atan(v/b)``; ``alpha_ratio = alpha_c/alpha_b``.
        hinge_storey: storey whose base holds the hinge (1 = top).
        hinge_load_factors: the minimum of Eq. (10) for the hinge at storeys 1, 2, ...
        mechanism: one of :data:`macro.bounds.MECHANISMS`.
        status: ``"optimal"`` or ``"numerical_error"`` (``load_factor`` NaN).
        solve_seconds: wall-clock time of the solve.
    """

    load_factor: float
    rocking_load_factor: float
    sliding_load_factor: float
    overturning_load_factor: float
    tan_alpha_c: float
    alpha_c_deg: float
    tan_alpha_c_star: float
    alpha_c_star_deg: float
    alpha_b_deg: float
    alpha_ratio: float
    hinge_storey: int
    hinge_load_factors: tuple[float, ...]
    mechanism: str
    status: str
    solve_seconds: float

    def __post_init__(self) -> None:
        if self.status == "optimal" and not (math.isfinite(self.load_factor) and self.load_factor > 0.0):
            raise ValueError(f"an optimal macro record needs a finite positive load factor, got {self.load_factor!r}")

    def __getitem__(self, key: str) -> Any:
        """``rec[name]``: the field ``name`` (as in memory: NaN, tuples).

        Raises:
            KeyError: ``name`` is not a field.
        """
        if key not in self.__dataclass_fields__:
            raise KeyError(key)
        return getattr(self, key)

    def __iter__(self) -> Iterator[str]:
        """The field names, in order."""
        return (f.name for f in fields(self))

    def __len__(self) -> int:
        return len(fields(self))

    def to_dict(self) -> dict[str, Any]:
        """The JSON form: a dictionary of plain values (non-finite numbers as ``None``, tuples as lists)."""
        d = asdict(self)
        for f in fields(self):
            if f.type == "float":
                d[f.name] = _json_number(d[f.name])
        d["hinge_load_factors"] = [_json_number(x) for x in self.hinge_load_factors]
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> MacroRecord:
        """The record :meth:`to_dict` wrote."""
        values: dict[str, Any] = {f.name: (_number(d[f.name]) if f.type == "float" else d[f.name]) for f in fields(cls)}
        values["hinge_load_factors"] = tuple(_number(x) for x in d["hinge_load_factors"])
        return cls(**values)
