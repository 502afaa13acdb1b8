"""How an iterate of the iterated LP goes on: the selections, one object each behind one interface.

The loop of :class:`~micro.nonassociative.iteration.LPSequence` asks its
selection the same few questions at every LP and holds no branch of its own:

* the model: friction as bounds of ``s`` or as rows (:attr:`Selection.rows`),
  the first slope and the cohesion of the rows;
* where the next ``nbar`` lies (:meth:`Selection.next_nbar`) and the next slope;
* whether an iterate may be solved cold;
* when the certificate is due;
* which no-progress test ends the sequence (cycles, or the proximal steps' stall).

``Vertex``        Gilbert et al.'s iteration, scheme (a) or (b):
                  ``nbar = beta n_k + (1 - beta) n_(k-1)`` from the simplex's vertex;
``Proximal``      ``nbar`` moved by ``beta`` towards its projection onto the
                  fields that carry the LP's load (:mod:`~micro.nonassociative.proximal`);
``Continuation``  scheme (a) reached from associative friction: friction rows of
                  slope ``gamma mu`` falling to 0 (``CONT_*`` in :mod:`~micro.nonassociative.tuning`).

Which sequences run on a direction (the vertex one, then the proximal one,
then the fused wall) is :mod:`micro.nonassociative.pipeline`'s.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from micro.lp import LimitLP
from micro.nonassociative import convergence
from micro.nonassociative.proximal import Projection
from micro.nonassociative.recipe import Recipe
from micro.nonassociative.tuning import (
    COHESION,
    CONT_COHESION,
    CONT_FACTOR,
    CONT_GAMMA0,
    CONT_GAMMA_MIN,
    TINY,
    WARM_UNLIMITED,
)

FloatArray = NDArray[np.float64]
Band = tuple[float, float]
NAN = math.nan


class Selection:
    """The interface of a selection, its answers those of the vertex iteration (module docstring).

    Args:
        options: the recipe (scheme, relaxation, slopes, tolerances).
        lp: the LP the sequence runs on.
        direction: ``+1`` or ``-1``.
    """

    #: Its name in the records (``SequenceDiagnostics.selection``) and the progress lines.
    name = "vertex"

    def __init__(self, options: Recipe, lp: LimitLP, direction: int) -> None:
        self.o = options
        self.beta = options.beta

    # ------------------------------------------------------------- the model
    @property
    def rows(self) -> bool:
        """Friction as rows (scheme (b), the continuation) rather than bounds of ``s``."""
        return self.o.scheme == "b"

    def first_alpha(self) -> float:
        """The slope of the first LP's friction rows (0: none)."""
        return self.o.alpha0 if self.o.scheme == "b" else 0.0

    def cohesion(self, associative: FloatArray, start: FloatArray) -> float:
        """``c0`` of the friction rows: :data:`COHESION` of the largest associative normal force."""
        return COHESION * max(float(np.max(associative, initial=0.0)), TINY)

    def warm_limit(self, limit: int) -> int:
        """The simplex iterations a warm run may take (the policy's ``limit``)."""
        return limit

    @property
    def may_go_cold(self) -> bool:
        """Whether a slow warm run sends the next iterates cold (scheme (a))."""
        return self.o.scheme == "a"

    # ------------------------------------------------------------- a step
    def next_nbar(self, nbar: FloatArray, lam: float, n_prev: FloatArray, n_prev2: FloatArray) -> FloatArray:
        """The next ``nbar`` from the last two iterates' forces (``nbar``: the
        current one, ``lam``: the last LP's load factor)."""
        return self.beta * n_prev + (1.0 - self.beta) * n_prev2

    def next_alpha(self, alpha: float) -> float:
        """The next LP's slope: scheme (b)'s halved down to ``alpha_min``, else 0."""
        if self.o.scheme == "b":
            return max(self.o.alpha_min, alpha * self.o.alpha_factor)
        return 0.0

    def alpha_done(self, alpha: float) -> bool:
        """Whether the slope has reached its end (stops and the certificate wait for it)."""
        return self.o.scheme == "a" or alpha <= self.o.alpha_min

    def take_step(self) -> float:
        """The proximal step of the last ``nbar`` (NaN for the others), then forgotten."""
        return NAN

    # ------------------------------------------------------------- stops
    def certificate_due(self, lams: list[float], k: int, last_try: int) -> bool:
        """Whether to try the certificate at LP ``k``: once ``lambda`` has settled."""
        return convergence.settled(lams, k, last_try, self.o)

    def no_progress(self, lams: list[float], dns: list[float], alpha_done: bool) -> tuple[str, Band] | None:
        """The cycle tests of :func:`~micro.nonassociative.convergence.detect_cycle` once the slope is done."""
        return convergence.detect_cycle(lams, dns, self.o.lambda_tol, self.o.window) if alpha_done else None


