"""Which back end plays which part in the non-associative method: the solver roles, by name.

The iterated LP (:mod:`micro.nonassociative`) names a role, never a solver
package; this module says which back end fills it. Five roles:

``InteriorLP``       an interior point on a static LP, solved once: the
                     associative start (iterate 0), the certificate's restricted
                     LPs and the fused wall's start. Built as
                     ``InteriorLP(lp, time_limit=..., settings=...)``;
                     ``solve(direction)`` returns an :class:`~micro.backends.base.Outcome`.
                     Filled by Clarabel (:class:`~micro.backends.clarabel.ClarabelStaticBackend`):
                     a point near the centre of the optimal face, which the
                     scheme's fixed point needs.
``InteriorLPRetry``  an LP of ``InteriorLP`` solved again where it failed
                     (:func:`solve_interior`, the one place that writes it): the
                     associative start (of the wall's sequences, of the fused wall
                     and of the reduced wall) on any failure but the user's time
                     limit, the certificate's restricted LP where it ends
                     inaccurate, at an iteration limit or with a solver error.
                     Filled by HiGHS' interior point without crossover
                     (:class:`~micro.backends.highs.HighsBackend`, ``algorithm="ipm"``;
                     no BLAS, so the path stays independent of the BLAS kernel).
``PersistentLP``     one LP changed in place between solves and warm-started:
                     the iterated LP's model, the descent's two LPs, the cold
                     check (a copy). Filled by HiGHS
                     (:class:`~micro.backends.highs.PersistentHighsModel`): bound,
                     row and cost changes, the basis read and set, the
                     algorithm switched between simplex and interior point,
                     limits counted in simplex iterations.
``LeastDistance``    the proximal selection's projection, ``min 1/2 |x - t|^2``
                     (:class:`~micro.backends.normal_qp.LeastDistanceQP`, the
                     interior point on the normal equations).
``LeastDistanceFallback``  the same QP where the first does not converge
                     (:class:`~micro.backends.normal_qp.ClarabelLeastDistance`).

A back end for the iterated LP goes here: a module of ``micro/backends/`` with
the methods of ``PersistentLP`` that the method calls (those of
:class:`~micro.backends.highs.PersistentHighsModel`), named in this module. The
layering test (``tests/micro/nonassociative/test_layering.py``) holds the
method to it: no module of ``micro.nonassociative`` imports a solver package.
The associative LP's back ends, chosen by name at run time, are another
matter: :mod:`micro.backends.registry`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection
from typing import Any

from micro.backends.base import Outcome, Status
from micro.backends.clarabel import CLARABEL_RETRY, ClarabelStaticBackend
from micro.backends.highs import BASIC, LOWER, HighsBackend, PersistentHighsModel  # PersistentLP's basis statuses
from micro.backends.normal_qp import ClarabelLeastDistance, LeastDistanceQP
from micro.lp import LimitLP

InteriorLP = ClarabelStaticBackend
#: ``InteriorLP``'s settings for a retry after a failed solve (tighter than its defaults).
INTERIOR_RETRY = CLARABEL_RETRY
PersistentLP = PersistentHighsModel
InteriorLPRetry = HighsBackend
LeastDistance = LeastDistanceQP
LeastDistanceFallback = ClarabelLeastDistance

#: Outcomes of ``InteriorLP`` that end in numerical trouble (:func:`solve_interior`'s ``retry_on`` for an LP
#: whose infeasibility is an answer, as the certificate's restricted LP).
NUMERICAL_TROUBLE = frozenset({Status.INACCURATE, Status.ITERATION_LIMIT, Status.SOLVER_ERROR})
#: Every outcome of ``InteriorLP`` but an optimum and the user's time limit (``retry_on`` for an LP that
#: has an optimum, as the associative start).
ANY_FAILURE = frozenset(Status) - {Status.OPTIMAL, Status.TIME_LIMIT}


def solve_interior(lp: LimitLP, direction: int, *, retry_on: Collection[Status], time_limit: float | None = None,
                   settings: dict[str, Any] | None = None) -> tuple[Outcome, str]:
    """One static LP by ``InteriorLP``, solved again by ``InteriorLPRetry`` where it ends with a status of
    ``retry_on`` (:data:`NUMERICAL_TROUBLE` or :data:`ANY_FAILURE`); the one place that writes this
    fallback, for the associative starts (the iterated LP's, the fused wall's, the reduced wall's) and the
    certificate's restricted LPs.

    Returns:
        ``(outcome, algorithm)``: the outcome that stands, with the seconds and interior-point
        iterations of both solves where the retry ran, and ``"clarabel"`` or ``"ipm"`` (the one that
        gave it).
    """
    out = InteriorLP(lp, time_limit=time_limit, settings=settings).solve(direction)
    if out.status not in retry_on:
        return out, "clarabel"
    again = InteriorLPRetry(lp, algorithm="ipm", time_limit=time_limit).solve(direction)
    return dataclasses.replace(again.plus_seconds(out.seconds),
                               ipm_iterations=again.ipm_iterations + out.ipm_iterations), "ipm"


#: The names each role goes by in the method's solver description
#: (:meth:`micro.nonassociative.config.Resolved.solver_description`).
ROLE_NAMES = {"interior": "clarabel", "persistent": "highs"}

__all__ = ["ANY_FAILURE", "BASIC", "INTERIOR_RETRY", "LOWER", "NUMERICAL_TROUBLE", "ROLE_NAMES", "InteriorLP",
           "InteriorLPRetry", "LeastDistance", "LeastDistanceFallback", "PersistentLP", "solve_interior"]
