"""Non-associative (zero-dilatancy) Coulomb friction by a sequence of LPs.

Gilbert, Casapulla & Ahmed (2006) replace the non-associative problem, which
is not an LP, by a sequence of LPs in which the yield condition of every
contact point is rebuilt from the normal forces ``nbar`` of the previous
iterate, until the sequence settles. Two of their rebuilt conditions are
implemented:

``"a"``  fixed shear capacity ``|s| <= mu nbar``. Its associated flow rule
         has no dilatancy. In the persistent HiGHS model it is a pure change
         of the bounds of the ``s`` columns.
``"b"``  a line through ``(nbar, mu nbar)`` with a small negative slope,
         ``|s| <= c0 + (1 + alpha) mu nbar - alpha mu n``, ``alpha`` halved
         every iteration from 0.3 down to 1e-3 (``selections.ALPHA0``, ``ALPHA_MIN``), a
         tiny cohesion ``c0`` so that contacts with ``nbar = 0`` keep a
         feasible point. Two rows per point, ``+s + alpha mu n <= rhs`` and
         ``-s + alpha mu n <= rhs``; their right-hand sides change every
         iterate and, while ``alpha`` changes, their ``n`` coefficients. The
         cap ``n <= nbar (1 + alpha)/alpha + c0/(alpha mu)`` that the line
         implies freezes points with ``nbar ~ 0``; the support can then
         shrink until the LP is infeasible. Such an iterate is replaced by
         one scheme (a) step from the last forces (``algorithm="fallback-a"``).

Relaxation (both schemes): the capacities of iterate ``k + 1`` are built from
``nbar = beta n_k + (1 - beta) n_(k-1)`` (``beta = 1``: none).

Modules, one concept each:

``config``       :class:`NonAssociativeOptions` (what a user sets, with its :class:`Tuning`: the
                 research knobs), the policy constants, and :func:`resolve`: the options resolved for
                 one wall into what the stages read (:class:`Resolved`, nothing copied);
``model``        the persistent HiGHS model of one direction and its updates;
``iteration``    the sequence of one direction: start, loop, finish;
``warm_cold``    when the sequence solves an iterate warm and when cold (counted in simplex iterations);
``pipeline``     one direction: the fallback chain, in plain code (the vertex sequence, the
                 proximal retry, the fused wall with the continuation);
``fusion``       the fused wall: the blocks that move as one rigid body joined, their LP, and
                 its state made the wall's;
``selections``   the selections (vertex, proximal, continuation), one object each behind one
                 interface, and the stops (the exact stop, the settle test, cycles);
``proximal``     the proximal selection's projection (its QP solved by the back ends);
``certificate``  is an iterate's mechanism an exact collapse state? the mechanism band;
``checks``       final-state residuals, the cold re-solve, :func:`verify_collapse_state`;
``results``      the types: :class:`IterationRecord`, :class:`SequenceDiagnostics`,
                 :class:`NonAssociativeResult`;
``descent``      the descent to the lowest certified collapse state (``options.lowest``): a
                 subpackage, ``lowest`` (the walk) and ``states`` (the two LPs of a contact
                 pattern: least ``lambda``, a compatible mechanism), ``results`` (its type).

After a converged run, the descent (on by default) reports the lowest
certified collapse state it reaches (``lowest_load_factor``), which is then the
value to quote (``load_factor``), beside the iterated LP's own fixed point
(``iterated_load_factor``, unchanged by the descent). The search for the
global minimum is not part of this method: its caller composes it,
``micro.global_search.solve_global(lp, start=result)``, for a proven lower
bound (``global_lower_bound``) and the gap.

A sequence stops as ``converged`` (exactly, or certified), ``cycling``
(``lambda_band`` is ``[min, max]`` over the cycle or the last window),
``max_iterations`` (the cap on LPs or the work budget
``max_simplex_iterations``), ``time_limit`` (a user's wall-clock stop,
``max_seconds`` or ``time_limit``: no final answer), or ``solver_failure``
(an LP failed warm and cold, or the final iterate re-solved cold disagrees
with the warm one). The load factor of a sequence that did not converge is
NaN; the last value and the band are reported beside it.
"""

from __future__ import annotations

import time
from typing import Any

from micro.geometry import BlockWall, check_block_wall
from micro.limit_result import DirectionResult, load_directions
from micro.lp import assemble
from micro.nonassociative.config import (
    DEFAULT_RELAXATION,
    FUSE_BLOCKS,
    LOWEST_BUDGET,
    SCHEMES,
    SELECTIONS,
    TUNING_KNOBS,
    LPProgress,
    NonAssociativeOptions,
    Progress,
    Resolved,
    Tuning,
    continuation_allowed,
    resolve,
)
from micro.nonassociative.descent.lowest import lowest_state
from micro.nonassociative.descent.lowest_direction import LowestDirection
from micro.nonassociative.final_checks import verify_collapse_state
from micro.nonassociative.nonassociative_result import (
    CONVERGED,
    CYCLING,
    MAX_ITERATIONS,
    SOLVER_FAILURE,
    STATUSES,
    TIME_LIMIT,
    FusionDiagnostics,
    IterationRecord,
    NonAssociativeResult,
    SequenceDiagnostics,
)
from micro.nonassociative.reduced import solve_direction
from micro.nonassociative.selections import detect_cycle

