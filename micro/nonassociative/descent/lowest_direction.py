"""The descent's result: the lowest certified state of one direction, and its record and JSON parts.

A types module (it imports no module that computes): :mod:`.lowest` fills
:class:`LowestDirection`; :class:`micro.NonAssociativeResult` holds one per
converged direction and writes its record fields (:func:`lowest_fields`) and
its summary (:func:`lowest_summary`) from them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from micro.limit_result import DirectionResult
from micro.records import json_number

#: Values of :attr:`LowestDirection.status`.
FOUND, FAILED = "found", "failed"
#: Values of :attr:`LowestDirection.stop`.
FINISHED, BUDGET, TARGET = "finished", "budget", "target"


@dataclass(frozen=True, eq=False)
class LowestDirection:
    """The lowest certified state of one load direction.

    Attributes:
        direction: ``"+x"`` or ``"-x"``.
        status: ``"found"`` (an exact state, checked) or ``"failed"``.
        load_factor: its ``lambda`` (NaN when failed).
        band: ``(lambda, greatest lambda)`` of the collapse states with its
            mechanism (``None`` when failed).
        path: ``lambda`` of the iterated LP's state, of its band's lower end
            after the polish (when lower) and after every accepted move.
        moves: the accepted proposals (their origin).
        lps: LPs solved by the descent.
        budget: the most LPs it could solve (module docstring).
        stop: ``"finished"`` (it ended by its own rules), ``"budget"`` (it
            spent its budget: the lowest state found so far) or ``"target"``
            (it stopped at the first state below the options' ``stop_below``).
        seconds: its wall time.
        state: the state as a direction result (dimensional forces, mechanism,
            contact states; ``None`` when failed).
        residuals: its :func:`~micro.nonassociative.checks.verify_collapse_state`.
        origin: how the state was found.
        message: why it failed.
    """

    direction: str
    status: str
    load_factor: float
    band: tuple[float, float] | None
    path: tuple[float, ...]
    moves: tuple[str, ...]
    lps: int
    budget: int
    stop: str
    seconds: float
    state: DirectionResult | None = field(repr=False)
    residuals: dict[str, float] = field(repr=False)
    origin: str = ""
    message: str = ""

    @property
    def found(self) -> bool:
        """True when an exact state was found."""
        return self.status == FOUND


def lowest_fields(governing: LowestDirection | None, lowest: tuple[LowestDirection, ...]) -> dict[str, Any]:
    """The record fields of the descent (:class:`micro.NonAssociativeRecord`).

    Args:
        governing: the lowest state over the directions (``None`` without one).
        lowest: the descent of every direction (empty when it did not run).

    Returns:
        The ``lowest_*`` fields (:class:`micro.records.NonAssociativeRecord`); LPs and seconds summed over
        the directions, ``"failed"`` when some direction has no state, ``"budget"`` when one spent its budget,
        ``"target"`` when one stopped below the options' ``stop_below``.
    """
    status = "" if not lowest else FOUND if governing is not None else FAILED
    stops = {low.stop for low in lowest}
    stop = "" if not lowest else TARGET if TARGET in stops else BUDGET if BUDGET in stops else FINISHED
    return {
        "lowest_load_factor": governing.load_factor if governing is not None else math.nan,
        "lowest_direction": governing.direction if governing is not None else "",
        "lowest_band": governing.band if governing is not None else None,
        "lowest_moves": len(governing.moves) if governing is not None else 0,
        "lowest_lps": sum(low.lps for low in lowest),
        "lowest_seconds": sum(low.seconds for low in lowest),
        "lowest_status": status,
        "lowest_stop": stop,
    }


def lowest_summary(low: LowestDirection) -> dict[str, Any]:
    """One direction's descent as JSON-ready data (NaN -> ``None``; ``contact_states`` ``None`` without a state)."""
    num = json_number
    mech = low.state.mechanism if low.state is not None else None
    return {
        "direction": low.direction, "status": low.status, "load_factor": num(low.load_factor),
        "band": None if low.band is None else [num(x) for x in low.band], "path": [num(x) for x in low.path],
        "moves": list(low.moves), "origin": low.origin, "lps": low.lps, "budget": low.budget,
        "stop": low.stop, "seconds": low.seconds,
        "contact_states": mech.state_counts() if mech is not None else None,
        "residuals": {k: num(v) for k, v in low.residuals.items()}, "message": low.message,
    }
