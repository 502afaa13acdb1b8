"""The descent's result: the lowest certified state of one direction, and its record and JSON parts.

A types module (it imports no module that computes): :mod:`.lowest` fills
:class:`LowestDirection`; :class:`micro.NonAssociativeResult` holds one per
converged direction and reads its record fields (:func:`descent_summary`) and
its summary's entries (:class:`DescentEntry`) from them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from micro.columns import Band, FlatRecord, LoadFactor, Seconds, column
from micro.limit_result import DirectionResult

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
        residuals: its :func:`~micro.nonassociative.final_checks.verify_collapse_state`.
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

    @property
    def contact_states(self) -> dict[str, int] | None:
        """The contacts of its mechanism in each state (``None`` without a state)."""
        mech = self.state.mechanism if self.state is not None else None
        return mech.state_counts() if mech is not None else None


@dataclass(frozen=True)
class DescentSummary:
    """The descent over the directions, as the record's ``lowest_*`` fields read it
    (:class:`micro.records.NonAssociativeRecord`): the lowest state's λ, direction, band and moves, the LPs
    and seconds summed over the directions, ``status`` ``"found"`` or ``"failed"`` (some direction has no
    state) and ``stop`` ``"finished"``, ``"budget"`` (one spent its budget) or ``"target"`` (one stopped
    below the options' ``stop_below``); ``""`` for both when the descent did not run."""

    load_factor: float = math.nan
    direction: str = ""
    band: tuple[float, float] | None = None
    moves: int = 0
    lps: int = 0
    seconds: float = 0.0
    status: str = ""
    stop: str = ""


def descent_summary(governing: LowestDirection | None, lowest: tuple[LowestDirection, ...]) -> DescentSummary:
    """The :class:`DescentSummary` of the descents ``lowest`` (empty: it did not run), ``governing`` the
    lowest state over the directions (``None`` without one)."""
    if not lowest:
        return DescentSummary()
    stops = {low.stop for low in lowest}
    stop = TARGET if TARGET in stops else BUDGET if BUDGET in stops else FINISHED
    lps, seconds = sum(low.lps for low in lowest), sum(low.seconds for low in lowest)
    if governing is None:
        return DescentSummary(lps=lps, seconds=seconds, status=FAILED, stop=stop)
    return DescentSummary(governing.load_factor, governing.direction, governing.band, len(governing.moves), lps,
                          seconds, FOUND, stop)


@dataclass(frozen=True)
class DescentEntry(FlatRecord):
    """One direction's descent, an entry of the summary's ``lowest`` (made from a :class:`LowestDirection`)."""

    direction: str = column("The load direction.", schema={"enum": ["+x", "-x"]})
    status: str = column("found (an exact state, checked) or failed.", schema={"enum": [FOUND, FAILED]})
    load_factor: LoadFactor = column("lambda of the lowest certified state (null when failed).")
    band: Band = column("[lambda, greatest lambda] of the collapse states with its mechanism (null when failed).")
    path: tuple[LoadFactor, ...] = column(
        "lambda of the iterated LP's state, of its band's lower end after the polish (when lower) and after "
        "every accepted move.")
    moves: tuple[str, ...] = column("The accepted proposals (their origin).")
    origin: str = column("How the state was found.")
    lps: int = column("LPs solved by the descent.")
    budget: int = column("The most LPs it could solve.")
    stop: str = column("finished (by its own rules), budget (it spent its budget: the lowest state found so "
                       "far) or target (the first state below the options' stop_below).",
                       schema={"enum": [FINISHED, BUDGET, TARGET]})
    seconds: Seconds = column("Its wall time.")
    contact_states: dict[str, int] | None = column(
        "closed, opening, sliding: the contacts of its mechanism in each state (null without a state).")
    residuals: dict[str, float] = column("Its residuals of the collapse conditions (verify_collapse_state).")
    message: str = column("Why it failed.")
