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
                  slope ``gamma mu`` falling to 0 (``CONT_*`` in :mod:`~micro.nonassociative.config`).

When a sequence stops: the LPs are degenerate, and the simplex returns a
vertex whose forces in the parts that do not move jump from one iterate to
the next, so an iterate's own forces rarely satisfy Coulomb even when
``lambda`` has settled. Two stops count as converged: the exact one
(:func:`exact_stop`) and the certificate (:mod:`micro.nonassociative.certificate`),
tried once ``lambda`` has settled (:func:`settled`). Otherwise a sequence
stops when it cycles (:func:`detect_cycle`) or stalls (:func:`detect_stall`),
or on the caps on LPs and time.

Which sequences run on a direction (the vertex one, then the proximal one,
then the fused wall) is :mod:`micro.nonassociative.pipeline`'s.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from micro.lp import LimitLP
from micro.nonassociative.config import TINY, Resolved
from micro.nonassociative.proximal import Projection

FloatArray = NDArray[np.float64]
Band = tuple[float, float]
NAN = math.nan

#: Scheme (b)'s cohesion ``c0``, relative to the largest normal force of the
#: associative solution (scale-free: one millionth of the force level).
COHESION = 1e-6
#: The continuation (``continuation=True``) reaches scheme (a)'s vertex
#: sequence from associative friction: LP ``k`` bounds the shear by the line
#: ``|s| <= c0 + (1 - gamma) mu nbar + gamma mu n`` through ``(nbar, mu nbar)``
#: (``gamma = 1``: associative Coulomb; ``gamma = 0``: scheme (a)) in scheme
#: (b)'s friction rows, ``gamma = CONT_GAMMA0`` at the first LP ...
CONT_GAMMA0 = 0.9
#: ... times this at every LP ...
CONT_FACTOR = 0.8
#: ... and 0 once it would fall to this or below (LP 32 on).
CONT_GAMMA_MIN = 1e-3
#: Its cohesion ``c0``, relative to the largest normal force it starts from
#: (scheme (b) has ``cohesion``, 1e-6: with it the fused Set 9's first LP gave
#: lambda = 5.46 against 0.394 associative).
CONT_COHESION = 1e-9
#: Its warm runs are not cut short (a cap would make the path depend on it):
#: the fused Set 10's second LP took 60,122 simplex iterations.
WARM_UNLIMITED = 2**31 - 1
#: Scheme (b)'s slope schedule: ``alpha`` from ``ALPHA0``, times
#: ``ALPHA_FACTOR`` at every LP, down to ``ALPHA_MIN`` (Gilbert et al.'s).
ALPHA0, ALPHA_FACTOR, ALPHA_MIN = 0.3, 0.5, 1e-3

#: The exact stop and the cycle tests: relative change of ``lambda`` counted as none.
LAMBDA_TOL = 1e-6
#: LPs per window of the oscillation, stagnation and stall tests.
WINDOW = 20
#: The certificate is tried once ``lambda``'s spread over the last
#: ``SETTLE_WINDOW`` LPs is at most ``SETTLE_TOL`` relative.
SETTLE_TOL, SETTLE_WINDOW = 1e-3, 3
#: The exact stop: largest change of the normal forces (relative to the
#: largest) for ``"lambda_and_forces"`` (else ``"lambda_and_coulomb"``).
FORCE_TOL = 1e-6
#: Periods of the repeating-sequence test (a period seen twice in a row).
PERIODS = range(2, 7)
#: Oscillation: the last window's spread of lambda is at least this fraction
#: of the window before (no contraction). Stagnation: the smallest change of
#: the forces over the last window is at least this fraction of the window
#: before (no progress).
NO_PROGRESS = 0.5


