"""The iterated LP of one load direction: the selection's sequence, and the retry where a vertex sequence fails.

:class:`~micro.nonassociative.iteration.Sequence` is one sequence;
:func:`solve_direction` decides which run on a direction (``"vertex"``,
``"lazy"``, ``"proximal"`` alone, or the vertex sequence followed by the lazy
or proximal one) and joins their results.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
from numpy.typing import NDArray

from micro.lp import LimitLP
from micro.nonassociative.iteration import Sequence
from micro.nonassociative.recipe import Recipe
from micro.nonassociative.tuning import RETRY_STATUSES, Selection
from micro.results import DirectionResult

FloatArray = NDArray[np.float64]


def solve_direction(lp: LimitLP, direction: int, options: Recipe,
                    start: FloatArray | None = None) -> DirectionResult:
    """The iterated LP on one load direction with ``options.selection``.

    ``"vertex+lazy"`` (``"vertex+proximal"``) runs the vertex sequence, and
    where it ends with a status of
    :data:`~micro.nonassociative.tuning.RETRY_STATUSES` the lazy (proximal)
    sequence (at most ``options.retry_iterations`` LPs), its ``nbar``
    started from the vertex sequence's last normal forces rather than the
    associative LP's: Set 2 (1,230 blocks) was certified after 17 lazy LPs
    from there against 30 from the associative forces. The second result is
    returned with the vertex sequence in ``sequence.vertex_attempt``, and
    the LPs and seconds of both. ``start``: normal forces to start the
    (first) sequence's ``nbar`` from (:class:`Sequence`).
    """
    if not options.selection.startswith("vertex+"):
        return Sequence(lp, direction, options, start=start).run()
    retry: Selection = "proximal" if options.selection == "vertex+proximal" else "lazy"
    vertex = Sequence(lp, direction, dataclasses.replace(options, selection="vertex"), start=start)
    first = vertex.run()
    if first.status not in RETRY_STATUSES:
        return first
    cap = options.max_iterations if options.retry_iterations is None else options.retry_iterations
    start = None if first.normal is None else np.asarray(first.normal) / lp.force_scale
    second = Sequence(lp, direction, dataclasses.replace(options, selection=retry, max_iterations=cap,
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
