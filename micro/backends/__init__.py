"""Back ends of the limit-analysis LP: one module per back end behind one small interface.

``base``      :class:`Status`, :class:`Outcome`, the independent re-check (imports no back end);
``interrupt`` Ctrl-C during a solver's compiled code: the solver stopped by its own callback;
``registry``  :func:`make_backend`, the back ends by name (:data:`SOLVERS`, :data:`DEFAULT_SOLVER`);
``highs``     :class:`HighsBackend` and the :class:`PersistentHighsModel` it (and the iterated LP) runs on;
``clarabel``  Clarabel's settings and :class:`ClarabelStaticBackend` (the static form: ``clarabel-static``);
``clarabel_kinematic``  :class:`ClarabelKinematicBackend` (the kinematic form, ``clarabel``);
``normal_ipm``  :class:`NormalIpmBackend` (``normal-ipm``), the suite's interior point on the normal
              equations, over ``normal_matrix`` (:class:`NormalMatrix`, CHOLMOD);
``normal_qp``  :class:`LeastDistanceQP` (the least-distance QP on the normal equations) and
              :class:`ClarabelLeastDistance`: the proximal projection's solvers;
``roles``     which back end plays which part in the non-associative method (the interior-point LP,
              the persistent LP of the iterated LP and the descent, the projection): a back end for
              the iterated LP is named there;
``polish``    :func:`polish_equilibrium`, the kinematic form's forces corrected onto exact equilibrium;
``cvxpy_``    :class:`CvxpyBackend`, the readable reference formulation.
"""

from micro.backends.base import MAX_RESIDUAL, Backend, Outcome, Status, recheck
from micro.backends.clarabel import CLARABEL_RETRY, CLARABEL_TIGHT, ClarabelStaticBackend
from micro.backends.clarabel_kinematic import CLARABEL_KINEMATIC, POLISH, ClarabelKinematicBackend
from micro.backends.cvxpy_ import CvxpyBackend
from micro.backends.highs import HighsBackend, PersistentHighsModel
from micro.backends.normal_ipm import NORMAL_IPM, NormalIpmBackend, NormalIpmSettings
from micro.backends.normal_matrix import NormalMatrix
from micro.backends.polish import POLISH_MAX_LOAD_FACTOR_CHANGE
from micro.backends.registry import DEFAULT_SOLVER, EXPERIMENTS, SOLVERS, make_backend

__all__ = [
    "CLARABEL_KINEMATIC",
    "CLARABEL_RETRY",
    "CLARABEL_TIGHT",
    "DEFAULT_SOLVER",
    "EXPERIMENTS",
    "MAX_RESIDUAL",
    "NORMAL_IPM",
    "POLISH",
    "POLISH_MAX_LOAD_FACTOR_CHANGE",
    "SOLVERS",
    "Backend",
    "ClarabelKinematicBackend",
    "ClarabelStaticBackend",
    "CvxpyBackend",
    "HighsBackend",
    "NormalIpmBackend",
    "NormalIpmSettings",
    "NormalMatrix",
    "Outcome",
    "PersistentHighsModel",
    "Status",
    "make_backend",
    "recheck",
]
