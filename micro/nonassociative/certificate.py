"""The certificate: is an iterate's mechanism an exact non-associative collapse state?

With the mechanism fixed, the non-associative collapse conditions on the
forces are linear: equilibrium; ``n = 0`` where the points open;
``s = -sign(slip) mu n`` where they slip (friction at the yield line, against
the slip); ``|s| <= mu n`` where they stick. In the generator form of the
associative LP (:mod:`micro.lp`) that is a choice of columns: both generators
at a sticking point, the one on the right side of the cone at a slipping
point, none at an opening point (:meth:`Certificate.pattern`). Any feasible
field forms with the mechanism an exact non-associative collapse state
(equilibrium, Coulomb with its own normal forces, no dilatancy where
``n > 0``, no interpenetration, slip only at the yield line, against the
slip; the energy balance follows by virtual work). The mechanism of the LP
``|s| <= mu nbar`` already has no dilatancy where ``n > 0``; what a sequence
that does not settle in the forces lacks is a field that satisfies Coulomb
with its own normal forces, and the certificate looks for one among ALL
fields, not only the LP's optimal ones.

The load factors of these states form an interval, the MECHANISM BAND: its
ends are two LPs (min and max ``lambda``), solved by an interior point, no
basis. An iterate's ``lambda`` is certified when it lies in the band
(relative slack :data:`~micro.nonassociative.config.BAND_SLACK`), and the
state at ``lambda`` is the convex combination of the two end states
(equilibrium is linear). A feasibility LP at fixed ``lambda`` would be one LP
instead of two, but HiGHS' interior point stopped with "Solve error" when
``lambda`` sat at an end of the band (seen on pure rocking mechanisms, whose
``lambda`` is a geometric constant). The ends are load factors of feasible
states found to ~1e-5, so the band can only come out a little narrower than
the exact one and a certificate is never accepted wrongly.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from micro.backends.base import Outcome, Status
from micro.backends.roles import INTERIOR_RETRY, NUMERICAL_TROUBLE, solve_interior
from micro.lp import LimitLP
from micro.mechanism import STATE_TOL
from micro.nonassociative.config import INTERPENETRATION, TINY

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
#: ``(n, s, lambda)`` of a state found by a certificate LP.
StateTriple = tuple[FloatArray, FloatArray, float]

#: Clarabel settings of the certificate LPs: their ends are checked for
#: feasibility, so optimality to 1e-9 is enough (the tight settings stopped
#: short on every certificate LP of the Table 7 walls and were retried).
STATE_CLARABEL = INTERIOR_RETRY
#: Outcomes of ``InteriorLP`` after which a certificate LP is solved again by ``InteriorLPRetry``
#: (HiGHS' interior point): numerical trouble, not an answer. Read as "no state", such an outcome hides a
#: band that exists, and the sequence runs on past a certified state (walls that slide at lambda = f, whose
#: band is one point; a wall with frictionless head joints that had no value at all: the research page on
#: Set 9's profile, ``docs/research/``).
RETRY_STATUSES = NUMERICAL_TROUBLE
#: Relative slack of the test "the iterate's lambda lies in the mechanism band".
BAND_SLACK = 1e-7


def point_states(dn: FloatArray, ds: FloatArray, max_noise: float) -> tuple[BoolArray, BoolArray, BoolArray] | None:
    """Which points of a mechanism open and which slip, by the one rule for
    "this rate is zero" (the certificate's pattern and the descent's
    :func:`~micro.nonassociative.descent.states.restricted_columns`).

    A rate is zero below :data:`~micro.mechanism.STATE_TOL` of the largest,
    the rule of :func:`~micro.nonassociative.final_checks.verify_collapse_state`, so
    that a state built on the pattern passes its slip-at-yield check (a
    former margin of 10 x the dual noise let states slip at 1.01e-6 of the
    largest rate with friction below yield). Closing rates up to
    ``max_noise`` of the largest are read as the dual noise of a simplex
    mechanism at closed points (down to -1.1e-5 seen on Set 4, where exact
    duals give >= 0); beyond it the mechanism interpenetrates.

    Args:
        dn, ds: ``(P,)`` opening and slip rates.
        max_noise: largest closing rate, relative to the largest rate, read as noise.

    Returns:
        ``(opening, slipping with ds > 0, slipping with ds < 0)`` masks, or
        ``None`` when a point closes by more than ``max_noise``.
    """
    scale = max(float(np.max(np.abs(ds), initial=0.0)), float(np.max(np.abs(dn), initial=0.0)), 1e-300)
    noise = max(-float(np.min(dn, initial=0.0)), 0.0) / scale
    if noise > max_noise:
        return None
    tol = STATE_TOL * scale
    opening = dn > tol
    return opening, (ds > tol) & ~opening, (ds < -tol) & ~opening



@dataclass(frozen=True, eq=False)
class CertificateResult:
    """The outcome of one certificate try.

    Attributes:
        forces: ``(n, s)`` (scaled) of an exact collapse state at the
            iterate's ``lambda``, or ``None`` (none found).
        band: the mechanism band ``(min, max)``; ``max`` is NaN when only the
            lower end was found, ``None`` when no state was found at all.
        seconds: wall time of the LPs.
        iterations: their interior-point (and simplex) iterations.
    """

    forces: tuple[FloatArray, FloatArray] | None
    band: tuple[float, float] | None
    seconds: float
    iterations: int


class Certificate:
    """The certificate LPs of one load direction (module docstring).

    Args:
        lp: the wall's LP.
        direction: ``+1`` or ``-1``.
        scheme: the sequence's scheme, ``"a"`` or ``"b"`` (how much closing
            of a mechanism counts as noise: :meth:`pattern`).
    """

    def __init__(self, lp: LimitLP, direction: int, scheme: str) -> None:
        self.lp, self.d, self.scheme = lp, direction, scheme
        #: the answers of :meth:`state_lp` by pattern and sense: a sequence that settles on one
        #: mechanism tries the same restricted LP again at each later iterate, and its answer is the same
        self._answers: dict[tuple[bytes, float], tuple[StateTriple | None, Outcome]] = {}

    def pattern(self, v: FloatArray) -> tuple[FloatArray, FloatArray] | None:
        """Generator bounds of the collapse states compatible with the
        mechanism ``v`` (block velocities): ``(upper of g+, upper of g-)``,
        or ``None`` when ``v`` makes points interpenetrate (possible with
        scheme (b), whose ``n`` columns also enter the friction rows): no
        force field can then make it a collapse state."""
        # scheme (b)'s own mechanisms dilate by alpha mu |slip|: its closing
        # rates are not noise, and any beyond STATE_TOL reject it
        states = point_states(self.lp.Bn.T @ v, self.lp.Bs.T @ v,
                              INTERPENETRATION if self.scheme == "a" else STATE_TOL)
        if states is None:
            return None
        opening, slip_pos, slip_neg = states
        up_p = np.where(opening | slip_pos, 0.0, np.inf)  # g+ carries s = +mu n
        up_m = np.where(opening | slip_neg, 0.0, np.inf)  # g- carries s = -mu n
        return up_p, up_m

    def state_lp(self, v: FloatArray, sense: float, time_limit: float = math.inf) -> tuple[StateTriple | None, Outcome]:
        """Minimise ``sense * lambda`` over the collapse states compatible
        with the mechanism ``v``: the generator LP without the columns
        :meth:`pattern` excludes, by Clarabel's interior point, and by HiGHS'
        where Clarabel ends in numerical trouble (:data:`RETRY_STATUSES`; the
        user's ``time_limit`` in seconds per solve, ``inf``: none). The
        answer is kept per pattern and sense: the same LP asked again (a
        sequence settled on one mechanism, tried at each later iterate) is
        answered at no cost (``seconds`` and iterations 0).

        Returns:
            ``((n, s, lambda) or None, outcome)``: ``None`` unless the
            interior point found an optimal state that passes the back end's re-check.
        """
        pattern = self.pattern(v)
        if pattern is None:
            return None, Outcome(Status.INFEASIBLE, "mechanism interpenetrates")
        key = (np.packbits(np.concatenate(pattern) == 0.0).tobytes(), float(sense))
        if key in self._answers:  # the same LP: its answer, at no cost
            state, out = self._answers[key]
            return state, dataclasses.replace(out, seconds=0.0, simplex_iterations=0, ipm_iterations=0,
                                              crossover_iterations=0)
        state, out = self._solve(pattern, sense, time_limit)
        if out.status is not Status.TIME_LIMIT:  # a run the user's limit stopped may end otherwise next time
            self._answers[key] = state, out
        return state, out

    def _solve(self, pattern: tuple[FloatArray, FloatArray], sense: float, time_limit: float
               ) -> tuple[StateTriple | None, Outcome]:
        """:meth:`state_lp` for ``pattern``, solved."""
        lp, d = self.lp, self.d
        restricted = dataclasses.replace(lp, col_upper=np.concatenate([*pattern, [np.inf]]))
        tl = None if not math.isfinite(time_limit) else float(time_limit)
        direction = -d if sense > 0 else d  # InteriorLP maximises direction * lambda_column
        out, _ = solve_interior(restricted, direction, retry_on=RETRY_STATUSES, time_limit=tl,
                                settings=STATE_CLARABEL)
        if out.status is not Status.OPTIMAL or out.n is None or out.s is None:
            return None, out
        return (np.asarray(out.n), np.asarray(out.s), d * (out.load_factor * direction)), out

    def certify(self, v: FloatArray, lam: float, *, time_limit: float = math.inf) -> CertificateResult:
        """Is there a non-associative collapse state at ``lam`` with the
        mechanism ``v``? (module docstring; ``time_limit``: the user's
        wall-clock limit per LP, ``inf`` for none)"""
        lo, out_lo = self.state_lp(v, 1.0, time_limit)
        seconds, iterations = out_lo.seconds, out_lo.simplex_iterations + out_lo.ipm_iterations
        slack = BAND_SLACK * max(abs(lam), TINY)
        if lo is None or lo[2] > lam + slack:
            return CertificateResult(None, None if lo is None else (lo[2], math.nan), seconds, iterations)
        hi, out_hi = self.state_lp(v, -1.0, time_limit)
        seconds += out_hi.seconds
        iterations += out_hi.simplex_iterations + out_hi.ipm_iterations
        if hi is None:
            return CertificateResult(None, (lo[2], math.nan), seconds, iterations)
        band = (lo[2], hi[2])
        if hi[2] < lam - slack:
            return CertificateResult(None, band, seconds, iterations)
        width = hi[2] - lo[2]
        theta = 1.0 if width <= 0 else min(max((hi[2] - lam) / width, 0.0), 1.0)
        n = theta * lo[0] + (1.0 - theta) * hi[0]
        s = theta * lo[1] + (1.0 - theta) * hi[1]
        return CertificateResult((n, s), band, seconds, iterations)
