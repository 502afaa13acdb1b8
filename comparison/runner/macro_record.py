"""The record of a macro result: what the runner, the cache and the tables keep of :class:`macro.MacroResult`.

Declared field by field with the suite's one machinery (:func:`micro.columns.column`: a field's type,
description and source, the JSON form and the schema from that declaration), as the micro records are:
the result's wall and its per-storey terms stay on the result; every field here is read from the result
by its name (``hinge_load_factors``: :attr:`macro.MacroResult.hinge_load_factors`). ``macro`` imports
neither ``micro`` nor ``comparison``, so its record lives here, where both models are composed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import macro
from micro.columns import FlatRecord, LoadFactor, Seconds, column, record_of


@dataclass(frozen=True)
class MacroRecord(FlatRecord):
    """A :class:`macro.MacroResult` without its wall and its per-storey terms: flat, frozen, a read-only
    mapping of its fields (``rec["load_factor"]``); :meth:`to_dict` is its JSON form."""

    load_factor: LoadFactor = column("The least of rocking_load_factor, f and overturning_load_factor.")
    rocking_load_factor: LoadFactor = column("The minimum of Eq. (10).")
    sliding_load_factor: LoadFactor = column("lambda_s of Eq. (12) at the optimum crack.")
    overturning_load_factor: LoadFactor = column("Rigid overturning above a storey's base (macro.bounds).")
    tan_alpha_c: float = column("The crack's slope at the optimum.")
    alpha_c_deg: float = column("The crack's angle at the optimum (degrees).")
    tan_alpha_c_star: float = column("The slope of the stepped crack (Eq. 9).")
    alpha_c_star_deg: float = column("The stepped crack's angle (degrees).")
    alpha_b_deg: float = column("atan(v/b) (degrees).")
    alpha_ratio: float = column("alpha_c / alpha_b.")
    hinge_storey: int = column("The storey whose base holds the hinge (1 = top).")
    hinge_load_factors: tuple[LoadFactor, ...] = column("The minimum of Eq. (10) for the hinge at storeys 1, 2, ...")
    mechanism: str = column("One of macro.bounds.MECHANISMS.")
    status: str = column("optimal, or numerical_error (load_factor null).")
    solve_seconds: Seconds = column("Wall-clock time of the solve.")

    def __post_init__(self) -> None:
        if self.status == "optimal" and not (math.isfinite(self.load_factor) and self.load_factor > 0.0):
            raise ValueError(f"an optimal macro record needs a finite positive load factor, got {self.load_factor!r}")


def macro_record(result: macro.MacroResult) -> MacroRecord:
    """The :class:`MacroRecord` of ``result``."""
    return record_of(MacroRecord, result)
