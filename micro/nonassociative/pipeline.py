"""One load direction: which sequences run, on the wall or on its fused bodies, and their joint result.

:func:`solve_chain` is what :func:`micro.solve_nonassociative` runs on a
direction: the fused wall (``fuse``), or the fallback chain :func:`run_stages`,
plain code run in order, each stage where the ones before it failed: the vertex
sequence, the proximal one (``"vertex+proximal"``), the fused wall with the
continuation (``fused_retry``). A new stage is one more step there. One sequence
is :class:`~micro.nonassociative.iteration.LPSequence` with its :mod:`~micro.nonassociative.selections` object.

The fused wall itself (its bodies, its LP, its state made the wall's) is
:mod:`micro.nonassociative.fusion`'s; :func:`solve_fused` composes it with the
sequences' stages.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.limit_result import DirectionResult
from micro.lp import LimitLP
from micro.nonassociative.config import Resolved
from micro.nonassociative.fusion import fused_wall, on_the_wall
from micro.nonassociative.iteration import LPSequence
from micro.nonassociative.model import IterationModel

FloatArray = NDArray[np.float64]

#: ``"vertex+proximal"`` runs the proximal sequence on a direction whose vertex
#: sequence ended with one of these statuses.
RETRY_STATUSES = ("cycling", "max_iterations")

#: A direction's result with the model of the sequence that gave it, after
#: its last LP (``None`` where that model is not on the wall's own LP: the
#: fused wall); the descent to the lowest state takes it over.
Solved = tuple[DirectionResult, IterationModel | None]


@dataclass(frozen=True, eq=False)
class Attempt:
    """What the stages of a direction have given so far.

    Attributes:
        result: the joined result (the LPs and seconds of every stage that ran).
        model: the model of the sequence that gave it (:data:`Solved`).
        sequence: the last sequence run on the wall's own LP (its associative
            LP is reused by the next sequence there), or ``None``.
    """

    result: DirectionResult
    model: IterationModel | None
    sequence: LPSequence | None = None


def _first_sequence(lp: LimitLP, direction: int, resolved: Resolved, start: FloatArray | None) -> Attempt:
    """The first sequence: the selection resolved (the vertex one of ``"vertex+proximal"``), its ``nbar``
    started from ``start`` (:class:`LPSequence`)."""
    selection = "vertex" if resolved.selection.startswith("vertex+") else resolved.selection
    seq = LPSequence(lp, direction, dataclasses.replace(resolved, selection=selection), start=start)
    return Attempt(seq.run(), seq.model, seq)


def _proximal_retry(lp: LimitLP, direction: int, resolved: Resolved, before: Attempt) -> Attempt:
    """The proximal sequence (at most ``retry_iterations`` LPs), its ``nbar`` started from the vertex
    sequence's last normal forces rather than the associative LP's; its result is the direction's,
    with the vertex sequence in ``sequence.vertex_attempt`` and the LPs and seconds of both."""
    assert before.sequence is not None
    first = before.result
    start = None if first.normal is None else np.asarray(first.normal) / lp.force_scale
    retry = dataclasses.replace(resolved, selection="proximal", max_lps=resolved.tuning.retry_iterations,
                                continuation=False)
    again = LPSequence(lp, direction, retry, start=start, iterate0=before.sequence.iterate0)
    second = again.run()
    assert second.sequence is not None
    message = second.message if second.converged else f"proximal: {second.message}; vertex: {first.message}"
    return Attempt(joined(first, second, second, message=message,
                          sequence=dataclasses.replace(second.sequence, vertex_attempt=first.sequence)),
                   again.model, again)


def _fused_continuation(lp: LimitLP, direction: int, resolved: Resolved, before: Attempt) -> Attempt:
    """The fused wall with the continuation, where the wall's own sequences failed. A certified run is
    the direction's result, with the wall's sequences in ``sequence.unfused_attempt``; a failed one
    leaves the wall's result, its message extended. Either way the LPs and seconds of all runs count.
    Why it is in the chain (walls on which the vertex and the proximal sequences both end at their caps,
    certified by it): the research page on the fused retry (``docs/research/``)."""
    first = before.result
    third, _ = solve_fused(lp, direction, dataclasses.replace(resolved, fuse=True, continuation=True))
    assert first.sequence is not None and third.sequence is not None
    if not third.converged:
        return Attempt(joined(first, third, first,
                              message=f"{first.message}; the fused wall with the continuation: {third.message}"),
                       before.model)
    return Attempt(joined(first, third, third,
                          sequence=dataclasses.replace(third.sequence, unfused_attempt=first.sequence)), None)


def _failed(attempt: Attempt) -> bool:
    """Whether the stages so far ended where the next one runs (one of :data:`RETRY_STATUSES`)."""
    return attempt.result.status in RETRY_STATUSES


def run_stages(lp: LimitLP, direction: int, resolved: Resolved, start: FloatArray | None = None, *,
               fused_retry: bool = True) -> Solved:
    """The fallback chain of a direction, in order, each stage where the ones before it ended with one
    of :data:`RETRY_STATUSES`: the first sequence (the vertex one, or the one selection asked for); with
    ``"vertex+proximal"`` the proximal retry; then, with the ``fused_retry`` knob on scheme (a) and no
    continuation, the fused wall with the continuation (``fused_retry=False``: not that one, as on the
    fused wall itself). A new stage is one more step here.

    Returns:
        The direction's result and the model of the sequence that gave it (:data:`Solved`).
    """
    done = _first_sequence(lp, direction, resolved, start)
    if not resolved.selection.startswith("vertex+"):
        return done.result, done.model
    if _failed(done):
        done = _proximal_retry(lp, direction, resolved, done)
    t = resolved.tuning
    if fused_retry and t.fused_retry and not resolved.continuation and t.scheme == "a" and _failed(done):
        done = _fused_continuation(lp, direction, resolved, done)
    return done.result, done.model


def joined(first: DirectionResult, second: DirectionResult, result: DirectionResult,
           **changes: Any) -> DirectionResult:
    """``result`` (one of two runs on a direction, ``first`` then ``second``)
    with the LPs and seconds of both, and ``changes``."""
    return dataclasses.replace(result, iterations=first.iterations + second.iterations,
                               seconds=first.seconds + second.seconds, **changes)


def solve_fused(lp: LimitLP, direction: int, resolved: Resolved) -> Solved:
    """The iterated LP of one direction on the fused wall
    (:func:`~micro.nonassociative.fusion.fused_wall`): the wall's sequences (the stages but the fused one)
    run on the bodies' LP, and :func:`~micro.nonassociative.fusion.on_the_wall` makes
    their state the wall's, or rejects it. Where the associative LP fails, or
    nothing moves, the wall itself runs instead."""
    t0 = time.perf_counter()
    unfused = dataclasses.replace(resolved, fuse=False)
    made = fused_wall(lp, direction, resolved)
    if made is None:
        return run_stages(lp, direction, unfused, fused_retry=False)
    fused, assoc = made
    t_fuse = time.perf_counter() - t0
    # the continuation starts from the wall's associative forces at the points kept
    start = (np.maximum(np.asarray(assoc.n)[fused.points], 0.0) if resolved.continuation and assoc.n is not None
             else None)
    r, _ = run_stages(fused.lp, direction, unfused, start, fused_retry=False)
    return on_the_wall(lp, direction, fused, assoc, r, resolved, t0, t_fuse), None  # its model is the bodies' LP


def solve_chain(lp: LimitLP, direction: int, resolved: Resolved) -> Solved:
    """One load direction as ``resolved`` asks: the fused wall (``fuse``: walls of more than
    :data:`~micro.nonassociative.config.FUSE_BLOCKS` blocks), or the fallback chain (:func:`run_stages`) on
    the wall. (The reduced wall, tried before it on large walls, is
    :func:`micro.nonassociative.reduced.solve_reduced`'s.)"""
    if resolved.fuse:
        return solve_fused(lp, direction, resolved)
    return run_stages(lp, direction, resolved)
