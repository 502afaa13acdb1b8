"""The back ends by name: :func:`make_backend`, :data:`SOLVERS`, :data:`DEFAULT_SOLVER`.

Names of :data:`SOLVERS` (the CLI's ``--solver``, the report's back ends):

``normal-ipm``     the suite's own interior point on the normal equations
                   (:mod:`micro.backends.normal_ipm`, CHOLMOD through cvxopt),
                   the default (:data:`DEFAULT_SOLVER`): faster than the best
                   configuration of the maintained solvers (``clarabel``) on
                   walls of 1,230-7,575 blocks, as accurate
                   (``docs/micro/associative.md``, docs/speed.md);
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

A back end's module is imported when it is chosen (:func:`make_backend`), not
when this module is: the CLI, the report and the iterated LP do not pay for a
back end they do not run, and a back end whose package is an optional extra
(``cvxpy``: ``pip install 'xcheck-masonry[cvxpy]'``) is refused in one line
naming the extra when that package is missing (:func:`missing_extra`).
:mod:`micro.backends.base` imports no back end.
"""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType
from typing import Literal

from micro.backends.base import Backend, check_time_limit
from micro.lp import LimitLP

#: The back end of :func:`micro.solve_associative` (and of the CLI and the
#: report) when none is named.
DEFAULT_SOLVER = "normal-ipm"


@dataclass(frozen=True)
class _Entry:
    """One back end by name: its module (imported when chosen), how to make it, the optional extra that
    installs its package (``""``: a dependency of the package itself), and which reports time it in their
    speed-accuracy study (``"all"``; ``"quick"``: the quick report's small walls only)."""

    module: str
    make: Callable[[ModuleType, LimitLP, float | None], Backend]
    extra: str = ""
    timed: Literal["all", "quick"] = "all"


_SOLVERS: dict[str, _Entry] = {
    "normal-ipm": _Entry("normal_ipm", lambda m, lp, t: m.NormalIpmBackend(lp, time_limit=t)),
    "clarabel": _Entry("clarabel_kinematic", lambda m, lp, t: m.ClarabelKinematicBackend(lp, time_limit=t)),
    "highs-ipm": _Entry("highs", lambda m, lp, t: m.HighsBackend(lp, algorithm="ipm", time_limit=t)),
    # cold, the simplex is slow on large walls: timed on the quick report's walls only
    "highs-simplex": _Entry("highs", lambda m, lp, t: m.HighsBackend(lp, algorithm="simplex", time_limit=t),
                            timed="quick"),
    "cvxpy": _Entry("cvxpy_", lambda m, lp, t: m.CvxpyBackend(lp, solver="CLARABEL"), extra="cvxpy"),
}
_EXPERIMENTS: dict[str, _Entry] = {
    "clarabel-static": _Entry("clarabel", lambda m, lp, t: m.ClarabelStaticBackend(lp, time_limit=t)),
    "clarabel-default": _Entry("clarabel", lambda m, lp, t: m.ClarabelStaticBackend(lp, tight=False, time_limit=t)),
    "cvxpy-highs": _Entry("cvxpy_", lambda m, lp, t: m.CvxpyBackend(lp, solver="HIGHS"), extra="cvxpy"),
    "cvxpy-clarabel-default": _Entry("cvxpy_", lambda m, lp, t: m.CvxpyBackend(lp, solver="CLARABEL", tight=False),
                                     extra="cvxpy"),
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
    entry = (_SOLVERS.get(solver) or _EXPERIMENTS.get(solver)) if isinstance(solver, str) else None
    if entry is None:
        raise ValueError(f"solver must be one of {', '.join(SOLVERS)}; got {solver!r}")
    missing = missing_extra(solver)
    if missing:
        raise ValueError(missing)
    return entry.make(importlib.import_module(f"micro.backends.{entry.module}"), lp, time_limit)


def timed_solvers(quick: bool) -> tuple[str, ...]:
    """The back ends of :data:`SOLVERS` the report times in its speed-accuracy study (all of them on the quick
    report's walls, those that are not ``timed="quick"`` on the full report's), where they can run here (an
    optional extra that is not installed leaves its back end out, :func:`missing_extra`)."""
    return tuple(name for name, entry in _SOLVERS.items()
                 if (quick or entry.timed == "all") and not missing_extra(name))


def missing_extra(solver: str) -> str:
    """``""`` when the back end ``solver`` can run here, else the one line that says which optional extra
    installs its package (``solver 'cvxpy' needs cvxpy: pip install 'xcheck-masonry[cvxpy]'``)."""
    entry = _SOLVERS.get(solver) or _EXPERIMENTS.get(solver)
    if entry is None or not entry.extra or _installed(entry.extra):
        return ""
    return f"solver {solver!r} needs {entry.extra}: pip install 'xcheck-masonry[{entry.extra}]'"


def _installed(package: str) -> bool:
    """Whether ``package`` can be imported (``sys.modules[package] = None`` counts as missing, as for import)."""
    try:
        return importlib.util.find_spec(package) is not None
    except ValueError:  # in sys.modules with no spec (None: an import of it is refused)
        return False
