"""The recipe of one run: the user's options and the tuning, resolved for one wall.

:func:`recipe_for` turns :class:`~micro.nonassociative.options.NonAssociativeOptions`
and :class:`~micro.nonassociative.tuning.Tuning` into a flat :class:`Recipe`
(the selection and the fusing decided for the wall's size), which is what the
modules of the iterated LP read. With no options and no tuning it is the
report's method.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

from micro.nonassociative.options import NonAssociativeOptions
from micro.nonassociative.tuning import SelectionName, Tuning
from micro.results import Directions


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
    """What the iterated LP runs (fields: those of the options and the tuning).

    ``selection``, ``fuse`` and ``continuation`` are resolved (no ``None``);
    ``relaxation`` is the ``beta`` used. ``progress`` is the caller's callback
    (not part of the method).
    """

    scheme: Literal["a", "b"]
    selection: SelectionName
    relaxation: float
    alpha0: float
    alpha_min: float
    alpha_factor: float
    max_iterations: int
    retry_iterations: int
    max_simplex_iterations: int | None
    max_seconds: float | None
    lambda_tol: float
    window: int
    directions: Directions
    start: Literal["interior", "vertex"]
    certify: bool
    settle_tol: float
    settle_window: int
    mechanism_band: bool
    state_solver: Literal["clarabel", "highs"]
    time_limit: float | None
    lowest: bool
    lowest_budget: float
    global_: bool
    global_time_limit: float | None
    global_node_limit: int | None
    global_bounds: Literal["per_point", "uniform"]
    fuse: bool
    continuation: bool
    fused_retry: bool
    progress: Progress | None = field(default=None, repr=False, compare=False)

    @property
    def beta(self) -> float:
        """The relaxation ``beta``."""
        return self.relaxation

    @property
    def user_limit(self) -> float:
        """:attr:`time_limit` in seconds, ``inf`` for none."""
        return float(self.time_limit) if self.time_limit is not None else math.inf

    def tell(self, event: LPProgress) -> None:
        """Pass ``event`` to the progress callback, if any."""
        if self.progress is not None:
            self.progress(event)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (without the callback)."""
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "progress"}
        return d


def recipe_for(blocks: int, options: NonAssociativeOptions | None = None, tuning: Tuning | None = None,
               progress: Progress | None = None) -> Recipe:
    """The :class:`Recipe` of a wall of ``blocks`` blocks."""
    o = options or NonAssociativeOptions()
    t = tuning or Tuning()
    large = t.large_wall(blocks)
    return Recipe(
        scheme=t.scheme, selection=t.resolved_selection, relaxation=t.beta, alpha0=t.alpha0, alpha_min=t.alpha_min,
        alpha_factor=t.alpha_factor, max_iterations=o.max_iterations, retry_iterations=t.retry_iterations,
        max_simplex_iterations=t.max_simplex_iterations, max_seconds=o.max_seconds, lambda_tol=t.lambda_tol,
        window=t.window, directions=o.directions, start=t.start, certify=t.certify, settle_tol=t.settle_tol,
        settle_window=t.settle_window, mechanism_band=t.mechanism_band, state_solver=t.state_solver,
        time_limit=o.time_limit, lowest=o.lowest_on(blocks), lowest_budget=o.lowest_budget, global_=o.global_,
        global_time_limit=o.global_time_limit, global_node_limit=o.global_node_limit, global_bounds=t.global_bounds,
        fuse=large if t.fuse is None else t.fuse, continuation=large if t.continuation is None else t.continuation,
        fused_retry=t.fused_retry,
        progress=progress,
    )
