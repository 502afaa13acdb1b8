"""What a user of :func:`micro.solve_nonassociative` may set: :class:`NonAssociativeOptions`.

The method itself (scheme, selections, fusing, tolerances) is not an option:
its defaults are the report's method, and the research knobs live apart in
:class:`~micro.nonassociative.tuning.Tuning` (``docs/micro/tuning.md``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from micro.backends.base import check_integer, finite_real
from micro.nonassociative.global_search.results import GlobalOptions
from micro.results import Directions, check_directions

#: The descent to the lowest certified state may solve at most
#: ``(LOWEST_ROW_LPS + lowest_budget * (the direction's iterated LPs)) / (equilibrium rows)``
#: LPs per direction (:mod:`micro.nonassociative.lowest`): a work budget in LPs
#: times rows, so many LPs on a small wall and few on a large one, whose LPs
#: cost more. With 20,000 and 500 every descent of ``xcheck stability
#: --lowest`` (178 walls, up to 294 blocks, up to 86 LPs) finishes, and the
#: walls of Table 5 get 7 (1,230 blocks, 9 iterated LPs) to 17 LPs (Set 2, 82).
LOWEST_ROW_LPS = 20_000
#: Default of :attr:`NonAssociativeOptions.lowest_budget` (LPs times rows per iterated LP).
LOWEST_BUDGET = 500.0
#: With ``lowest=None`` (the default) the descent runs on walls of at most this
#: many blocks. Above it a descent LP is a cold interior point + crossover of
#: 2-9 s on 1,230 blocks (against 0.3-0.6 s for a warm LP of the iterated LP),
#: and the budget's few LPs cost up to several times the iterated LP: measured
#: on main 2026-11-25 (CPU s, one process, iterated LP / with the descent):
#: Set 5 (450 blocks) 0.9 / 4.4, Set 8 (450) 4.5 / 29.3, Ref (1,230) 7.7 /
#: 36.6; in two report runs on one host (wall s) Set 1 3.7 / 27.6, Set 9
#: (1,830) 540 / 634, Set 10 (3,630) 752 / 970: about 530 CPU s more over the
#: report (+26 %), and ratios to the associative solve of 60-90x instead of
#: 10-20x on the 1,230-block walls that converge with vertices. Every wall of
#: ``xcheck stability --lowest`` (up to 294 blocks) and of Table 7 is below it.
LOWEST_AUTO_BLOCKS = 300


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
            collapse state (``lowest_load_factor``; :mod:`micro.nonassociative.lowest`):
            ``True`` always, ``False`` never, ``None`` (the default) on walls
            of at most :data:`LOWEST_AUTO_BLOCKS` blocks.
        lowest_budget: the descent's budget per direction, in LPs times
            equilibrium rows per LP of the direction's iterated LP (plus
            :data:`LOWEST_ROW_LPS`; divided by the wall's rows it is a number
            of LPs); a descent that spends it returns the lowest certified
            state found so far (``lowest_stop="budget"``). No clock decides it.
        global_: the search for the global minimum by branch and bound
            (:mod:`micro.nonassociative.global_search`; walls of a few
            blocks): ``False`` (the default) none, ``True`` with the
            defaults of :class:`~micro.nonassociative.GlobalOptions`, or a
            ``GlobalOptions`` with every setting of the search (time and node
            limits, gap, big-M policy, HiGHS or SCIP). Stored as the
            ``GlobalOptions`` or ``None``.

    Raises:
        ValueError: a bad option (the message names it).
    """

    directions: Directions = "auto"
    max_iterations: int = 100
    time_limit: float | None = None
    max_seconds: float | None = None
    lowest: bool | None = None
    lowest_budget: float = LOWEST_BUDGET
    global_: GlobalOptions | bool | None = None

    def __post_init__(self) -> None:
        check_directions(self.directions)
        check_integer("max_iterations", self.max_iterations, 2)
        for name in ("time_limit", "max_seconds"):
            tl = getattr(self, name)
            if tl is not None and ((x := finite_real(tl)) is None or x <= 0):
                raise ValueError(f"{name} must be a positive number of seconds, got {tl!r}")
            if tl is not None:
                object.__setattr__(self, name, float(tl))
        lb = self.lowest_budget
        if (x := finite_real(lb)) is None or x < 0:
            raise ValueError(f"lowest_budget must be a finite number >= 0, got {lb!r}")
        object.__setattr__(self, "lowest_budget", float(self.lowest_budget))
        g = self.global_
        if not isinstance(g, (GlobalOptions, bool, np.bool_)) and g is not None:
            raise ValueError(f"global_ must be True, False or a GlobalOptions, got {g!r}")
        object.__setattr__(self, "global_", GlobalOptions() if g is True or g is np.True_ else g or None)
        if self.lowest is not None and not isinstance(self.lowest, (bool, np.bool_)):
            raise ValueError(f"lowest must be True, False or None (by the wall's size), got {self.lowest!r}")
        if self.lowest is not None:
            object.__setattr__(self, "lowest", bool(self.lowest))

    def lowest_on(self, blocks: int) -> bool:
        """Whether the descent runs on a wall of ``blocks`` blocks (:attr:`lowest`)."""
        return self.lowest if self.lowest is not None else blocks <= LOWEST_AUTO_BLOCKS

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
