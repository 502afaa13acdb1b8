"""Associative limit analysis of a block wall: the public entry point.

:func:`solve_associative` assembles the LP once, makes one back end (a
persistent model), solves it for the live load in ``+x`` and, unless the wall
is mirror-symmetric, in ``-x``; the smaller load factor governs.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from micro.geometry import BlockWall
from micro.lp import LimitLP, assemble
from micro.mechanism import CONTACT_STATE_NAMES, Mechanism, mechanism_from_duals
from micro.records import AssociativeRecord
from micro.solvers import Backend, Status, make_backend

FloatArray = NDArray[np.float64]

_DIR_NAME = {1: "+x", -1: "-x"}


@dataclass(frozen=True, eq=False)
class DirectionResult:
    """The solution for one direction of the live load.

    Attributes:
        direction: ``"+x"`` or ``"-x"``.
        status: shared status (:class:`micro.solvers.Status` value).
        native_status: the back end's own status.
        load_factor: ``lambda`` (NaN unless ``status == "optimal"``).
        iterations: solver iterations.
        solve_seconds: wall time of the solve.
        normal, shear: point forces (dimensional; ``None`` unless optimal).
        mechanism: the collapse mechanism (``None`` unless optimal).
        info: back-end facts (residual, raw load factor, ...).
    """

    direction: str
    status: str
    native_status: str
    load_factor: float
    iterations: int
    solve_seconds: float
    normal: FloatArray | None = field(repr=False)
    shear: FloatArray | None = field(repr=False)
    mechanism: Mechanism | None = field(repr=False)
    info: dict[str, Any] = field(default_factory=dict, repr=False)


@dataclass(frozen=True, eq=False)
class LimitResult:
    """Result of an associative limit analysis (governing direction first).

    Attributes:
        load_factor: governing (smallest) ``lambda``; NaN when any solve failed.
        direction: governing direction, ``"+x"`` or ``"-x"`` (``""`` on failure).
        status: ``"optimal"`` or the first failing direction's status.
        solver: back end name (e.g. ``"highs-ipm"``).
        build_seconds: wall time of the LP assembly plus the back end's setup.
        solve_seconds: wall time of all solves.
        blocks, contacts, points, variables, rows, nnz: problem sizes.
        iterations: solver iterations of the governing direction (of the
            first failing direction when a solve failed).
        total_iterations: solver iterations summed over the directions.
        normal, shear: point forces of the governing direction (dimensional,
            point ``2c + k`` is end ``k`` of contact ``c``).
        velocities: ``(blocks, 3)`` block velocities ``(u, v, omega)`` of the
            governing mechanism (scaled units; live work = 1).
        contact_state: ``(contacts,)`` state names ``closed``/``opening``/``sliding``.
        mirror_symmetric: the wall is its own mirror image (one direction solved).
        directions: per-direction results.
        message: a one-line explanation when the status is not optimal.
    """

    load_factor: float
    direction: str
    status: str
    solver: str
    build_seconds: float
    solve_seconds: float
    blocks: int
    contacts: int
    points: int
    variables: int
    rows: int
    nnz: int
    iterations: int
    total_iterations: int
    normal: FloatArray | None = field(repr=False)
    shear: FloatArray | None = field(repr=False)
    velocities: FloatArray | None = field(repr=False)
    contact_state: tuple[str, ...] | None = field(repr=False)
    mirror_symmetric: bool
    directions: tuple[DirectionResult, ...] = field(repr=False)
    message: str = ""

    @property
    def ok(self) -> bool:
        """True when the solve was optimal and ``load_factor`` is a number."""
        return self.status == Status.OPTIMAL.value and math.isfinite(self.load_factor)

    @property
    def mechanism(self) -> Mechanism | None:
        """The governing mechanism."""
        for d in self.directions:
            if d.direction == self.direction:
                return d.mechanism
        return None

    def by_direction(self, direction: str) -> DirectionResult:
        """The result for ``"+x"`` or ``"-x"``; for a mirror-symmetric wall
        ``"-x"`` is the mirror image of ``"+x"`` (same load factor)."""
        for d in self.directions:
            if d.direction == direction:
                return d
        if self.mirror_symmetric and self.directions:
            d = self.directions[0]
            return DirectionResult(direction, d.status, d.native_status, d.load_factor, 0, 0.0, None, None, None,
                                   {"mirror_of": d.direction})
        raise KeyError(direction)

    def to_record(self) -> AssociativeRecord:
        """The flat, JSON-ready record of this result (see :mod:`micro.records`)."""
        counts = dict.fromkeys(CONTACT_STATE_NAMES, 0)
        for c in self.contact_state or ():
            counts[c] += 1
        by_dir = {d.direction: d.load_factor for d in self.directions}
        return AssociativeRecord(
            load_factor=self.load_factor, status=self.status, solver=self.solver, direction=self.direction,
            load_factor_plus=by_dir.get("+x", math.nan), load_factor_minus=by_dir.get("-x", math.nan),
            blocks=self.blocks, contacts=self.contacts, points=self.points, variables=self.variables,
            rows=self.rows, nnz=self.nnz, iterations=self.iterations, total_iterations=self.total_iterations,
            build_seconds=self.build_seconds, solve_seconds=self.solve_seconds,
            mirror_symmetric=self.mirror_symmetric, closed_contacts=counts["closed"],
            opening_contacts=counts["opening"], sliding_contacts=counts["sliding"], message=self.message,
        )

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary: the record (:meth:`to_record`) with the contact
        states and the directions as nested objects."""
        record = self.to_record()
        return {
            **record.to_dict(),
            "contact_states": record.contact_states if self.contact_state is not None else {},
            "directions": {
                d.direction: {
                    "load_factor": None if not math.isfinite(d.load_factor) else d.load_factor,
                    "status": d.status,
                    "native_status": d.native_status,
                    "iterations": d.iterations,
                    "solve_seconds": d.solve_seconds,
                }
                for d in self.directions
            },
        }