__all__ = [
    "CONVERGED", "CYCLING", "DEFAULT_RELAXATION", "FUSE_BLOCKS", "MAX_ITERATIONS", "SCHEMES", "SELECTIONS",
    "SOLVER_FAILURE", "STATUSES", "TIME_LIMIT", "FusionDiagnostics",
    "IterationRecord", "LOWEST_BUDGET", "LPProgress", "LowestDirection", "NonAssociativeOptions",
    "NonAssociativeResult", "Progress", "Resolved", "SequenceDiagnostics", "TUNING_KNOBS", "Tuning",
    "continuation_allowed", "detect_cycle", "lowest_state", "resolve", "solve_nonassociative",
    "verify_collapse_state"
]


def solve_nonassociative(wall: BlockWall, options: NonAssociativeOptions | None = None,
                         *, progress: Progress | None = None,
                         **overrides: Any) -> NonAssociativeResult:
    """Collapse load factor of ``wall`` with non-associative (zero-dilatancy) friction.

    With no options this is the method of ``xcheck report`` on every wall:
    scheme (a), the vertex sequence and the proximal one where it cycles, the
    fused wall with the continuation where both fail (and from the start on
    walls of more than :data:`~micro.nonassociative.config.FUSE_BLOCKS`
    blocks), the certificate, and a bounded descent to the lowest certified
    state.

    Args:
        wall: the block assemblage (:func:`micro.build_wall`).
        options: what a user sets, the research knobs in its ``tuning`` (``None``: the defaults, the
            report's method; ``docs/micro/tuning.md``).
        progress: called with one :class:`LPProgress` per LP as it finishes.
        **overrides: option fields to change, e.g. ``lowest=False, time_limit=20``,
            ``tuning=micro.Tuning(scheme="b")``.

    Returns:
        The :class:`NonAssociativeResult`; a sequence that did not converge
        has a NaN load factor and says why.

    Raises:
        ValueError: a bad option (the message names it).
        TypeError: an unknown option name; ``wall``, ``options``, ``tuning`` or ``progress`` of the wrong
            type (``options="fast"``, ``progress="print"``), naming it.

    Examples:
        >>> import micro
        >>> wall = micro.build_wall(length=3.0, block_length=1.0, block_height=0.5, rows=(6,),
        ...                         thickness=(1.0,), overload=(0.0,), unit_weight=1.0, friction=0.75)
        >>> result = micro.solve_nonassociative(wall)
        >>> result.status, result.sequence.stop_reason, round(result.load_factor, 4)
        ('converged', 'certified', 0.5789)
        >>> result.load_factor <= result.associative_load_factor
        True

        The state is exact: every residual of the collapse conditions is
        at rounding level, checked from the forces and the mechanism alone.

        >>> residuals = micro.verify_collapse_state(micro.assemble(wall), result.governing)
        >>> max(v for k, v in residuals.items() if k != "slipping_points") < 1e-9
        True

        Options as keywords, research knobs through ``tuning``:

        >>> plain = micro.solve_nonassociative(wall, lowest=False, tuning=micro.Tuning(certify=False))
        >>> plain.sequence.stop_reason in ("lambda_and_forces", "lambda_and_coulomb", "repeating", "oscillating")
        True
    """
    check_block_wall(wall)
    if options is not None and not isinstance(options, NonAssociativeOptions):
        raise TypeError(f"options must be a micro.NonAssociativeOptions or None, got {options!r} "
                        f"({type(options).__name__})")
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be a function of one LPProgress or None, got {progress!r}")
    o = (options or NonAssociativeOptions()).with_overrides(**overrides)
    r = resolve(wall.n_blocks, o, progress)
    t0 = time.perf_counter()
    lp = assemble(wall)
    build = time.perf_counter() - t0
    results_list: list[DirectionResult] = []
    lowest_list: list[LowestDirection] = []
    for d in load_directions(o.directions, wall.mirror_symmetric):
        res, model = solve_direction(lp, d, r)
        results_list.append(res)
        if res.converged and o.lowest:
            # without the iterated LP's model (a fused wall) the descent makes no proposal (its module docstring)
            searched = isinstance(res.sequence, SequenceDiagnostics) and res.sequence.reduced
            lowest_list.append(lowest_state(lp, res, r, model, proposals=model is not None, searched=searched))
        del model  # the descent has taken over what it needs
        if _on_target(o, res, lowest_list):
            break  # a certified state below ``stop_below``: the other direction is not needed
    results, lowest = tuple(results_list), tuple(lowest_list)
    solve_secs = time.perf_counter() - t0 - build
    failing = [res for res in results if not res.converged]
    if failing:
        g = failing[0]
        lam, direction, status, msg = float("nan"), "", g.status, f"{g.direction}: {g.message}"
    else:
        g = min(results, key=lambda res: res.load_factor)
        lam, direction, status, msg = g.load_factor, g.direction, CONVERGED, ""
    return NonAssociativeResult(
        iterated_load_factor=lam, direction=direction, status=status, scheme=o.tuning.scheme,
        relaxation=o.tuning.beta,
        blocks=wall.n_blocks, contacts=wall.n_contacts, points=lp.n_points, variables=lp.n_cols, rows=lp.n_rows,
        nnz=lp.nnz, build_seconds=build, solve_seconds=solve_secs, mirror_symmetric=wall.mirror_symmetric,
        directions=results, resolved=r, message=msg, lowest=lowest,
    )


def _on_target(o: NonAssociativeOptions, res: DirectionResult, lowest: list[LowestDirection]) -> bool:
    """Whether a direction just solved holds a certified state below ``o.stop_below``: its descent's
    state, or without the descent its iterated LP's converged state."""
    if lowest and lowest[-1].direction == res.direction and lowest[-1].found:
        return o.below_target(lowest[-1].load_factor)
    return res.converged and not o.lowest and o.below_target(res.load_factor)
