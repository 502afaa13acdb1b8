"""The recipe of one run: the user's options and the tuning, with the choices resolved for one wall.

:func:`recipe_for` composes :class:`~micro.nonassociative.options.NonAssociativeOptions`
and :class:`~micro.nonassociative.tuning.Tuning` into a :class:`Recipe` (the
selection, the relaxation and the fusing decided for the wall's size), which
is what the modules of the iterated LP read. With no options and no tuning it
is the report's method.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from micro.backends.roles import ROLE_NAMES
from micro.nonassociative.options import NonAssociativeOptions
from micro.nonassociative.tuning import SelectionName, Tuning


@dataclass(frozen=True)
class LPProgress:
    """One LP as it finishes, for a progress display (``progress=`` of
    :func:`micro.solve_nonassociative`).

    Attributes:
        direction: ``"+x"`` or ``"-x"``.
        stage: ``"vertex"``, ``"proximal"``, ``"fused"`` (a
            sequence of the iterated LP) or ``"lowest"`` (the descent).
        lp: the LP's number in its stage (0: the associative LP).
        load_factor: its ``lambda`` (NaN when it failed or has none).
        step: ``max |n_k - n_(k-1)|`` relative to ``max n_k`` (NaN when not defined).
        algorithm: how it was solved.
        seconds: its wall time.
    """

    direction: str
    stage: str
    lp: int
    load_factor: float
    step: float
    algorithm: str
    seconds: float


#: A callback that receives one :class:`LPProgress` per LP.
Progress = Callable[[LPProgress], None]


@dataclass(frozen=True)
class Recipe:
    """What the iterated LP runs on one wall: the user's options and the tuning as given, and the few
    choices resolved for this wall and this sequence (what the modules of the iterated LP read).

    Attributes:
        options: the user's :class:`~micro.nonassociative.options.NonAssociativeOptions`.
        tuning: the research knobs (:class:`~micro.nonassociative.tuning.Tuning`).
        selection: this sequence's selection (``tuning.selection`` resolved for the scheme; the
            pipeline sets ``"vertex"`` or ``"proximal"`` for each sequence of ``"vertex+proximal"``).
        beta: the relaxation (``tuning.relaxation`` or the scheme's default).
        fuse, continuation: ``tuning.fuse`` and ``tuning.continuation`` resolved for the wall's size.
        max_iterations: this sequence's cap on LPs (``options.max_iterations``; the proximal
            retry's ``tuning.retry_iterations``).
        lowest: whether the descent runs (``options.lowest``).
        progress: the caller's callback (not part of the method).
    """

    options: NonAssociativeOptions
    tuning: Tuning
    selection: SelectionName
    beta: float
    fuse: bool
    continuation: bool
    max_iterations: int
    lowest: bool
    progress: Progress | None = field(default=None, repr=False, compare=False)

    @property
    def user_limit(self) -> float:
        """The user's ``time_limit`` per LP in seconds, ``inf`` for none."""
        return self.options.user_limit

    def tell(self, event: LPProgress) -> None:
        """Pass ``event`` to the progress callback, if any."""
        if self.progress is not None:
            self.progress(event)

    def solver_description(self) -> str:
        """Which solver does what in the iterated LP, e.g. ``"clarabel (start,
        certificate) + highs-simplex (iterated) + highs-ipm (cold check)"``."""
        t, interior, persistent = self.tuning, ROLE_NAMES["interior"], ROLE_NAMES["persistent"]
        roles = [(interior if t.start == "interior" else f"{persistent}-ipm+crossover", "start")]
        if t.certify or t.mechanism_band:
            roles.append((interior, "certificate"))
        roles.append((f"{persistent}-simplex", "iterated" + (", fused" if self.fuse else "")))
        roles.append((f"{persistent}-ipm", "cold check"))
        by_solver: dict[str, list[str]] = {}
        for solver, role in roles:
            by_solver.setdefault(solver, []).append(role)
        return " + ".join(f"{solver} ({', '.join(r)})" for solver, r in by_solver.items())

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: the options and the knobs, with the resolved values in place of theirs."""
        resolved = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                    if f.name not in ("options", "tuning", "progress")}
        return {**self.options.as_dict(), **self.tuning.as_dict(), **resolved, "relaxation": self.beta}


def recipe_for(blocks: int, options: NonAssociativeOptions | None = None, tuning: Tuning | None = None,
               progress: Progress | None = None) -> Recipe:
    """The :class:`Recipe` of a wall of ``blocks`` blocks."""
    o = options or NonAssociativeOptions()
    t = tuning or Tuning()
    large = t.large_wall(blocks)
    return Recipe(o, t, selection=t.resolved_selection, beta=t.beta, fuse=large if t.fuse is None else t.fuse,
                  continuation=large if t.continuation is None else t.continuation,
                  max_iterations=o.max_iterations, lowest=o.lowest, progress=progress)
