"""What every back end shares: the status, the outcome, the independent re-check, the argument checks.

Modelled on cvxpy's solver layer: one module per back end, each a class with a
``STATUS_MAP`` from its native statuses onto :class:`Status`, and one
:class:`Outcome` type for success and failure. The back ends by name are in
:mod:`micro.backends.registry`; this module imports none of them.
"""

from __future__ import annotations

import dataclasses
import enum
import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from micro.exact import exact_dot
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]

#: Largest primal violation (equilibrium, ``n >= 0``, Coulomb; scaled units:
#: full-block weights) accepted from a back end that reports optimal. Beyond
#: it the status becomes ``inaccurate`` and the load factor NaN: HiGHS was seen
#: to report "Optimal" with unscaled equilibrium residuals of 1e-3.
MAX_RESIDUAL = 1e-6


class Status(str, enum.Enum):
    """Solver outcome, shared by every back end."""

    OPTIMAL = "optimal"
    INFEASIBLE = "infeasible"
    UNBOUNDED = "unbounded"
    INFEASIBLE_OR_UNBOUNDED = "infeasible_or_unbounded"
    TIME_LIMIT = "time_limit"
    ITERATION_LIMIT = "iteration_limit"
    INACCURATE = "inaccurate"
    SOLVER_ERROR = "solver_error"

    def __str__(self) -> str:  # pragma: no cover - trivial
        return self.value


@dataclass(frozen=True, eq=False)
class Outcome:
    """What one solve returns, success or failure (arrays are ``None`` unless optimal).

    Shared dual convention: ``duals`` are the row duals signed so that, on
    the equilibrium rows (the first ``3 n_blocks``), they ARE the
    (generalised) block velocities ``(u, v, omega)`` of the collapse
    mechanism, scaled by the LP's own normalisation: the live load does work
    ``+1`` (``(d * f_L) . duals = 1``) and the dead load ``-lambda``.

    Attributes:
        status: shared status.
        native_status: the back end's own status string.
        load_factor: ``lambda`` for the direction solved (one-shot back ends;
            NaN unless optimal, and from a persistent-model run, whose
            columns only the caller knows).
        x: column values (persistent-model runs).
        n, s: point forces (normal, shear) in scaled units (one-shot back ends).
        duals: row duals in the shared convention (above).
        simplex_iterations, ipm_iterations, crossover_iterations: solver
            iterations by algorithm.
        seconds: wall time of the solve call(s).
        info: extra back-end facts (residuals, algorithm, fallback, ...).
    """

    status: Status
    native_status: str
    load_factor: float = math.nan
    x: FloatArray | None = field(default=None, repr=False)
    n: FloatArray | None = field(default=None, repr=False)
    s: FloatArray | None = field(default=None, repr=False)
    duals: FloatArray | None = field(default=None, repr=False)
    simplex_iterations: int = 0
    ipm_iterations: int = 0
    crossover_iterations: int = 0
    seconds: float = 0.0
    info: Mapping[str, Any] = field(default_factory=dict, repr=False)

    @property
    def ok(self) -> bool:
        """True when the status is optimal."""
        return self.status is Status.OPTIMAL

    @property
    def iterations(self) -> int:
        """Iterations of every algorithm together."""
        return self.simplex_iterations + self.ipm_iterations + self.crossover_iterations

    def plus_seconds(self, seconds: float) -> Outcome:
        """The same outcome with ``seconds`` more wall time (e.g. a model update)."""
        return dataclasses.replace(self, seconds=self.seconds + seconds)


def recheck(lp: LimitLP, direction: int, out: Outcome) -> Outcome:
    """Check an optimal one-shot outcome independently of the back end.

    The forces must satisfy equilibrium, ``n >= 0`` and Coulomb within
    :data:`MAX_RESIDUAL`; otherwise the status becomes ``inaccurate`` and
    the load factor NaN. ``info`` gains ``primal_residual``, ``live_work``
    and ``raw_load_factor``.

    Args:
        lp: the LP solved.
        direction: ``+1`` or ``-1``.
        out: an optimal outcome with ``n``, ``s``, ``duals`` and ``load_factor``.

    Returns:
        The outcome, checked.
    """
    assert out.n is not None and out.s is not None and out.duals is not None
    lam = float(direction) * out.load_factor  # the value of the lambda column
    res = lp.primal_residual(out.n, out.s, lam)
    live_work = float(direction) * exact_dot(lp.live, out.duals)
    info = {**out.info, "primal_residual": res, "live_work": live_work, "raw_load_factor": out.load_factor}
    if not np.isfinite(res) or res > MAX_RESIDUAL:
        return dataclasses.replace(out, status=Status.INACCURATE, load_factor=math.nan, info=info)
    return dataclasses.replace(out, info=info)


#: The largest count an option may hold: HiGHS' integer options are 32-bit (``HighsInt``), and a
#: larger count (``10**400``) reached them as an ``OverflowError``.
MAX_INTEGER = 2**31 - 1


class Backend(Protocol):
    """The interface every one-shot back end implements."""

    name: str

    def solve(self, direction: int) -> Outcome:
        """Solve for the live load in ``+x`` (``direction=+1``) or ``-x`` (``-1``)."""
        ...


def finite_real(value: Any) -> float | None:
    """``value`` as a finite float, ``None`` when it is no real number (a bool, a string, ``None``), NaN,
    infinite or an integer beyond the doubles (``10**400``, whose ``math.isfinite`` raises ``OverflowError``)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return None
    try:
        x = float(value)
    except OverflowError:
        return None
    return x if math.isfinite(x) else None


def check_time_limit(time_limit: float | None) -> float | None:
    """``None`` (no limit) or a positive finite number of seconds.

    Raises:
        ValueError: ``"time_limit must be a positive number of seconds, got ..."``.
    """
    if time_limit is None:
        return None
    x = finite_real(time_limit)
    if x is None or x <= 0:
        raise ValueError(f"time_limit must be a positive number of seconds, got {time_limit!r}")
    return x


def check_number(name: str, value: Any, lower: float = 0.0) -> None:
    """A finite number above ``lower`` (booleans refused).

    Raises:
        ValueError: ``"<name> must be a positive finite number, got ..."``.
    """
    x = finite_real(value)
    if x is None or x <= lower:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")


def check_integer(name: str, value: Any, minimum: int, maximum: int = MAX_INTEGER) -> None:
    """An integer of at least ``minimum`` and at most ``maximum`` (booleans refused).

    Raises:
        ValueError: ``"<name> must be an integer >= <minimum>, got ..."``, or ``"... an integer in
            <minimum>..<maximum>, got ..."`` for one above ``maximum``.
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if value > maximum:
        raise ValueError(f"{name} must be an integer in {minimum}..{maximum:,}, got {value!r}")
