"""Back ends of the limit-analysis LP: one module per back end behind one small interface.

``base``      :class:`Status`, :class:`Outcome`, the independent re-check (imports no back end);
``interrupt`` Ctrl-C during a solver's compiled code: the solver stopped by its own callback;
``registry``  :func:`make_backend`, the back ends by name (:data:`SOLVERS`, :data:`DEFAULT_SOLVER`);
``highs``     :class:`HighsBackend` and the :class:`PersistentHighsModel` it (and the iterated LP) runs on;
``highs_runs``  how a HiGHS run is watched (the stall guard, its callback) and kept quiet;
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

from typing import Any

from micro.backends.base import MAX_RESIDUAL, Backend, Outcome, Status, recheck
from micro.backends.registry import DEFAULT_SOLVER, EXPERIMENTS, SOLVERS, make_backend, missing_extra

#: The names this package hands on from its back-end modules, imported on first use (a back end's module
#: is imported when it is chosen: :mod:`micro.backends.registry`).
_LAZY = {
    "CLARABEL_RETRY": "clarabel", "CLARABEL_TIGHT": "clarabel", "ClarabelStaticBackend": "clarabel",
    "CLARABEL_KINEMATIC": "clarabel_kinematic", "POLISH": "clarabel_kinematic",
    "ClarabelKinematicBackend": "clarabel_kinematic", "CvxpyBackend": "cvxpy_", "HighsBackend": "highs",
    "PersistentHighsModel": "highs", "NORMAL_IPM": "normal_ipm", "NormalIpmBackend": "normal_ipm",
    "NormalIpmSettings": "normal_ipm", "NormalMatrix": "normal_matrix", "POLISH_MAX_LOAD_FACTOR_CHANGE": "polish",
}


def __getattr__(name: str) -> Any:
    """A back end's name, its module imported now."""
    if name not in _LAZY:
        raise AttributeError(f"module 'micro.backends' has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(f"micro.backends.{_LAZY[name]}"), name)


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
    "missing_extra",
    "recheck",
]