def exact_stop(k: int, alpha_done: bool, dlam: float, dn: float, coulomb: float, coulomb_tol: float) -> str | None:
    """The exact stop: after at least two non-associative iterates (for
    scheme (b) once ``alpha`` has reached :data:`ALPHA_MIN`), the relative change
    of ``lambda`` is below :data:`LAMBDA_TOL` and the iterate satisfies Coulomb
    with its OWN normal forces within ``coulomb_tol``.

    Returns:
        ``"lambda_and_forces"`` (the normal forces settled too, within
        :data:`FORCE_TOL`), ``"lambda_and_coulomb"``, or ``None``.
    """
    if k >= 2 and alpha_done and dlam <= LAMBDA_TOL and coulomb <= coulomb_tol:
        return "lambda_and_forces" if dn <= FORCE_TOL else "lambda_and_coulomb"
    return None


def settled(lams: list[float], k: int, last_try: int) -> bool:
    """Time for a certificate try: ``lambda``'s spread over the last
    :data:`SETTLE_WINDOW` iterates is at most :data:`SETTLE_TOL` relative, and
    the last try is at least a window ago (on large walls a try costs a few LPs)."""
    w = SETTLE_WINDOW
    return len(lams) >= w and k - last_try >= w and float(np.ptp(lams[-w:])) <= SETTLE_TOL * abs(lams[-1])


def window_band(lams: list[float], window: int = WINDOW) -> Band | None:
    """``(min, max)`` of the last ``window`` load factors (``None`` if there are none)."""
    w = lams[-window:]
    return (min(w), max(w)) if w else None


def detect_cycle(lams: list[float], dns: list[float], tol: float, window: int) -> tuple[str, Band] | None:
    """Cycling tests on the non-associative ``lambda`` sequence.

    * ``"repeating"``: the sequence repeats with a period in :data:`PERIODS`,
      seen twice in a row, and is not constant;
    * ``"oscillating"``: ``lambda`` moves by more than ``tol`` over the last
      window without contracting (spread at least :data:`NO_PROGRESS` of the
      window before);
    * ``"stagnation"``: ``lambda`` unchanged over the last window while the
      forces make no progress (their smallest change at least
      :data:`NO_PROGRESS` of the window before).

    Args:
        lams: ``lambda`` of the non-associative iterates.
        dns: their largest relative change of the normal forces.
        tol: relative tolerance on ``lambda``.
        window: iterates per window.

    Returns:
        ``(reason, (min, max))`` over the cycle or the last window, or ``None``.
    """
    k = len(lams)
    lam = np.asarray(lams)
    ref = max(abs(lam[-1]), TINY)
    for p in PERIODS:
        if k >= 2 * p:
            a = lam[-p:]
            b = lam[-2 * p : -p]
            if np.all(np.abs(a - b) <= tol * ref) and np.ptp(a) > tol * ref:
                return "repeating", (float(a.min()), float(a.max()))
    if k >= 2 * window:
        w1, w2 = lam[-2 * window : -window], lam[-window:]
        b1, b2 = float(np.ptp(w1)), float(np.ptp(w2))
        if b2 > tol * ref and b2 >= NO_PROGRESS * b1:
            return "oscillating", (float(w2.min()), float(w2.max()))
        d1, d2 = min(dns[-2 * window : -window]), min(dns[-window:])
        if b2 <= tol * ref and d2 >= NO_PROGRESS * d1:
            return "stagnation", (float(w2.min()), float(w2.max()))
    return None


def detect_stall(steps: list[float], lams: list[float], window: int) -> tuple[str, Band] | None:
    """The proximal selection's no-progress test: its ``lambda`` may move
    while its steps ``|n - nbar|_1 / |nbar|_1`` shrink, so it stops only
    when the smallest step of the last window is at least
    :data:`NO_PROGRESS` of the smallest of the window before.

    Returns:
        ``("stagnation", (min, max) of lambda over the last window)`` or ``None``.
    """
    if len(steps) < 2 * window:
        return None
    if min(steps[-window:]) >= NO_PROGRESS * min(steps[-2 * window : -window]):
        w = lams[-window:]
        return "stagnation", (min(w), max(w))
    return None


