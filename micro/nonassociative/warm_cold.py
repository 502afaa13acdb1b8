"""When the iterated LP solves an iterate warm and when cold: :class:`WarmColdPolicy`.

A warm dual simplex from the last basis is the cheap way to the next iterate
on most walls; on large ones a warm run can cost more than a cold solve
(interior point + crossover + dual simplex), and a run that wanders is stuck.
The policy counts simplex iterations per equilibrium row, never seconds: a
loaded or slower machine follows the same path to the same numbers. The loop
(:class:`~micro.nonassociative.iteration.LPSequence`) asks it, for every
iterate, whether to go cold (:meth:`WarmColdPolicy.cold`) and how many
simplex iterations a warm run may take (:attr:`WarmColdPolicy.warm_limit`),
and tells it the work of every run (:meth:`WarmColdPolicy.account`,
:meth:`WarmColdPolicy.slow_warm`). The measurements behind the constants are on
the research pages each names; the iterated LP's warm and cold runs are
described on the research page on the iterated LP (``docs/research/``).
"""

from __future__ import annotations

import math

from micro.nonassociative.selections import Selection

#: The algorithm names of a cold and of a warm run (the history's ``algorithm``).
COLD = "ipm+crossover+simplex"
WARM = "simplex-warm"

# The warm/cold policy: every decision is taken on deterministic work measures
# (simplex and interior-point iteration counts, LP counts), never on seconds:
# a loaded or slower machine follows the same path to the same numbers.
#: On large walls a warm dual simplex can cost more than a cold solve, on
#: walls of about a thousand blocks it is several times faster
#: (the research page on the lowest certified state (``docs/research/``),
#: the research page on the non-associative profile (``docs/research/``)). Scheme (a) solves
#: an iterate cold while the last warm run took more than this many simplex
#: iterations per equilibrium row of the wall ...
COLD_SWITCH_PIVOTS = 2.0
#: ... and goes back to warm after this many cold iterates in a row, a number
#: doubled each time the warm run after a cold streak is slow again (or stopped
#: at its limit below).
COLD_STREAK = 3
#: A warm run that takes more than this many simplex iterations per
#: equilibrium row is stuck (a small infeasible LP took many times its usual work to be
#: declared so: the research page on the re-cut of the non-associative package (``docs/research/``)): it is stopped and
#: recovered ...
WARM_LIMIT_PIVOTS = 10.0
#: ... with at least this many iterations on small walls.
MIN_WARM_LIMIT = 20_000


class WarmColdPolicy:
    """The warm/cold policy of one sequence (module docstring).

    Scheme (a) solves an iterate cold while the last warm run took more than
    :attr:`cold_switch` simplex iterations, for at most :attr:`streak_length`
    cold iterates in a row (:data:`COLD_STREAK`, doubled each time the warm run
    after a cold streak is slow again, or stopped at :attr:`warm_limit`: on
    Set 10 warm runs after a cold streak were several times slower than cold
    ones, the research page on the re-cut of the non-associative package (``docs/research/``)).

    Args:
        n_eq: equilibrium rows of the LP (the counts are per row).
        selection: the sequence's selection: whether it may go cold at all,
            and the warm limit it allows.
    """

    def __init__(self, n_eq: int, selection: Selection) -> None:
        self.selection = selection
        self.cold_switch = COLD_SWITCH_PIVOTS * n_eq
        self.warm_limit = selection.warm_limit(max(MIN_WARM_LIMIT, math.ceil(WARM_LIMIT_PIVOTS * n_eq)))
        self.warm_pivots, self.cold_streak = 0, 0
        self.streak_length = COLD_STREAK

    def cold(self, k: int) -> bool:
        """Whether iterate ``k`` is solved cold (the first always is)."""
        return k == 1 or (self.selection.may_go_cold and self.warm_pivots > self.cold_switch
                          and self.cold_streak < self.streak_length)

    def account(self, k: int, pivots: int, *, warm: bool, cold: bool) -> None:
        """Book a good iterate ``k`` solved in ``pivots`` simplex iterations, warm or cold."""
        if warm:
            self.slow_warm(pivots)
        elif cold:
            self.cold_streak += k > 1

    def slow_warm(self, pivots: int) -> None:
        """Book a warm run of ``pivots`` simplex iterations: a slow one right
        after a cold streak doubles the next streak."""
        if pivots > self.cold_switch and self.cold_streak >= self.streak_length:
            self.streak_length *= 2
        self.warm_pivots, self.cold_streak = pivots, 0