class Vertex(Selection):
    """Gilbert et al.'s vertex iteration, scheme (a) or (b) (the interface's own answers)."""


class Proximal(Selection):
    """The proximal selection (module docstring): the certificate is tried at
    every LP from the second on, and the sequence stops when its steps
    ``|n - nbar|_1 / |nbar|_1`` stop shrinking."""

    name = "proximal"

    def __init__(self, options: Recipe, lp: LimitLP, direction: int) -> None:
        super().__init__(options, lp, direction)
        self.projection = Projection(lp, direction, options.user_limit)
        self.steps: list[float] = []
        self.step = NAN

    def next_nbar(self, nbar: FloatArray, lam: float, n_prev: FloatArray, n_prev2: FloatArray) -> FloatArray:
        """``nbar`` moved by ``beta`` towards its projection at the LP's ``lam``;
        where the QP is not solved, the vertex rule for this step."""
        proj = self.projection.project(nbar, lam)
        self.step = proj.step
        if proj.normal is None:
            return super().next_nbar(nbar, lam, n_prev, n_prev2)
        self.steps.append(proj.step)
        return nbar + self.beta * (proj.normal - nbar)

    def take_step(self) -> float:
        step, self.step = self.step, NAN
        return step

    def certificate_due(self, lams: list[float], k: int, last_try: int) -> bool:
        """At every LP from the second: its ``lambda`` need not settle before its state does."""
        return k >= 2

    def no_progress(self, lams: list[float], dns: list[float], alpha_done: bool) -> tuple[str, Band] | None:
        """:func:`~micro.nonassociative.convergence.detect_stall` on its steps."""
        return convergence.detect_stall(self.steps, lams, self.o.window)


class Continuation(Selection):
    """The continuation (module docstring): the vertex sequence's LPs hold
    scheme (b)'s friction rows with a slope ``gamma mu``, ``gamma`` from
    :data:`CONT_GAMMA0` times :data:`CONT_FACTOR` per LP down to 0; ``nbar``
    moves by ``beta`` towards each LP's forces; warm runs are uncapped and never
    sent cold (the path must not depend on a cap); from ``gamma = 0`` on the
    certificate is tried at every LP and only it or the cap ends the sequence."""

    name = "vertex continuation"

    @property
    def rows(self) -> bool:
        return True

    def first_alpha(self) -> float:
        return -CONT_GAMMA0

    def cohesion(self, associative: FloatArray, start: FloatArray) -> float:
        """:data:`CONT_COHESION` of the largest normal force it starts from."""
        return CONT_COHESION * max(float(np.max(start, initial=0.0)), TINY)

    def warm_limit(self, limit: int) -> int:
        return WARM_UNLIMITED

    @property
    def may_go_cold(self) -> bool:
        return False

    def next_nbar(self, nbar: FloatArray, lam: float, n_prev: FloatArray, n_prev2: FloatArray) -> FloatArray:
        """``nbar`` follows the forces as ``gamma`` falls."""
        return nbar + self.beta * (n_prev - nbar)

    def next_alpha(self, alpha: float) -> float:
        """``-gamma`` times :data:`CONT_FACTOR`, and 0 (scheme (a)) once ``gamma``
        would fall to :data:`CONT_GAMMA_MIN`."""
        return alpha * CONT_FACTOR if -alpha * CONT_FACTOR > CONT_GAMMA_MIN else 0.0

    def alpha_done(self, alpha: float) -> bool:
        return alpha == 0.0

    def certificate_due(self, lams: list[float], k: int, last_try: int) -> bool:
        return k >= 2

    def no_progress(self, lams: list[float], dns: list[float], alpha_done: bool) -> tuple[str, Band] | None:
        """None: the continuation ends certified or at its cap."""
        return None


def selection_for(options: Recipe, lp: LimitLP, direction: int) -> Selection:
    """The selection object of one sequence (``options.selection``: ``"vertex"``
    or ``"proximal"``; ``"vertex"`` with ``options.continuation``: the continuation)."""
    if options.selection == "proximal":
        return Proximal(options, lp, direction)
    if options.continuation and options.selection == "vertex":
        return Continuation(options, lp, direction)
    return Vertex(options, lp, direction)
