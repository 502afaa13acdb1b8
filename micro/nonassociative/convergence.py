"""When the sequence stops: the exact stop, the settle test of the certificate, cycles.

The LPs are degenerate: their optimal force fields are not unique, and the
simplex returns a vertex whose forces in the parts that do not move jump from
one iterate to the next, so the iterate's own forces rarely satisfy Coulomb
even when ``lambda`` has settled. Two stops count as converged: the exact one
(:func:`exact_stop`) and the certificate (:mod:`micro.nonassociative.certificate`),
tried once ``lambda`` has settled (:func:`settled`). Otherwise the sequence
stops when it cycles (:func:`detect_cycle`), or on the caps on LPs and time.
"""

from __future__ import annotations

import numpy as np

from micro.nonassociative.recipe import Recipe
from micro.nonassociative.tuning import FORCE_TOL, NO_PROGRESS, PERIODS, TINY

Band = tuple[float, float]


def exact_stop(k: int, alpha_done: bool, dlam: float, dn: float, coulomb: float, coulomb_tol: float,
               options: Recipe) -> str | None:
    """The exact stop: after at least two non-associative iterates (for
    scheme (b) once ``alpha`` has reached ``alpha_min``), the relative change
    of ``lambda`` is below ``lambda_tol`` and the iterate satisfies Coulomb
    with its OWN normal forces within ``coulomb_tol``.

    Returns:
        ``"lambda_and_forces"`` (the normal forces settled too, within
        :data:`~micro.nonassociative.tuning.FORCE_TOL`), ``"lambda_and_coulomb"``, or ``None``.
    """
    if k >= 2 and alpha_done and dlam <= options.lambda_tol and coulomb <= coulomb_tol:
        return "lambda_and_forces" if dn <= FORCE_TOL else "lambda_and_coulomb"
    return None


def settled(lams: list[float], k: int, last_try: int, options: Recipe) -> bool:
    """Time for a certificate try: ``lambda``'s spread over the last
    ``settle_window`` iterates is at most ``settle_tol`` relative, and the
    last try is at least a window ago (on large walls a try costs a few LPs)."""
    w = options.settle_window
    return (len(lams) >= w and k - last_try >= w
            and float(np.ptp(lams[-w:])) <= options.settle_tol * abs(lams[-1]))


def window_band(lams: list[float], window: int) -> Band | None:
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
