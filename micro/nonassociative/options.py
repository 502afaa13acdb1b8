"""What a user of :func:`micro.solve_nonassociative` may set: :class:`NonAssociativeOptions`.

The method itself (scheme, selections, fusing, tolerances) is not an option:
its defaults are the report's method, and the research knobs live apart in
:class:`~micro.nonassociative.tuning.Tuning` (``docs/micro/tuning.md``).
Nor is the search for the global minimum: its caller composes it after the
run (:func:`micro.global_search.solve_global` with ``start=result``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from micro.backends.base import check_integer, finite_real
from micro.results import Directions, check_directions

#: Default of :attr:`NonAssociativeOptions.lowest_budget`: LPs per direction.
#: The descent (its own rules end it after one accepted move) solved at most
#: 74 LPs on the 178 walls of ``xcheck stability --lowest`` (Set 13 with a half
#: first course); on the walls of Table 5 it solves 4-61.
LOWEST_BUDGET = 100


@dataclass(frozen=True)
class NonAssociativeOptions:
    """Options of :func:`micro.solve_nonassociative` (validated on construction).

    Attributes:
        directions: ``"auto"`` (both unless mirror-symmetric), ``"both"``,
            ``"+x"`` or ``"-x"``.
        max_iterations: cap on the non-associative LPs of a direction's first
            sequence; a sequence that reaches it ends ``max_iterations``.
        time_limit: optional wall-clock limit per LP in seconds (``None``:
            none); an LP it stops ends the run with status ``time_limit``,
            no final answer.
        max_seconds: optional wall-clock stop per direction (``None``: none);
            a sequence it stops has status ``time_limit``. No other decision
            depends on time: the same wall gives the same numbers everywhere.
        lowest: after a converged run, descend to the lowest certified
            collapse state (``lowest_load_factor``, the value to quote;
            :mod:`micro.nonassociative.descent.lowest`); ``False``: the iterated
            LP's state only.
        lowest_budget: the most LPs the descent may solve per direction
            (one more gives the band of the state it returns); a descent
            that spends it returns the lowest certified state found so far
            (``lowest_stop="budget"``). It counts LPs, not seconds: the same
            wall stops at the same state on every machine.

    Raises:
        ValueError: a bad option (the message names it).
    """

    directions: Directions = "auto"
    max_iterations: int = 100
    time_limit: float | None = None
    max_seconds: float | None = None
    lowest: bool = True
    lowest_budget: int = LOWEST_BUDGET

    def __post_init__(self) -> None:
        check_directions(self.directions)
        check_integer("max_iterations", self.max_iterations, 2)
        for name in ("time_limit", "max_seconds"):
            tl = getattr(self, name)
            if tl is not None and ((x := finite_real(tl)) is None or x <= 0):
                raise ValueError(f"{name} must be a positive number of seconds, got {tl!r}")
            if tl is not None:
                object.__setattr__(self, name, float(tl))
        check_integer("lowest_budget", self.lowest_budget, 0)
        if not isinstance(self.lowest, (bool, np.bool_)):
            raise ValueError(f"lowest must be True or False, got {self.lowest!r}")
        object.__setattr__(self, "lowest", bool(self.lowest))

    @property
    def user_limit(self) -> float:
        """:attr:`time_limit` in seconds, ``inf`` for none."""
        return float(self.time_limit) if self.time_limit is not None else math.inf

    def with_overrides(self, **overrides: Any) -> NonAssociativeOptions:
        """A copy with some options changed (validated again).

        Raises:
            TypeError: an unknown option name (the message lists the options).
        """
        unknown = sorted(set(overrides) - set(OPTION_NAMES))
        if unknown:
            raise TypeError(f"unknown option(s) {', '.join(unknown)}; the options are {', '.join(OPTION_NAMES)} "
                            "(research knobs: tuning=micro.nonassociative.Tuning(...))")
        return dataclasses.replace(self, **overrides)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return dataclasses.asdict(self)


#: The names of the fields of :class:`NonAssociativeOptions`.
OPTION_NAMES: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(NonAssociativeOptions))
