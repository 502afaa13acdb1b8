"""One load direction: which sequences run, one after another, and their joint result.

:func:`solve_chain` is what :func:`micro.solve_nonassociative` runs on a
direction: the fused wall (``fuse``), or the wall's own sequences
(:func:`solve_direction`: the vertex sequence, and the proximal one where it
fails) and, where those fail too, the fused wall with the
continuation (``fused_retry``). One sequence is
:class:`~micro.nonassociative.iteration.LPSequence` with its
:mod:`~micro.nonassociative.selections` object; the fusing is
:mod:`~micro.nonassociative.fusion`'s.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.lp import LimitLP
from micro.nonassociative.fusion import fused_wall, on_the_wall
from micro.nonassociative.iteration import LPSequence
from micro.nonassociative.recipe import Recipe
from micro.nonassociative.tuning import RETRY_STATUSES, SelectionName
from micro.results import DirectionResult

FloatArray = NDArray[np.float64]


def solve_direction(lp: LimitLP, direction: int, options: Recipe,
                    start: FloatArray | None = None) -> DirectionResult:
    """The iterated LP on one load direction with ``options.selection``.

    ``"vertex+proximal"`` runs the vertex sequence, and where it ends with a
    status of :data:`~micro.nonassociative.tuning.RETRY_STATUSES` the
    proximal sequence (at most ``options.retry_iterations`` LPs), its
    ``nbar`` started from the vertex sequence's last normal forces rather
    than the associative LP's. The second result is
    returned with the vertex sequence in ``sequence.vertex_attempt``, and
    the LPs and seconds of both. ``start``: normal forces to start the
    (first) sequence's ``nbar`` from (:class:`LPSequence`).
    """
    if not options.selection.startswith("vertex+"):
        return LPSequence(lp, direction, options, start=start).run()
    retry: SelectionName = "proximal"
    vertex = LPSequence(lp, direction, dataclasses.replace(options, selection="vertex"), start=start)
    first = vertex.run()
    if first.status not in RETRY_STATUSES:
        return first
    cap = options.max_iterations if options.retry_iterations is None else options.retry_iterations
    start = None if first.normal is None else np.asarray(first.normal) / lp.force_scale
    second = LPSequence(lp, direction, dataclasses.replace(options, selection=retry, max_iterations=cap,
                                                         continuation=False),
                      start=start, iterate0=vertex.iterate0).run()
    assert second.sequence is not None
    message = second.message if second.converged else f"{retry}: {second.message}; vertex: {first.message}"
    return joined(first, second, second, message=message,
                  sequence=dataclasses.replace(second.sequence, vertex_attempt=first.sequence))


def joined(first: DirectionResult, second: DirectionResult, result: DirectionResult,
           **changes: Any) -> DirectionResult:
    """``result`` (one of two runs on a direction, ``first`` then ``second``)
    with the LPs and seconds of both, and ``changes``."""
    return dataclasses.replace(result, iterations=first.iterations + second.iterations,
                               seconds=first.seconds + second.seconds, **changes)


def solve_fused(lp: LimitLP, direction: int, options: Recipe) -> DirectionResult:
    """The iterated LP of one direction on the fused wall
    (:func:`~micro.nonassociative.fusion.fused_wall`): the sequences run on
    the bodies' LP, and :func:`~micro.nonassociative.fusion.on_the_wall` makes
    their state the wall's, or rejects it. Where the associative LP fails, or
    nothing moves, the wall itself runs instead."""
    t0 = time.perf_counter()
    unfused = dataclasses.replace(options, fuse=False)
    made = fused_wall(lp, direction, options)
    if made is None:
        return solve_direction(lp, direction, unfused)
    fused, assoc = made
    t_fuse = time.perf_counter() - t0
    # the continuation starts from the wall's associative forces at the points kept
    start = np.maximum(np.asarray(assoc.n)[fused.points], 0.0) if options.continuation and assoc.n is not None else None
    r = solve_direction(fused.lp, direction, unfused, start=start)
    return on_the_wall(lp, direction, fused, assoc, r, options, t0, t_fuse)


def solve_chain(lp: LimitLP, direction: int, options: Recipe) -> DirectionResult:
    """One load direction as ``options`` ask: the fused wall (``fuse``), or
    the wall's own sequences (:func:`solve_direction`) and, where those of
    ``"vertex+proximal"`` (scheme (a)) both end
    ``cycling`` or ``max_iterations``, the fused wall with the continuation
    (``fused_retry``).

    It certified the two error-map walls (882 and 1,314 blocks) on which the
    vertex and the proximal sequences end at their caps (measurements:
    ``docs/research/2026-11-25-nonassociative-recipe.md``).

    A certified third run is returned with the wall's sequences in
    ``sequence.unfused_attempt``; a failed one leaves the wall's result,
    its message extended. Either way the LPs and seconds of all runs count.
    """
    if options.fuse:
        return solve_fused(lp, direction, options)
    first = solve_direction(lp, direction, options)
    if (not options.fused_retry or options.continuation or options.scheme != "a"
            or not options.selection.startswith("vertex+") or first.status not in RETRY_STATUSES):
        return first
    third = solve_fused(lp, direction, dataclasses.replace(options, fuse=True, continuation=True))
    assert first.sequence is not None and third.sequence is not None
    if not third.converged:
        return joined(first, third, first,
                      message=f"{first.message}; the fused wall with the continuation: {third.message}")
    return joined(first, third, third, sequence=dataclasses.replace(third.sequence, unfused_attempt=first.sequence))
