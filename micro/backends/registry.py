"""The back ends by name: :func:`make_backend`, :data:`SOLVERS`, :data:`DEFAULT_SOLVER`.

Names of :data:`SOLVERS` (the CLI's ``--solver``, the report's back ends):

``normal-ipm``     the suite's own interior point on the normal equations
                   (:mod:`micro.backends.normal_ipm`, CHOLMOD through cvxopt),
                   the default (:data:`DEFAULT_SOLVER`): 1.8-4.3 times faster
                   than the best configuration of the maintained solvers
                   (``clarabel``) on walls of 1,230-7,575 blocks, as accurate
                   (``docs/micro/associative.md``);
``clarabel``       Clarabel (interior point) on the kinematic (dual) form of
                   the LP (:mod:`micro.backends.clarabel_kinematic`), the
                   fastest and most accurate maintained solver measured;
``highs-ipm``      HiGHS interior point (IPX) without crossover;
``highs-simplex``  HiGHS dual simplex with 1e-10 feasibility tolerances
                   (a vertex; cold, it is slow on large walls);
``cvxpy``          the readable reference formulation in cvxpy expressions,
                   solved by Clarabel with tightened tolerances.

:data:`EXPERIMENTS`, accepted by :func:`make_backend` only (baselines of the
benchmarks and tests): ``clarabel-static`` (Clarabel's direct API on the static
form, :data:`micro.backends.clarabel.CLARABEL_TIGHT`), ``clarabel-default`` (the
same with Clarabel's default settings), ``cvxpy-highs`` (the cvxpy formulation
solved by HiGHS) and ``cvxpy-clarabel-default`` (by Clarabel with cvxpy's
default settings).

This module imports every back end; :mod:`micro.backends.base` imports none.
"""

from __future__ import annotations

from collections.abc import Callable

from micro.backends.base import Backend, check_time_limit
from micro.backends.clarabel import ClarabelStaticBackend
from micro.backends.clarabel_kinematic import ClarabelKinematicBackend
from micro.backends.cvxpy_ import CvxpyBackend
from micro.backends.highs import HighsBackend
from micro.backends.normal_ipm import NormalIpmBackend
from micro.lp import LimitLP

#: The back end of :func:`micro.solve_associative` (and of the CLI and the
#: report) when none is named.
DEFAULT_SOLVER = "normal-ipm"

_Factory = Callable[[LimitLP, "float | None"], Backend]

_SOLVERS: dict[str, _Factory] = {
    "normal-ipm": lambda lp, t: NormalIpmBackend(lp, time_limit=t),
    "clarabel": lambda lp, t: ClarabelKinematicBackend(lp, time_limit=t),
    "highs-ipm": lambda lp, t: HighsBackend(lp, algorithm="ipm", time_limit=t),
    "highs-simplex": lambda lp, t: HighsBackend(lp, algorithm="simplex", time_limit=t),
    "cvxpy": lambda lp, t: CvxpyBackend(lp, solver="CLARABEL"),
}
_EXPERIMENTS: dict[str, _Factory] = {
    "clarabel-static": lambda lp, t: ClarabelStaticBackend(lp, time_limit=t),
    "clarabel-default": lambda lp, t: ClarabelStaticBackend(lp, tight=False, time_limit=t),
    "cvxpy-highs": lambda lp, t: CvxpyBackend(lp, solver="HIGHS"),
    "cvxpy-clarabel-default": lambda lp, t: CvxpyBackend(lp, solver="CLARABEL", tight=False),
}

#: Names of the back ends (the CLI's ``--solver``; module docstring).
SOLVERS = tuple(_SOLVERS)
#: Baselines :func:`make_backend` accepts as well (module docstring).
EXPERIMENTS = tuple(_EXPERIMENTS)


def make_backend(lp: LimitLP, solver: str = DEFAULT_SOLVER, *, time_limit: float | None = None) -> Backend:
    """Make the back end called ``solver`` (one of :data:`SOLVERS` or :data:`EXPERIMENTS`) for ``lp``.

    Raises:
        ValueError: an unknown solver name (the message lists :data:`SOLVERS`),
            or a time limit that is not a positive number of seconds.
    """
    time_limit = check_time_limit(time_limit)
    factory = (_SOLVERS.get(solver) or _EXPERIMENTS.get(solver)) if isinstance(solver, str) else None
    if factory is None:
        raise ValueError(f"solver must be one of {', '.join(SOLVERS)}; got {solver!r}")
    return factory(lp, time_limit)