def solve_associative(
    wall: BlockWall,
    *,
    solver: str = "highs",
    directions: Literal["auto", "both", "+x", "-x"] = "auto",
    time_limit: float | None = None,
) -> LimitResult:
    """Collapse load factor of ``wall`` with associative friction (one LP per direction).

    Args:
        wall: the block assemblage (:func:`micro.build_wall`).
        solver: back end, one of :data:`micro.solvers.SOLVERS` (default
            ``"highs"``: HiGHS interior point without crossover).
        directions: ``"auto"`` (both, unless the wall is mirror-symmetric),
            ``"both"``, ``"+x"`` or ``"-x"``.
        time_limit: seconds per solve (``None``: unlimited).

    Returns:
        The :class:`LimitResult`. A failed solve is reported in ``status``
        (``infeasible`` — the wall cannot stand under its own weight;
        ``unbounded`` — no live load or nothing limits it; ``time_limit``,
        ``iteration_limit``, ``inaccurate``, ``solver_error``) with a NaN load
        factor, never as a number.

    Raises:
        ValueError: an unknown solver or directions value.
    """
    if directions not in ("auto", "both", "+x", "-x"):
        raise ValueError(f"directions must be 'auto', 'both', '+x' or '-x', got {directions!r}")
    t0 = time.perf_counter()
    lp = assemble(wall)
    backend = make_backend(lp, solver, time_limit=time_limit)
    build = time.perf_counter() - t0
    symmetric = wall.mirror_symmetric
    if directions == "auto":
        dirs = (1,) if symmetric else (1, -1)
    elif directions == "both":
        dirs = (1, -1)
    else:
        dirs = (1,) if directions == "+x" else (-1,)
    return _solve(lp, backend, dirs, build, symmetric)


def _solve(lp: LimitLP, backend: Backend, dirs: tuple[int, ...], build: float, symmetric: bool) -> LimitResult:
    results: list[DirectionResult] = []
    fs = lp.force_scale
    for d in dirs:
        raw = backend.solve(d)
        mech = None
        normal = shear = None
        info = dict(raw.info)
        lam = raw.load_factor
        status = raw.status
        if status is Status.OPTIMAL and raw.velocities is not None:
            mech = mechanism_from_duals(lp, raw.velocities, d)
            info["virtual_work_residual"] = mech.virtual_work_residual(lam)
            normal = raw.n * fs if raw.n is not None else None
            shear = raw.s * fs if raw.s is not None else None
            if lam < 0.0:
                # the feasible interval of lambda does not contain 0
                status, lam = Status.INFEASIBLE, float("nan")
                info["reason"] = "equilibrium needs a live load in the opposite direction"
        results.append(
            DirectionResult(_DIR_NAME[d], status.value, raw.native_status, lam, raw.iterations,
                            raw.solve_seconds, normal, shear, mech, info)
        )
    solve_secs = sum(r.solve_seconds for r in results)
    total = sum(r.iterations for r in results)
    failed = [r for r in results if r.status != Status.OPTIMAL.value]
    sizes = dict(
        blocks=lp.wall.n_blocks, contacts=lp.wall.n_contacts, points=lp.n_points,
        variables=lp.n_cols, rows=lp.n_rows, nnz=lp.nnz,
    )
    if failed:
        f = failed[0]
        msg = {
            "infeasible": "no equilibrium: the wall cannot stand under its own weight",
            "unbounded": "the load factor is unbounded (no live load, or nothing limits it)",
        }.get(f.status, f"solver {backend.name} stopped with {f.status} ({f.native_status}) for {f.direction}")
        return LimitResult(float("nan"), "", f.status, backend.name, build, solve_secs, iterations=f.iterations,
                           total_iterations=total,
                           normal=None, shear=None, velocities=None, contact_state=None,
                           mirror_symmetric=symmetric, directions=tuple(results), message=msg, **sizes)
    gov = min(results, key=lambda r: r.load_factor)
    mech = gov.mechanism
    states = tuple(CONTACT_STATE_NAMES[i] for i in mech.contact_state) if mech is not None else None
    return LimitResult(
        gov.load_factor, gov.direction, Status.OPTIMAL.value, backend.name, build, solve_secs,
        iterations=gov.iterations, total_iterations=total,
        normal=gov.normal, shear=gov.shear, velocities=None if mech is None else mech.velocities,
        contact_state=states, mirror_symmetric=symmetric, directions=tuple(results), **sizes,
    )
