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
``InteriorLPRetry``  an LP of ``InteriorLP`` solved again where it failed: the
                     associative start on any failure but the user's time limit,
                     the certificate's restricted LP where it ends inaccurate, at
                     an iteration limit or with a solver error.
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

from micro.backends.clarabel import CLARABEL_RETRY, ClarabelStaticBackend
from micro.backends.highs import BASIC, LOWER, HighsBackend, PersistentHighsModel  # PersistentLP's basis statuses
from micro.backends.normal_qp import ClarabelLeastDistance, LeastDistanceQP

InteriorLP = ClarabelStaticBackend
#: ``InteriorLP``'s settings for a retry after a failed solve (tighter than its defaults).
INTERIOR_RETRY = CLARABEL_RETRY
PersistentLP = PersistentHighsModel
InteriorLPRetry = HighsBackend
LeastDistance = LeastDistanceQP
LeastDistanceFallback = ClarabelLeastDistance

#: The names each role goes by in the method's solver description
#: (:meth:`micro.nonassociative.config.Resolved.solver_description`).
ROLE_NAMES = {"interior": "clarabel", "persistent": "highs"}

__all__ = ["BASIC", "INTERIOR_RETRY", "LOWER", "ROLE_NAMES", "InteriorLP", "InteriorLPRetry", "LeastDistance",
           "LeastDistanceFallback", "PersistentLP"]
