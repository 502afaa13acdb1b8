"""Associative limit analysis of a block wall: :func:`solve_associative`.

The LP is assembled once and one back end (a persistent model) is made; it is
solved for the live load in ``+x`` and, unless the wall is mirror-symmetric,
in ``-x``; the smaller load factor governs.
"""

from __future__ import annotations

import math
import time

from micro.backends.base import Outcome, Status, check_time_limit
from micro.backends.registry import DEFAULT_SOLVER, make_backend
from micro.geometry import BlockWall, check_block_wall
from micro.limit_result import DIR_NAME, DirectionResult, Directions, LimitResult, check_directions, load_directions
from micro.lp import LimitLP, assemble
from micro.mechanism import mechanism_from_duals

#: The message of a failed analysis, by status.
_FAILURE_MESSAGE = {
    "infeasible": "no equilibrium: the wall cannot stand under its own weight",
    "unbounded": "the load factor is unbounded (no live load, or nothing limits it)",
}


def solve_associative(
    wall: BlockWall,
    *,
    solver: str = DEFAULT_SOLVER,
    directions: Directions = "auto",
    time_limit: float | None = None,
) -> LimitResult:
    """Collapse load factor of ``wall`` with associative friction (one LP per direction).

    Args:
        wall: the block assemblage (:func:`micro.build_wall`).
        solver: back end, one of :data:`micro.SOLVERS` (default
            :data:`micro.DEFAULT_SOLVER`, ``"normal-ipm"``: the suite's interior
            point on the normal equations, the report's back end).
        directions: ``"auto"`` (both, unless the wall is mirror-symmetric),
            ``"both"``, ``"+x"`` or ``"-x"``.
        time_limit: seconds per solve (``None``: unlimited).

    Returns:
        The :class:`~micro.limit_result.LimitResult`. A failed solve is reported
        in ``status`` (``infeasible``: the wall cannot stand under its own
        weight; ``unbounded``: no live load or nothing limits it;
        ``time_limit``, ``iteration_limit``, ``inaccurate``,
        ``solver_error``) with a NaN load factor, never as a number.

    Raises:
        ValueError: an unknown solver or directions value, or a time limit
            that is not a positive number of seconds (checked before any work).
        TypeError: ``wall`` is not a :class:`~micro.geometry.BlockWall`.

    Examples:
        >>> import micro
        >>> wall = micro.build_wall(length=3.0, block_length=1.0, block_height=0.5, rows=(6,),
        ...                         thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=0.75)
        >>> result = micro.solve_associative(wall)
        >>> result.status, round(result.load_factor, 4), result.direction
        ('optimal', 0.639, '+x')

        Another back end answers the same LP:

        >>> other = micro.solve_associative(wall, solver="highs-simplex")
        >>> abs(other.load_factor - result.load_factor) < 1e-6
        True
    """
    check_block_wall(wall)
    check_directions(directions)
    check_time_limit(time_limit)
    t0 = time.perf_counter()
    lp = assemble(wall)
    backend = make_backend(lp, solver, time_limit=time_limit)
    build = time.perf_counter() - t0
    dirs = load_directions(directions, wall.mirror_symmetric)
    results = tuple(_direction(lp, d, backend.solve(d)) for d in dirs)
    return _limit_result(lp, backend.name, results, build)


def _direction(lp: LimitLP, d: int, out: Outcome) -> DirectionResult:
    """One direction's result from its back-end outcome (forces made dimensional)."""
    info = dict(out.info)
    lam, status = out.load_factor, out.status
    mech = normal = shear = None
    if out.ok and out.duals is not None and out.n is not None and out.s is not None:
        mech = mechanism_from_duals(lp, out.duals, d)
        info["virtual_work_residual"] = mech.virtual_work_residual(lam)
        normal, shear = out.n * lp.force_scale, out.s * lp.force_scale
        if lam < 0.0:
            # the feasible interval of lambda does not contain 0
            status, lam = Status.INFEASIBLE, math.nan
            info["reason"] = "equilibrium needs a live load in the opposite direction"
    return DirectionResult(
        direction=DIR_NAME[d], status=status.value, load_factor=lam, iterations=out.iterations, seconds=out.seconds,
        normal=normal, shear=shear, mechanism=mech, native_status=out.native_status, info=info,
    )


def _limit_result(lp: LimitLP, solver: str, results: tuple[DirectionResult, ...], build: float) -> LimitResult:
    """The governing direction (the smallest load factor), or the first failure."""
    failed = [r for r in results if r.status != Status.OPTIMAL.value]
    gov = failed[0] if failed else min(results, key=lambda r: r.load_factor)
    mech = None if failed else gov.mechanism
    message = ""
    if failed:
        message = _FAILURE_MESSAGE.get(
            gov.status, f"solver {solver} stopped with {gov.status} ({gov.native_status}) for {gov.direction}")
    return LimitResult(
        load_factor=math.nan if failed else gov.load_factor, direction="" if failed else gov.direction,
        status=gov.status, solver=solver, build_seconds=build, solve_seconds=sum(r.seconds for r in results),
        blocks=lp.wall.n_blocks, contacts=lp.wall.n_contacts, points=lp.n_points, variables=lp.n_cols,
        rows=lp.n_rows, nnz=lp.nnz, iterations=gov.iterations, total_iterations=sum(r.iterations for r in results),
        normal=None if failed else gov.normal, shear=None if failed else gov.shear,
        velocities=None if mech is None else mech.velocities,
        contact_state=None if failed else gov.contact_states, mirror_symmetric=lp.wall.mirror_symmetric,
        directions=results, message=message,
    )