class Selection:
    """The interface of a selection, its answers those of the vertex iteration (module docstring).

    Args:
        resolved: what the stages read (the scheme, the relaxation).
        lp: the LP the sequence runs on.
        direction: ``+1`` or ``-1``.
    """

    #: Its name in the records (``SequenceDiagnostics.selection``) and the progress lines.
    name = "vertex"

    def __init__(self, resolved: Resolved, lp: LimitLP, direction: int) -> None:
        self.scheme = resolved.tuning.scheme
        self.beta = resolved.tuning.beta

    # ------------------------------------------------------------- the model
    @property
    def rows(self) -> bool:
        """Friction as rows (scheme (b), the continuation) rather than bounds of ``s``."""
        return self.scheme == "b"

    def first_alpha(self) -> float:
        """The slope of the first LP's friction rows (0: none)."""
        return ALPHA0 if self.scheme == "b" else 0.0

    def cohesion(self, associative: FloatArray, start: FloatArray) -> float:
        """``c0`` of the friction rows: :data:`COHESION` of the largest associative normal force."""
        return COHESION * max(float(np.max(associative, initial=0.0)), TINY)

    def warm_limit(self, limit: int) -> int:
        """The simplex iterations a warm run may take (the policy's ``limit``)."""
        return limit

    @property
    def may_go_cold(self) -> bool:
        """Whether a slow warm run sends the next iterates cold (scheme (a))."""
        return self.scheme == "a"

    # ------------------------------------------------------------- a step
    def next_nbar(self, nbar: FloatArray, lam: float, n_prev: FloatArray, n_prev2: FloatArray) -> FloatArray:
        """The next ``nbar`` from the last two iterates' forces (``nbar``: the
        current one, ``lam``: the last LP's load factor)."""
        return self.beta * n_prev + (1.0 - self.beta) * n_prev2

    def next_alpha(self, alpha: float) -> float:
        """The next LP's slope: scheme (b)'s halved down to ``alpha_min``, else 0."""
        if self.scheme == "b":
            return max(ALPHA_MIN, alpha * ALPHA_FACTOR)
        return 0.0

    def alpha_done(self, alpha: float) -> bool:
        """Whether the slope has reached its end (stops and the certificate wait for it)."""
        return self.scheme == "a" or alpha <= ALPHA_MIN

    def take_step(self) -> float:
        """The proximal step of the last ``nbar`` (NaN for the others), then forgotten."""
        return NAN

    # ------------------------------------------------------------- stops
    def certificate_due(self, lams: list[float], k: int, last_try: int) -> bool:
        """Whether to try the certificate at LP ``k``: once ``lambda`` has settled."""
        return settled(lams, k, last_try)

    def no_progress(self, lams: list[float], dns: list[float], alpha_done: bool) -> tuple[str, Band] | None:
        """The cycle tests of :func:`detect_cycle` once the slope is done."""
        return detect_cycle(lams, dns, LAMBDA_TOL, WINDOW) if alpha_done else None


class Vertex(Selection):
    """Gilbert et al.'s vertex iteration, scheme (a) or (b) (the interface's own answers)."""


class Proximal(Selection):
    """The proximal selection (module docstring): the certificate is tried at
    every LP from the second on, and the sequence stops when its steps
    ``|n - nbar|_1 / |nbar|_1`` stop shrinking."""

    name = "proximal"

    def __init__(self, resolved: Resolved, lp: LimitLP, direction: int) -> None:
        super().__init__(resolved, lp, direction)
        self.projection = Projection(lp, direction, resolved.options.user_limit)
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
        """:func:`detect_stall` on its steps."""
        return detect_stall(self.steps, lams, WINDOW)


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


def selection_for(resolved: Resolved, lp: LimitLP, direction: int) -> Selection:
    """The selection object of one sequence (``resolved.selection``: ``"vertex"``
    or ``"proximal"``; ``"vertex"`` with ``resolved.continuation``: the continuation)."""
    if resolved.selection == "proximal":
        return Proximal(resolved, lp, direction)
    if resolved.continuation and resolved.selection == "vertex":
        return Continuation(resolved, lp, direction)
    return Vertex(resolved, lp, direction)
