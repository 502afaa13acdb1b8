"""Non-associative (zero-dilatancy) Coulomb friction by a sequence of LPs.

Gilbert, Casapulla & Ahmed (2006) replace the non-associative problem, which
is not an LP, by a sequence of LPs in which the yield condition of every
contact point is rebuilt from the normal forces ``nbar`` of the previous
iterate, until the sequence settles. Two of the published rebuilt conditions
are implemented (see ``/work/shared/methods.md`` §2):

``"a"``  fixed shear capacity ``|s| <= mu nbar``. Its associated flow rule
         has no dilatancy. In the persistent HiGHS model it is a pure change
         of the bounds of the ``s`` columns.
``"b"``  a line through ``(nbar, mu nbar)`` with a small negative slope,
         ``|s| <= c0 + (1 + alpha) mu nbar - alpha mu n``, ``alpha`` halved
         every iteration from ``alpha0`` (0.3) down to ``alpha_min`` (1e-3), a
         tiny cohesion ``c0`` so that contacts with ``nbar = 0`` keep a
         feasible point. Two rows per point,
         ``+s + alpha mu n <= rhs`` and ``-s + alpha mu n <= rhs``; the
         right-hand sides change by ``changeRowsBounds`` and, while ``alpha``
         changes (nine times from 0.3 to 1e-3), the ``2P`` coefficients of
         ``n`` by ``changeCoeff`` (no change of bounds alone can tilt a row).
         Measured: 9 ms for the 14,200 coefficients of the 1,230-block wall,
         against ~1 s for one warm simplex run, so affordable. The cap
         ``n <= nbar (1 + alpha)/alpha + c0/(alpha mu)`` that the line implies
         freezes points with ``nbar ~ 0``; the support can then shrink until
         the LP is infeasible (seen on every Table 7 wall with ``c0 = 1e-6``).
         Such an iterate is replaced by one scheme (a) step from the last
         forces (``algorithm="fallback-a"``; bounds only) and (b) goes on.

Relaxation (both schemes): the capacities of iterate ``k + 1`` are built from
``nbar = beta n_k + (1 - beta) n_(k-1)`` (``beta = 1``: none).

Models (per load direction, each built once): the associative LP (iterate
0, which gives the first ``nbar``) is solved by Clarabel's interior point
(tight tolerances; HiGHS IPM if it fails). The ITERATION model is a
persistent HiGHS model with the columns ``[n, s, lambda]`` over the
equilibrium rows (and for scheme (b) the ``2P`` friction rows). Its first
LP is solved by interior point with crossover (a basis in seconds where a
cold dual simplex takes minutes on a 1,230-block wall) and a dual-simplex
clean-up (crossover alone left residuals ~1e-4); every later iterate
changes bounds (or rows) only and HiGHS' dual simplex restarts from the
previous basis. The final iterate is re-solved COLD (a fresh copy of the
model, interior point, no basis) and the two load factors compared: HiGHS
has open reports of wrong objectives after hot starts (#3294, #3194); when
the interior point disagrees, a cold vertex (its crossover and a dual
simplex, no warm basis) settles it. On large walls a warm run can cost more
than a cold one (7,575 blocks: 170-200 s against 45 s), so an iterate is
solved cold while the last warm run was 1.5x slower than the last cold one.
The certificate below solves the associative LP in generator form with some
columns left out (Clarabel by default, or HiGHS IPM on a persistent model).

Convergence. The LPs are degenerate: their optimal force fields are not
unique, and the simplex returns a vertex whose forces in the parts that do
not move jump from one iterate to the next, so the iterate's own forces
rarely satisfy Coulomb even when ``lambda`` has settled (the plain sequence
converged on 50 of the 104 walls of ``xcheck stability`` without relaxation,
62 with ``beta = 0.6``; with the certificate, 102 and 104). Two stops count
as converged:

* exact (``"lambda_and_forces"`` / ``"lambda_and_coulomb"``): after at
  least two non-associative iterates (for scheme (b) once ``alpha`` has
  reached ``alpha_min``), the relative change of ``lambda`` is below
  ``lambda_tol`` and the iterate satisfies Coulomb with its OWN normal forces
  (``|s| <= mu n`` within ``coulomb_tol``; scheme (b): plus ``c0``); the
  reason says whether the normal forces also settled (``force_tol``);
* certified (``"certified"``): once ``lambda`` has settled (spread at most
  ``settle_tol`` over ``settle_window`` iterates), the current LP's
  mechanism is fixed and the forces are sought among ALL fields, not only
  the LP's optimal ones: with the mechanism given, the non-associative
  collapse conditions on the forces are linear (``n = 0`` where the points
  open, ``s = -sign(slip) mu n`` where they slip, ``|s| <= mu n`` where they
  stick), i.e. a choice of generator columns of the state model. The load
  factors of the states so found form an interval, the MECHANISM BAND
  (two LPs: min and max ``lambda``); when the iterate's ``lambda`` lies in
  it, the state at that ``lambda`` is an exact non-associative collapse
  state (equilibrium, Coulomb with its own normal forces, no dilatancy
  where ``n > 0``, no interpenetration, slip only at the yield line against
  the friction force; energy balance by virtual work) and the sequence
  stops with it. The band is reported (``mechanism_band``): the same
  mechanism can form at any load factor in it, a measure of how far the
  non-associative solution is from unique. Its ends are load factors of
  states found by an interior point (feasible, optimal to ~1e-5), so the
  band can only come out a little narrower than the exact one and a
  certificate is never accepted wrongly.

Otherwise the sequence stops as

* ``cycling``: the ``lambda`` sequence repeats (period 2..6), oscillates
  without contracting over two windows, or stagnates (``lambda`` unchanged
  over a window while the forces make no progress): ``lambda_band`` is
  ``[min, max]`` over the cycle or the last window;
* ``max_iterations``: the cap on LPs (or the time budget ``max_seconds``)
  was reached;
* ``solver_failure``: an LP failed (warm, then restarted cold), or the cold
  re-solve of the final iterate disagrees with the warm one.

:func:`verify_collapse_state` checks any final state independently
(equilibrium, Coulomb, no interpenetration, no dilatancy, slip only at the
yield line and against the friction force, energy balance).

The load factor of a sequence that did not converge is NaN; the last value
and the band are reported beside it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.geometry import BlockWall
from micro.lp import LimitLP, assemble
from micro.mechanism import CONTACT_STATE_NAMES, STATE_TOL, Mechanism, mechanism_from_duals
from micro.records import NonAssociativeRecord
from micro.solvers import HighsBackend, Status

FloatArray = NDArray[np.float64]

#: Values of ``status``.
CONVERGED, CYCLING, MAX_ITERATIONS, SOLVER_FAILURE = "converged", "cycling", "max_iterations", "solver_failure"
STATUSES = (CONVERGED, CYCLING, MAX_ITERATIONS, SOLVER_FAILURE)
#: Published rebuilt yield conditions implemented here.
SCHEMES = ("a", "b")
#: Default relaxation ``beta`` per scheme (``n̄ = beta n_k + (1 - beta) n_(k-1)``).
DEFAULT_RELAXATION = {"a": 0.6, "b": 0.6}

_DIR_NAME = {1: "+x", -1: "-x"}
#: Largest closing rate (relative to the largest rate) that the certificate
#: still reads as dual noise rather than interpenetration.
_INTERPENETRATION = 1e-3
#: Clarabel settings of the certificate LPs (their ends are checked for
#: feasibility, so optimality to 1e-9 is enough).
_STATE_CLARABEL = {"static_regularization_constant": 1e-8, "tol_gap_abs": 1e-9, "tol_gap_rel": 1e-9, "tol_feas": 1e-9}


@dataclass(frozen=True)
class IterationRecord:
    """One LP of the sequence.

    Attributes:
        iteration: 0 for the associative LP, then 1, 2, ...
        load_factor: ``lambda`` of this LP (NaN if it failed).
        lambda_change: ``|lambda_k - lambda_(k-1)| / |lambda_k|`` (NaN for k = 0).
        max_dn: ``max |n_k - n_(k-1)|`` relative to ``max n_k`` (NaN for k = 0).
        coulomb_residual: ``max(|s_k| - mu n_k, 0)`` relative to ``max n_k``.
        alpha: slope parameter of scheme (b) (0 for scheme (a) and k = 0).
        simplex_iterations: simplex iterations of this LP.
        ipm_iterations: interior-point iterations of this LP.
        seconds: wall time of the solve (and of the model update before it).
        algorithm: ``"ipm"``, ``"ipm+crossover+simplex"`` or ``"simplex-warm"``
            (``"simplex-cold"`` after a failed warm run).
        status: the LP's status (:class:`micro.solvers.Status` value).
        certificate: ``""`` (not tried), ``"not found"`` (no collapse
            state at this ``lambda`` with this LP's mechanism, or the try
            hit its time limit) or ``"certified"`` (see
            :meth:`_Sequence._certify`); ``coulomb_residual`` is then that
            of the certified field.
        certificate_seconds, certificate_iterations: cost of the try
            (interior-point iterations).
    """

    iteration: int
    load_factor: float
    lambda_change: float
    max_dn: float
    coulomb_residual: float
    alpha: float
    simplex_iterations: int
    ipm_iterations: int
    seconds: float
    algorithm: str
    status: str
    certificate: str = ""
    certificate_seconds: float = 0.0
    certificate_iterations: int = 0

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (NaN -> None)."""
        out: dict[str, Any] = {}
        for k, v in self.__dict__.items():
            out[k] = None if isinstance(v, float) and not math.isfinite(v) else v
        return out


@dataclass(frozen=True, eq=False)
class NonAssocDirection:
    """The iterated scheme for one direction of the live load.

    Attributes:
        direction: ``"+x"`` or ``"-x"``.
        status: one of :data:`STATUSES`.
        stop_reason: what stopped the sequence (``"lambda_and_forces"``,
            ``"lambda_and_coulomb"``, ``"certified"``, ``"repeating"``,
            ``"oscillating"``, ``"stagnation"``, ``"max_iterations"``,
            ``"time_budget"``, ``"lp_failed"``,
            ``"cold_check_failed"``, ``"associative_failed"``).
        load_factor: ``lambda`` (NaN unless converged).
        last_load_factor: ``lambda`` of the last successful iterate.
        lambda_band: ``(min, max)`` of ``lambda`` over the detected cycle or
            the last window (``None`` when converged).
        associative_load_factor: ``lambda`` of the associative LP.
        iterations: non-associative LPs solved.
        history: every LP, the associative one first.
        cold_load_factor: ``lambda`` of the final iterate re-solved cold.
        warm_cold_rel_diff: ``|warm - cold| / |cold|``.
        coulomb_residual: ``max(|s| - mu n, 0)`` with the final forces,
            relative to ``max n``.
        dilatancy_residual: largest ``|opening rate|`` at sliding points in
            contact (``n > 0``) of the final mechanism, relative to the
            largest slip rate.
        equilibrium_residual: largest equilibrium violation (block weights).
        sliding_points: points of the final mechanism that slide while in
            contact.
        normal, shear: final point forces (dimensional), or ``None``.
        mechanism: the final LP's mechanism, or ``None``.
        seconds: wall time of the whole sequence incl. the cold check.
        message: a one-line explanation.
        cold_algorithm: ``"ipm"`` or ``"simplex"`` (when IPX gave up).
        fallback_steps: scheme (b) LPs replaced by a scheme (a) step.
        mechanism_band: ``(min, max)`` of ``lambda`` over ALL collapse
            states with the final mechanism (certified runs, and converged
            scheme (a) runs; ``None`` otherwise): the non-associative problem
            has many solutions, and the same mechanism can form at any load
            factor in this band.
    """

    direction: str
    status: str
    stop_reason: str
    load_factor: float
    last_load_factor: float
    lambda_band: tuple[float, float] | None
    associative_load_factor: float
    iterations: int
    history: tuple[IterationRecord, ...] = field(repr=False)
    cold_load_factor: float
    warm_cold_rel_diff: float
    coulomb_residual: float
    dilatancy_residual: float
    equilibrium_residual: float
    sliding_points: int
    normal: FloatArray | None = field(repr=False)
    shear: FloatArray | None = field(repr=False)
    mechanism: Mechanism | None = field(repr=False)
    seconds: float
    message: str = ""
    cold_algorithm: str = ""
    fallback_steps: int = 0
    mechanism_band: tuple[float, float] | None = None

    @property
    def converged(self) -> bool:
        """True when the sequence converged."""
        return self.status == CONVERGED


@dataclass(frozen=True, eq=False)
class NonAssociativeResult:
    """Result of the non-associative analysis (governing direction).

    Attributes:
        load_factor: governing ``lambda`` (NaN unless every direction converged).
        direction: governing direction (``""`` unless converged).
        status: :data:`CONVERGED` only if every direction converged, else the
            status of the first direction that did not.
        converged: ``status == "converged"``.
        scheme: ``"a"`` or ``"b"``.
        relaxation: ``beta``.
        iterations: non-associative LPs of the governing (or failing) direction.
        history: its LPs.
        lambda_band: its band when not converged.
        associative_load_factor: smallest associative ``lambda`` over the
            directions solved.
        cold_load_factor, warm_cold_rel_diff, coulomb_residual,
            dilatancy_residual: final-state checks of that direction.
        blocks, contacts, points: sizes of the wall.
        variables, rows, nnz: sizes of the assembled associative LP.
        build_seconds: assembly of the LP.
        solve_seconds: all sequences, incl. cold checks.
        mirror_symmetric: one direction solved.
        directions: per-direction results.
        options: the options used.
        message: explanation when not converged.
    """

    load_factor: float
    direction: str
    status: str
    converged: bool
    scheme: str
    relaxation: float
    iterations: int
    history: tuple[IterationRecord, ...] = field(repr=False)
    lambda_band: tuple[float, float] | None
    associative_load_factor: float
    cold_load_factor: float
    warm_cold_rel_diff: float
    coulomb_residual: float
    dilatancy_residual: float
    blocks: int
    contacts: int
    points: int
    variables: int
    rows: int
    nnz: int
    build_seconds: float
    solve_seconds: float
    mirror_symmetric: bool
    directions: tuple[NonAssocDirection, ...] = field(repr=False)
    options: dict[str, Any] = field(default_factory=dict, repr=False)
    message: str = ""

    @property
    def ok(self) -> bool:
        """True when converged with a finite load factor."""
        return self.converged and math.isfinite(self.load_factor)

    @property
    def mechanism_band(self) -> tuple[float, float] | None:
        """``(min, max)`` of ``lambda`` over the collapse states with the
        governing direction's final mechanism (see :class:`NonAssocDirection`)."""
        return self.governing.mechanism_band

    @property
    def governing(self) -> NonAssocDirection:
        """The direction the summary fields come from."""
        for d in self.directions:
            if d.direction == self.direction:
                return d
        for d in self.directions:
            if not d.converged:
                return d
        return self.directions[0]

    @property
    def total_iterations(self) -> int:
        """Non-associative LPs summed over the directions solved."""
        return sum(d.iterations for d in self.directions)

    def to_record(self) -> NonAssociativeRecord:
        """The flat, JSON-ready record of this result (see :mod:`micro.records`)."""
        g = self.governing
        counts = dict.fromkeys(CONTACT_STATE_NAMES, 0) if g.mechanism is None else g.mechanism.state_counts()
        by_dir = {d.direction: d.load_factor for d in self.directions}
        return NonAssociativeRecord(
            load_factor=self.load_factor, status=self.status, solver=solver_description(self.options),
            direction=self.direction, load_factor_plus=by_dir.get("+x", math.nan),
            load_factor_minus=by_dir.get("-x", math.nan), blocks=self.blocks, contacts=self.contacts,
            points=self.points, variables=self.variables, rows=self.rows, nnz=self.nnz,
            iterations=self.iterations, total_iterations=self.total_iterations, build_seconds=self.build_seconds,
            solve_seconds=self.solve_seconds, mirror_symmetric=self.mirror_symmetric,
            closed_contacts=counts["closed"], opening_contacts=counts["opening"],
            sliding_contacts=counts["sliding"], message=self.message, scheme=self.scheme,
            relaxation=self.relaxation, converged=self.converged, stop_reason=g.stop_reason,
            lambda_band=self.lambda_band, mechanism_band=g.mechanism_band, last_load_factor=g.last_load_factor,
            associative_load_factor=self.associative_load_factor, cold_load_factor=self.cold_load_factor,
            warm_cold_rel_diff=self.warm_cold_rel_diff, coulomb_residual=self.coulomb_residual,
            dilatancy_residual=self.dilatancy_residual,
            history_load_factor=tuple(r.load_factor for r in self.history), cold_algorithm=g.cold_algorithm,
            fallback_steps=sum(d.fallback_steps for d in self.directions),
        )

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary: the record (:meth:`to_record`) with the
        contact states, options, history and directions as nested objects."""

        def num(v: float) -> float | None:
            return v if math.isfinite(v) else None

        record = self.to_record()
        return {
            **record.to_dict(),
            "contact_states": record.contact_states if self.governing.mechanism is not None else {},
            "options": dict(self.options),
            "history": [r.as_dict() for r in self.history],
            "directions": {
                d.direction: {
                    "status": d.status,
                    "stop_reason": d.stop_reason,
                    "load_factor": num(d.load_factor),
                    "last_load_factor": num(d.last_load_factor),
                    "associative_load_factor": num(d.associative_load_factor),
                    "iterations": d.iterations,
                    "seconds": d.seconds,
                }
                for d in self.directions
            },
        }


def solver_description(options: dict[str, Any]) -> str:
    """Which solver does what in the iterated LP, e.g. ``"clarabel (start,
    certificate) + highs-simplex (iterated) + highs-ipm (cold check)"``."""
    roles = [("clarabel" if options["start"] == "interior" else "highs-ipm+crossover", "start")]
    if options["certify"] or options["mechanism_band"]:
        roles.append(("clarabel" if options["state_solver"] == "clarabel" else "highs-ipm", "certificate"))
    roles.append(("highs-simplex", "iterated"))
    if options["cold_check"]:
        roles.append(("highs-ipm", "cold check"))
    by_solver: dict[str, list[str]] = {}
    for solver, role in roles:
        by_solver.setdefault(solver, []).append(role)
    return " + ".join(f"{solver} ({', '.join(r)})" for solver, r in by_solver.items())


# =============================================================================
def solve_nonassociative(
    wall: BlockWall,
    *,
    scheme: Literal["a", "b"] = "a",
    relaxation: float | None = None,
    alpha0: float = 0.3,
    alpha_min: float = 1e-3,
    alpha_factor: float = 0.5,
    cohesion: float = 1e-6,
    max_iterations: int = 100,
    max_seconds: float | None = None,
    lambda_tol: float = 1e-6,
    force_tol: float = 1e-6,
    coulomb_tol: float = 1e-6,
    window: int = 20,
    directions: Literal["auto", "both", "+x", "-x"] = "auto",
    start: Literal["interior", "vertex"] = "interior",
    certify: bool = True,
    settle_tol: float = 1e-3,
    settle_window: int = 3,
    mechanism_band: bool = True,
    state_solver: Literal["clarabel", "highs"] = "clarabel",
    cold_check: bool = True,
    cold_tol: float = 1e-6,
    time_limit: float | None = None,
) -> NonAssociativeResult:
    """Collapse load factor of ``wall`` with non-associative (zero-dilatancy) friction.

    Args:
        wall: the block assemblage (:func:`micro.build_wall`).
        scheme: rebuilt yield condition, ``"a"`` or ``"b"`` (module docstring).
        relaxation: ``beta`` in ``(0, 1]`` (``None``: :data:`DEFAULT_RELAXATION`).
        alpha0, alpha_min, alpha_factor: slope schedule of scheme (b):
            ``alpha_(k+1) = max(alpha_min, alpha_factor * alpha_k)``.
        cohesion: ``c0`` of scheme (b) relative to the largest normal force
            of the associative solution (scale-free; default one millionth
            of the force level).
        max_iterations: cap on non-associative LPs per direction.
        max_seconds: wall-time budget per direction (``None``: none); when
            spent the sequence stops with status ``max_iterations``
            (``stop_reason="time_budget"``).
        lambda_tol: relative change of ``lambda`` for convergence.
        force_tol: largest change of the normal forces, relative to the
            largest normal force, for convergence.
        coulomb_tol: ``max(|s| - mu n, 0) / max n`` accepted as "Coulomb holds".
        window: iterations per window of the oscillation / stagnation tests.
        directions: ``"auto"`` (both unless mirror-symmetric), ``"both"``,
            ``"+x"`` or ``"-x"``.
        start: how the associative LP (iterate 0, which gives the first
            ``nbar``) is solved: ``"interior"`` (default; Clarabel's interior
            point with tight tolerances, HiGHS IPM if it fails: a point near
            the centre of the optimal face, 0.4 s on 1,230 blocks) or
            ``"vertex"`` (HiGHS IPM + crossover + dual simplex: a basic
            optimal solution as a simplex code returns). The first
            non-associative LP is solved by IPM + crossover + dual simplex
            either way. The non-associative solution is not unique and the
            two starts can end at different load factors (~1-2 %).
        certify: once ``lambda`` has settled (its spread over the last
            ``settle_window`` iterates is at most ``settle_tol`` relative),
            ask whether the current iterate's mechanism admits an exact
            collapse state at the current ``lambda`` (two interior-point LPs
            on the associative model with the columns the mechanism allows;
            see ``_Sequence._certify``; at most one try per
            ``settle_window`` iterates). If it does, the sequence stops,
            converged, with ``stop_reason="certified"`` and that state's
            forces. ``False``: only the exact test (Coulomb with the LP's
            own forces) ends a sequence as converged.
        settle_tol, settle_window: when to try the certificate (above).
        state_solver: interior point of the certificate LPs: ``"clarabel"``
            (default) or ``"highs"`` (HiGHS IPM on a persistent model).
        mechanism_band: for a converged scheme (a) sequence, also compute
            the band of load factors over all collapse states with the final
            mechanism (two more interior-point LPs).
        cold_check: re-solve the final iterate cold and compare.
        cold_tol: relative warm/cold difference beyond which the result is a
            ``solver_failure``.
        time_limit: seconds per LP.

    Returns:
        The :class:`NonAssociativeResult`; a sequence that did not converge
        has a NaN load factor and says why.

    Raises:
        ValueError: a bad option (the message names it).
    """
    if scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {', '.join(SCHEMES)}, got {scheme!r}")
    beta = DEFAULT_RELAXATION[scheme] if relaxation is None else relaxation
    if isinstance(beta, bool) or not isinstance(beta, (int, float)) or not (0.0 < float(beta) <= 1.0):
        raise ValueError(f"relaxation must be a number in (0, 1], got {relaxation!r}")
    beta = float(beta)
    for name, v, lo in (("alpha0", alpha0, 0.0), ("alpha_min", alpha_min, 0.0), ("cohesion", cohesion, -1.0),
                        ("lambda_tol", lambda_tol, 0.0), ("force_tol", force_tol, 0.0),
                        ("coulomb_tol", coulomb_tol, 0.0), ("cold_tol", cold_tol, 0.0)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= lo:
            raise ValueError(f"{name} must be a positive finite number, got {v!r}")
    if cohesion < 0:
        raise ValueError(f"cohesion must be >= 0, got {cohesion!r}")
    if alpha_min > alpha0:
        raise ValueError(f"alpha_min ({alpha_min}) must not exceed alpha0 ({alpha0})")
    if not (0.0 < alpha_factor <= 1.0):
        raise ValueError(f"alpha_factor must be in (0, 1], got {alpha_factor!r}")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, int) or max_iterations < 2:
        raise ValueError(f"max_iterations must be an integer >= 2, got {max_iterations!r}")
    if isinstance(window, bool) or not isinstance(window, int) or window < 3:
        raise ValueError(f"window must be an integer >= 3, got {window!r}")
    if isinstance(settle_window, bool) or not isinstance(settle_window, int) or settle_window < 2:
        raise ValueError(f"settle_window must be an integer >= 2, got {settle_window!r}")
    if isinstance(settle_tol, bool) or not isinstance(settle_tol, (int, float)) or not (0.0 <= settle_tol < 1.0):
        raise ValueError(f"settle_tol must be a number in [0, 1), got {settle_tol!r}")
    if directions not in ("auto", "both", "+x", "-x"):
        raise ValueError(f"directions must be 'auto', 'both', '+x' or '-x', got {directions!r}")
    if max_seconds is not None and (isinstance(max_seconds, bool) or not isinstance(max_seconds, (int, float))
                                    or not math.isfinite(max_seconds) or max_seconds <= 0):
        raise ValueError(f"max_seconds must be a positive number of seconds, got {max_seconds!r}")
    if state_solver not in ("clarabel", "highs"):
        raise ValueError(f"state_solver must be 'clarabel' or 'highs', got {state_solver!r}")
    if start not in ("interior", "vertex"):
        raise ValueError(f"start must be 'interior' or 'vertex', got {start!r}")
    if time_limit is not None and (not math.isfinite(time_limit) or time_limit <= 0):
        raise ValueError(f"time_limit must be a positive number of seconds, got {time_limit!r}")

    t0 = time.perf_counter()
    lp = assemble(wall)
    build = time.perf_counter() - t0
    symmetric = wall.mirror_symmetric
    if directions == "auto":
        dirs: tuple[int, ...] = (1,) if symmetric else (1, -1)
    elif directions == "both":
        dirs = (1, -1)
    else:
        dirs = (1,) if directions == "+x" else (-1,)
    opts = dict(scheme=scheme, relaxation=beta, alpha0=float(alpha0), alpha_min=float(alpha_min),
                alpha_factor=float(alpha_factor), cohesion=float(cohesion), max_iterations=max_iterations,
                max_seconds=None if max_seconds is None else float(max_seconds),
                lambda_tol=float(lambda_tol), force_tol=float(force_tol), coulomb_tol=float(coulomb_tol),
                window=window, start=start, certify=bool(certify), settle_tol=float(settle_tol),
                settle_window=settle_window, mechanism_band=bool(mechanism_band), state_solver=state_solver,
                cold_check=cold_check,
                cold_tol=float(cold_tol), time_limit=time_limit)
    results = tuple(_Sequence(lp, d, opts).run() for d in dirs)
    solve_secs = time.perf_counter() - t0 - build
    failing = [r for r in results if not r.converged]
    assoc = min((r.associative_load_factor for r in results), default=float("nan"))
    if failing:
        g = failing[0]
        lam, direction, status = float("nan"), "", g.status
        msg = f"{g.direction}: {g.message}"
    else:
        g = min(results, key=lambda r: r.load_factor)
        lam, direction, status, msg = g.load_factor, g.direction, CONVERGED, ""
    return NonAssociativeResult(
        load_factor=lam, direction=direction, status=status, converged=status == CONVERGED, scheme=scheme,
        relaxation=beta, iterations=g.iterations, history=g.history, lambda_band=g.lambda_band,
        associative_load_factor=assoc, cold_load_factor=g.cold_load_factor,
        warm_cold_rel_diff=g.warm_cold_rel_diff, coulomb_residual=g.coulomb_residual,
        dilatancy_residual=g.dilatancy_residual, blocks=wall.n_blocks, contacts=wall.n_contacts,
        points=lp.n_points, variables=lp.n_cols, rows=lp.n_rows, nnz=lp.nnz, build_seconds=build, solve_seconds=solve_secs, mirror_symmetric=symmetric,
        directions=results, options=opts, message=msg,
    )


# =============================================================================
class _Sequence:
    """The iterated LP for one load direction.

    Two persistent HiGHS models over the same equilibrium rows:

    * the ITERATION model, columns ``[n (P), s (P), lambda]`` (plus, for
      scheme (b), ``2P`` friction rows): every iterate changes bounds (or row
      bounds and coefficients) only and warm-starts the dual simplex. Without
      the associative generator columns each simplex iteration costs ~2/3 of
      what it did with them (1,230 blocks: 0.21 ms against 0.32 ms);
    * the STATE model, the associative LP in generator form: a collapse
      state compatible with a mechanism is a choice of generator columns
      (see :meth:`_certify`), so certificates and the mechanism band are
      bound changes of this model, solved by interior point.
    """

    def __init__(self, lp: LimitLP, direction: int, opts: dict[str, Any]) -> None:
        self.lp = lp
        self.d = direction
        self.o = opts
        self.P = lp.n_points
        P = self.P
        self.n_cols = np.arange(P)
        self.s_cols = np.arange(P, 2 * P)
        self.lam_col = 2 * P
        self.history: list[IterationRecord] = []
        self.fallbacks = 0
        self.c0 = 0.0
        self.cold_algorithm = ""
        self.good_basis: Any = None
        self.in_fallback = False
        self._state_be: HighsBackend | None = None
        self.mechanism_band: tuple[float, float] | None = None

    # ---------------------------------------------------------------- models
    def _build(self) -> HighsBackend:
        lp, P = self.lp, self.P
        A = sp.hstack([lp.Bn, lp.Bs, sp.csc_matrix(lp.live.reshape(-1, 1))], format="csc")
        cost = np.zeros(2 * P + 1)
        cost[self.lam_col] = -float(self.d)
        lower = np.concatenate([np.zeros(2 * P), [-np.inf]])
        upper = np.concatenate([np.full(P, np.inf), np.zeros(P), [np.inf]])
        be = HighsBackend(lp, algorithm="ipm", time_limit=self.o["time_limit"], columns=(A, cost, lower, upper))
        if self.o["scheme"] == "b":
            # rows n_eq + 2p (+s) and n_eq + 2p + 1 (-s): +-s + alpha mu n <= rhs
            be.add_rows(self._friction_rows(self.o["alpha0"] * lp.mu), np.full(2 * P, -np.inf), np.full(2 * P, np.inf))
            self.f_rows = lp.n_eq + np.arange(2 * P)
        return be

    def _state_model(self) -> HighsBackend:
        """The associative LP in generator form (built on first use)."""
        if self._state_be is None:
            be = HighsBackend(self.lp, algorithm="ipm", time_limit=self.o["time_limit"])
            be.highs.changeColCost(self.lp.lam_col, -float(self.d))
            self._state_be = be
        return self._state_be

    def _friction_rows(self, n_coef: FloatArray) -> sp.csr_matrix:
        """``2P`` rows over the iteration model's columns: row ``2p`` is
        ``+s_p + n_coef_p n_p``, row ``2p + 1`` is ``-s_p + n_coef_p n_p``."""
        P = self.P
        rows = np.repeat(np.arange(2 * P), 2)
        cols = np.empty(4 * P, dtype=np.int64)
        vals = np.empty(4 * P)
        cols[0::4], cols[1::4], cols[2::4], cols[3::4] = self.s_cols, self.n_cols, self.s_cols, self.n_cols
        vals[0::4], vals[1::4], vals[2::4], vals[3::4] = 1.0, n_coef, -1.0, n_coef
        return sp.csr_matrix((vals, (rows, cols)), shape=(2 * P, 2 * P + 1))

    def _forces(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        P = self.P
        return x[:P], x[P : 2 * P]

    def _coulomb(self, n: FloatArray, s: FloatArray) -> float:
        scale = max(float(np.max(n, initial=0.0)), 1e-12)
        return float(np.max(np.abs(s) - self.lp.mu * n, initial=0.0)) / scale

    def _set_capacity(self, be: HighsBackend, nbar: FloatArray, alpha: float, alpha_prev: float) -> None:
        """Rebuild the yield condition of every point from ``nbar`` (bounds;
        for scheme (b) row bounds and, when ``alpha`` changed, coefficients)."""
        P, mu = self.P, self.lp.mu
        nbar = np.maximum(nbar, 0.0)
        if self.o["scheme"] == "a":
            be.set_col_bounds(self.s_cols, -mu * nbar, mu * nbar)
        else:
            if self.in_fallback:
                be.set_col_bounds(self.s_cols, np.full(P, -np.inf), np.full(P, np.inf))
                self.in_fallback = False
            if alpha != alpha_prev:
                be.change_coeffs(self.f_rows, np.repeat(self.n_cols, 2), np.repeat(alpha * mu, 2))
            rhs = self.c0 + (1.0 + alpha) * mu * nbar
            be.set_row_bounds(self.f_rows, np.full(2 * P, -np.inf), np.repeat(rhs, 2))

    # ----------------------------------------------------------- certificate
    def _pattern(self, v: FloatArray) -> tuple[FloatArray, FloatArray] | None:
        """Generator bounds of the collapse states compatible with the
        mechanism ``v`` (block velocities): ``(upper of g+, upper of g-)``,
        or ``None`` when ``v`` makes points interpenetrate (possible with
        scheme (b), whose ``n`` columns also enter the friction rows): no
        force field can then make it a collapse state."""
        lp, P = self.lp, self.P
        dn = lp.Bn.T @ v
        ds = lp.Bs.T @ v
        scale = max(float(np.max(np.abs(ds), initial=0.0)), float(np.max(np.abs(dn), initial=0.0)), 1e-300)
        # the simplex duals carry noise: closed points of a scheme (a)
        # mechanism showed opening rates down to -1.1e-5 of the largest rate
        # (Set 4), where exact duals give >= 0. The noise level sets the
        # tolerance of the classification; beyond _INTERPENETRATION the
        # mechanism really interpenetrates (scheme (b): up to ~0.5). Scheme
        # (b)'s own mechanisms dilate by alpha mu |slip| and its closing rates
        # are not noise: there the classification stays strict.
        noise = max(-float(np.min(dn, initial=0.0)), 0.0) / scale
        limit = _INTERPENETRATION if self.o["scheme"] == "a" else STATE_TOL
        if noise > limit:
            return None
        tol = (max(STATE_TOL, 10.0 * noise) if self.o["scheme"] == "a" else STATE_TOL) * scale
        opening = dn > tol
        slip = (np.abs(ds) > tol) & ~opening
        up_p = np.where(opening | (slip & (ds > 0)), 0.0, np.inf)  # g+ carries s = +mu n
        up_m = np.where(opening | (slip & (ds < 0)), 0.0, np.inf)  # g- carries s = -mu n
        return up_p, up_m

    def _state_lp(self, v: FloatArray, sense: float,
                  time_limit: float) -> tuple[tuple[FloatArray, FloatArray, float] | None, dict[str, Any]]:
        """Minimise ``sense * lambda`` over the collapse states compatible
        with the mechanism ``v`` (the state model with the generator columns
        of :meth:`_pattern`). Interior point, no basis.

        Returns:
            ``((n, s, lambda) or None, raw)``: ``None`` unless HiGHS found an
            optimal state that passes the residual check.
        """
        lp, P, d = self.lp, self.P, self.d
        pattern = self._pattern(v)
        if pattern is None:
            return None, {"status": Status.INFEASIBLE, "native_status": "mechanism interpenetrates",
                          "seconds": 0.0, "simplex_iterations": 0, "ipm_iterations": 0}
        up_p, up_m = pattern
        if self.o["state_solver"] == "clarabel":
            return self._state_lp_clarabel(up_p, up_m, sense, time_limit)
        be = self._state_model()
        be.set_col_bounds(np.arange(2 * P), np.zeros(2 * P), np.concatenate([up_p, up_m]))
        be.highs.changeColCost(lp.lam_col, float(sense) * d)
        be.highs.clearSolver()
        _run_limit(be, time_limit)
        raw = be.run_raw()
        if raw["status"] is not Status.OPTIMAL:
            return None, raw
        n, s = lp.forces(raw["x"][: 2 * P])
        lam = float(raw["x"][lp.lam_col]) * d
        if lp.primal_residual(n, s, lam * d) > 1e-7:
            return None, raw  # the interior point stopped short of an accurate state
        return (n, s, lam), raw

    def _state_lp_clarabel(self, up_p: FloatArray, up_m: FloatArray, sense: float, time_limit: float
                           ) -> tuple[tuple[FloatArray, FloatArray, float] | None, dict[str, Any]]:
        """:meth:`_state_lp` by Clarabel: the generator LP with the excluded
        columns left out (tight tolerances, its own residual check)."""
        import dataclasses

        from micro.solvers import ClarabelBackend

        lp, d = self.lp, self.d
        restricted = dataclasses.replace(lp, col_upper=np.concatenate([up_p, up_m, [np.inf]]))
        tl = None if not math.isfinite(time_limit) else float(time_limit)
        direction = -d if sense > 0 else d  # ClarabelBackend maximises direction * lambda_column
        # the tight settings stopped short (AlmostSolved) on every certificate LP
        # of the Table 7 walls and were retried: start from the retry's settings
        r = ClarabelBackend(restricted, time_limit=tl, settings=_STATE_CLARABEL).solve(direction)
        raw = {"status": r.status, "native_status": r.native_status, "seconds": r.solve_seconds,
               "simplex_iterations": 0, "ipm_iterations": int(r.iterations)}
        if r.status is not Status.OPTIMAL or r.n is None or r.s is None:
            return None, raw
        lam = d * (r.load_factor * direction)
        return (np.asarray(r.n), np.asarray(r.s), lam), raw

    def _certify(self, v: FloatArray, lam: float, *, time_limit: float
                 ) -> tuple[tuple[FloatArray, FloatArray] | None, dict[str, Any], tuple[float, float] | None]:
        """Is there a non-associative collapse state at ``lam`` with the mechanism ``v``?

        With the mechanism fixed, the collapse conditions on the forces are
        linear: equilibrium; ``n = 0`` where the points open;
        ``s = -sign(slip) mu n`` where they slip (friction at the yield line,
        against the slip); ``|s| <= mu n`` where they stick. In the
        generator form that is a choice of columns: both generators at a
        sticking point, the one on the right side of the cone at a slipping
        point, none at an opening point. Any feasible field forms with
        ``v`` an exact non-associative collapse state (equilibrium, Coulomb
        with its own normal forces, no dilatancy where ``n > 0``, no
        interpenetration, slip only at the yield line, against the slip; the
        energy balance follows by virtual work). The mechanism of the LP
        ``|s| <= mu nbar`` already has no dilatancy where ``n > 0``; what a
        sequence that does not settle in the forces lacks is a field that
        satisfies Coulomb with its own normal forces, and this looks for one
        among ALL fields, not only the LP's optimal ones.

        The load factors of these states form an interval (the mechanism
        band): its ends are two LPs (min and max ``lambda``). ``lam`` is
        certified when it lies in the band (relative slack 1e-7), and the
        state at ``lam`` is the convex combination of the two end states
        (equilibrium is linear). A feasibility LP at fixed ``lambda`` would
        be one LP instead of two, but HiGHS' interior point stopped with
        "Solve error" when ``lam`` sat at an end of the band (seen on pure
        rocking mechanisms, whose ``lambda`` is a geometric constant).

        Returns:
            ``((n, s) or None, raw, band)``: ``raw`` sums the LPs' cost;
            ``band`` is ``(min, max)`` or ``None`` (no state at all).
        """
        lo, raw_lo = self._state_lp(v, 1.0, time_limit)
        cost = {"status": raw_lo["status"], "native_status": raw_lo["native_status"], "seconds": raw_lo["seconds"],
                "simplex_iterations": raw_lo["simplex_iterations"], "ipm_iterations": raw_lo["ipm_iterations"]}
        slack = 1e-7 * max(abs(lam), 1e-12)
        if lo is None or lo[2] > lam + slack:
            return None, cost, None if lo is None else (lo[2], math.nan)
        hi, raw_hi = self._state_lp(v, -1.0, time_limit)
        cost["seconds"] += raw_hi["seconds"]
        cost["ipm_iterations"] += raw_hi["ipm_iterations"]
        cost["simplex_iterations"] += raw_hi["simplex_iterations"]
        if hi is None:
            return None, cost, (lo[2], math.nan)
        band = (lo[2], hi[2])
        if hi[2] < lam - slack:
            return None, cost, band
        width = hi[2] - lo[2]
        theta = 1.0 if width <= 0 else min(max((hi[2] - lam) / width, 0.0), 1.0)
        n = theta * lo[0] + (1.0 - theta) * hi[0]
        s = theta * lo[1] + (1.0 - theta) * hi[1]
        return (n, s), cost, band

    # ---------------------------------------------------------- recoveries
    def _restart(self, be: HighsBackend) -> dict[str, Any]:
        """Solve the current model from scratch: IPM + crossover, then dual
        simplex from the crossover basis (as for the first iterate)."""
        be.highs.clearSolver()
        be.set_algorithm("ipm", crossover=True)
        first = be.run_raw()
        be.set_algorithm("simplex")
        if first["status"] is not Status.OPTIMAL and first["status"] is not Status.INFEASIBLE:
            be.highs.clearSolver()
        raw = be.run_raw()
        raw["seconds"] += first["seconds"]
        raw["ipm_iterations"] = first["ipm_iterations"]
        raw["simplex_iterations"] += first["simplex_iterations"] + first["crossover_iterations"]
        return raw

    def _fallback_a_step(self, be: HighsBackend, nbar: FloatArray) -> dict[str, Any]:
        """One LP of scheme (a) inside the scheme (b) model: friction rows
        switched off (infinite bounds), ``|s| <= mu nbar`` as ``s`` bounds;
        restored by the next :meth:`_set_capacity`. Bound changes only."""
        P, mu = self.P, self.lp.mu
        nbar = np.maximum(nbar, 0.0)
        be.set_row_bounds(self.f_rows, np.full(2 * P, -np.inf), np.full(2 * P, np.inf))
        be.set_col_bounds(self.s_cols, -mu * nbar, mu * nbar)
        raw = be.run_raw()
        self.in_fallback = True  # the model now holds a scheme (a) LP (for the cold check)
        return raw

    # ----------------------------------------------------------- iterate 0
    def _associative(self) -> tuple[dict[str, Any], str]:
        """The associative LP (iterate 0): ``"interior"`` by Clarabel (tight
        tolerances; 0.4 s on 1,230 blocks against 1.7 s for HiGHS IPM),
        HiGHS IPM if Clarabel fails; ``"vertex"`` by HiGHS IPM + crossover +
        dual simplex on the state model (a basic optimal solution). ``x`` of
        the returned outcome is in the iteration model's layout ``[n, s, lambda]``."""
        lp, P = self.lp, self.P
        if self.o["start"] == "interior":
            from micro.solvers import ClarabelBackend

            r = ClarabelBackend(lp, time_limit=self.o["time_limit"]).solve(self.d)
            if r.status is Status.OPTIMAL and r.n is not None and r.s is not None:
                raw = {"status": Status.OPTIMAL, "native_status": r.native_status, "seconds": r.solve_seconds,
                       "simplex_iterations": 0, "ipm_iterations": int(r.iterations)}
                raw["x"] = np.concatenate([r.n, r.s, [r.load_factor * self.d]])
                return raw, "clarabel"
            raw, algo = self._state_model().run_raw(), "ipm"
        else:
            be = self._state_model()
            raw, algo = self._restart(be), "ipm+crossover+simplex"
            be.set_algorithm("ipm")
        if raw["status"] is Status.OPTIMAL:
            n, s = lp.forces(raw["x"][: 2 * P])
            raw["x"] = np.concatenate([n, s, [raw["x"][lp.lam_col]]])
        return raw, algo

    # ------------------------------------------------------------------ run
    def run(self) -> NonAssocDirection:
        t_start = time.perf_counter()
        lp, P, o = self.lp, self.P, self.o
        raw, algo0 = self._associative()
        if raw["status"] is not Status.OPTIMAL:
            self._record(0, float("nan"), float("nan"), float("nan"), float("nan"), 0.0, raw, algo0)
            return self._fail("associative_failed", f"the associative LP failed ({raw['native_status']})",
                              t_start, float("nan"))
        x = raw["x"]
        lam_assoc = float(x[self.lam_col]) * self.d
        n0, s0 = self._forces(x)
        n0 = np.maximum(n0, 0.0)
        # scheme (b)'s cohesion, relative to the largest associative normal force
        self.c0 = o["cohesion"] * max(float(np.max(n0, initial=0.0)), 1e-12)
        self._record(0, lam_assoc, float("nan"), float("nan"), self._coulomb(n0, s0), 0.0, raw, algo0)
        if lam_assoc < 0:
            return self._fail("associative_failed", "equilibrium needs a live load in the opposite direction",
                              t_start, lam_assoc)
        # ---- the non-associative model; its first LP by IPM + crossover + dual simplex
        t_b = time.perf_counter()
        be = self._build()
        if o["scheme"] == "b":
            be.set_col_bounds(self.s_cols, np.full(P, -np.inf), np.full(P, np.inf))
        alpha = o["alpha0"] if o["scheme"] == "b" else 0.0
        self._set_capacity(be, n0, alpha, o["alpha0"])
        t_build = time.perf_counter() - t_b
        user_limit = float(o["time_limit"]) if o["time_limit"] is not None else float("inf")
        warm_limit = user_limit
        lams: list[float] = []
        dns: list[float] = []
        n_prev, n_prev2 = n0, n0
        lam_prev = lam_assoc
        stop = ""
        band: tuple[float, float] | None = None
        last_raw: dict[str, Any] | None = None
        last_try = -10**9
        t_warm, t_cold, cold_streak = 0.0, math.inf, 0
        self._final: tuple[Any, ...] = ()
        for k in range(1, o["max_iterations"] + 1):
            t_it = time.perf_counter()
            if k > 1:
                nbar = o["relaxation"] * n_prev + (1.0 - o["relaxation"]) * n_prev2
                new_alpha = max(o["alpha_min"], alpha * o["alpha_factor"]) if o["scheme"] == "b" else 0.0
                self._set_capacity(be, nbar, new_alpha, alpha)
                alpha = new_alpha
                _run_limit(be, warm_limit)
            t_upd = time.perf_counter() - t_it + (t_build if k == 1 else 0.0)
            # on large walls a warm dual simplex can cost more than a cold
            # solve (7,575 blocks: 78,000-104,000 simplex iterations, 170-200 s,
            # against 45 s for interior point + crossover): solve cold while
            # the last warm run was 1.5x slower than the last cold one, and
            # go back to warm after three cold iterates in a row
            # the first LP, and later ones in cold mode: interior point +
            # crossover + dual-simplex clean-up (crossover alone is not accurate)
            if k == 1 or (o["scheme"] == "a" and t_warm > 1.5 * t_cold and cold_streak < 3):
                _run_limit(be, user_limit)
                raw = self._restart(be)
                algo = "ipm+crossover+simplex"
            else:
                raw = be.run_raw()
                algo = "simplex-warm"
            _run_limit(be, user_limit)
            spent = 0.0 if raw["status"] is Status.OPTIMAL else raw["seconds"]
            if raw["status"] is not Status.OPTIMAL and k > 1 and o["scheme"] == "b":
                # scheme (b) caps every point at n <= nbar (1 + alpha) / alpha
                # + c0 / (alpha mu): with nbar ~ 0 the support pattern can only
                # shrink until no equilibrium is left (HiGHS says "Infeasible",
                # or "Unknown" when it is nearly so). Fall back to one step of
                # scheme (a) from the last forces (bounds only), then go on with (b).
                if self.good_basis is not None:
                    be.highs.setBasis(self.good_basis)  # the failed run's basis may be garbage
                raw = self._fallback_a_step(be, n_prev)
                algo = "fallback-a"
                self.fallbacks += 1
            elif raw["status"] is Status.INFEASIBLE and k > 1 and o["relaxation"] < 1.0:
                # the relaxed capacities admit no equilibrium: rebuild this
                # iterate from the last forces alone (no relaxation)
                self._set_capacity(be, n_prev, alpha, alpha)
                raw = be.run_raw()
                algo = "simplex-warm-unrelaxed"
            if raw["status"] is not Status.OPTIMAL:
                # warm simplex failed (HiGHS "Unknown" on near-degenerate
                # rows): restart cold by interior point + crossover, then clean up
                raw = self._restart(be)
                algo = "ipm-restart"
            raw["seconds"] += t_upd + spent
            if raw["status"] is not Status.OPTIMAL:
                self._record(k, float("nan"), float("nan"), float("nan"), float("nan"), alpha, raw, algo)
                stop = "lp_failed"
                break
            x = raw["x"]
            last_raw = raw
            if algo == "simplex-warm":
                t_warm, cold_streak = raw["seconds"], 0
            elif algo == "ipm+crossover+simplex":
                t_cold = raw["seconds"]
                cold_streak += k > 1
            if k == 1:
                # a warm run that takes 10x the first (cold) one is stuck (seen:
                # 13 s to declare a 150-block LP infeasible): stop it and recover
                warm_limit = min(user_limit, max(1.0, 10.0 * raw["seconds"]))
            if o["scheme"] == "b":
                self.good_basis = be.highs.getBasis()
            lam = float(x[self.lam_col]) * self.d
            n, s = self._forces(x)
            nscale = max(float(np.max(n, initial=0.0)), 1e-12)
            dlam = abs(lam - lam_prev) / max(abs(lam), 1e-12)
            dn = float(np.max(np.abs(n - n_prev), initial=0.0)) / nscale
            coul = self._coulomb(n, s)
            self._record(k, lam, dlam, dn, coul, alpha, raw, algo)
            lams.append(lam)
            dns.append(dn)
            n_prev2, n_prev = n_prev, n
            lam_prev = lam
            v = be.dual_sign * raw["row_dual"][: lp.n_eq]
            self._final = (v, n, s, lam)
            alpha_done = o["scheme"] == "a" or alpha <= o["alpha_min"]
            coul_tol = o["coulomb_tol"] + (self.c0 / nscale if o["scheme"] == "b" else 0.0)
            if k >= 2 and alpha_done and dlam <= o["lambda_tol"] and coul <= coul_tol:
                stop = "lambda_and_forces" if dn <= o["force_tol"] else "lambda_and_coulomb"
                break
            w = o["settle_window"]
            if (o["certify"] and alpha_done and algo != "fallback-a" and len(lams) >= w and k - last_try >= w
                    and float(np.ptp(lams[-w:])) <= o["settle_tol"] * abs(lam)):
                # (at most one try per window of iterates: on large walls a try costs a few LPs)
                # lambda has settled: is this iterate an exact collapse state
                # with other forces than the LP's vertex?
                cert, c_raw, mband = self._certify(v, lam, time_limit=min(user_limit, max(1.0, 10.0 * raw["seconds"])))
                last_try = k
                self.history[-1] = _with_certificate(
                    self.history[-1], cert is not None, c_raw, self._coulomb(*cert) if cert else float("nan"))
                if cert is not None:
                    self._final = (v, cert[0], cert[1], lam)
                    self.mechanism_band = mband
                    stop = "certified"
                    break
            if alpha_done:
                cyc = _detect_cycle(lams, dns, o["lambda_tol"], o["window"])
                if cyc is not None:
                    stop, band = cyc
                    break
            if o["max_seconds"] is not None and time.perf_counter() - t_start > o["max_seconds"]:
                stop = "time_budget"
                w_ = lams[-o["window"]:]
                band = (min(w_), max(w_))
                break
        else:
            stop = "max_iterations"
            w_ = lams[-o["window"]:]
            band = (min(w_), max(w_)) if w_ else None
        if stop == "lp_failed" or last_raw is None:
            return self._fail("lp_failed", f"LP {len(self.history) - 1} failed warm and cold "
                              f"({raw['native_status']})", t_start, lam_assoc, band)
        return self._finish(be, stop, band, lam_assoc, t_start)

    def _record(self, k: int, lam: float, dlam: float, dn: float, coul: float, alpha: float,
                raw: dict[str, Any], algo: str) -> None:
        self.history.append(IterationRecord(
            iteration=k, load_factor=lam, lambda_change=dlam, max_dn=dn, coulomb_residual=coul, alpha=alpha,
            simplex_iterations=int(raw["simplex_iterations"]), ipm_iterations=int(raw["ipm_iterations"]),
            seconds=float(raw["seconds"]), algorithm=algo, status=raw["status"].value,
        ))

    def _fail(self, reason: str, msg: str, t_start: float, lam_assoc: float,
              band: tuple[float, float] | None = None) -> NonAssocDirection:
        last = [r.load_factor for r in self.history[1:] if math.isfinite(r.load_factor)]
        nan = float("nan")
        return NonAssocDirection(
            _DIR_NAME[self.d], SOLVER_FAILURE, reason, nan, last[-1] if last else nan, band, lam_assoc,
            max(len(self.history) - 1, 0), tuple(self.history), nan, nan, nan, nan, nan, 0, None, None, None,
            time.perf_counter() - t_start, msg,
        )

    def _finish(self, be: HighsBackend, stop: str, band: tuple[float, float] | None, lam_assoc: float,
                t_start: float) -> NonAssocDirection:
        lp, o = self.lp, self.o
        v, n, s, lam = self._final
        status = CONVERGED if stop in ("lambda_and_forces", "lambda_and_coulomb", "certified") else (
            MAX_ITERATIONS if stop in ("max_iterations", "time_budget") else CYCLING)
        # ---- final-state checks
        coul = self._coulomb(n, s)
        eq = lp.Bn @ n + lp.Bs @ s + (lam * self.d) * lp.live - lp.rhs  # the LP column holds d * lambda
        eq_res = float(np.max(np.abs(eq), initial=0.0))
        mech = mechanism_from_duals(lp, v, self.d)
        dn_rate, ds_rate = mech.opening_rate, mech.slip_rate
        scale = max(float(np.max(np.abs(ds_rate), initial=0.0)), float(np.max(np.abs(dn_rate), initial=0.0)))
        nscale = max(float(np.max(n, initial=0.0)), 1e-12)
        sliding = (np.abs(ds_rate) > STATE_TOL * scale) & (n > 1e-9 * nscale)
        smax = max(float(np.max(np.abs(ds_rate), initial=0.0)), 1e-300)
        dil = float(np.max(np.abs(dn_rate[sliding]), initial=0.0)) / smax if sliding.any() else 0.0
        # ---- cold re-solve of the final iterate
        cold = float("nan")
        rel = float("nan")
        msg = cold_note = ""
        if o["cold_check"]:
            cb = be.cold_copy("ipm")
            craw = cb.run_raw()
            self.cold_algorithm = "ipm"
            if craw["status"] is not Status.OPTIMAL:
                # IPX gave up (seen on scheme (b)'s near-degenerate rows): dual simplex, no basis
                cb = be.cold_copy("simplex")
                craw = cb.run_raw()
                self.cold_algorithm = "simplex"
            if craw["status"] is Status.OPTIMAL:
                cold = float(craw["x"][self.lam_col]) * self.d
                rel = abs(cold - lam) / max(abs(cold), 1e-12)
            if craw["status"] is Status.OPTIMAL and rel > o["cold_tol"] and self.cold_algorithm == "ipm":
                # IPX without crossover stops at its own tolerances (seen: 1.6e-6
                # from the warm vertex on 7,575 blocks): settle it with a cold
                # vertex (crossover + dual simplex from the IPX point, no warm basis)
                craw = self._restart(cb)
                self.cold_algorithm = "ipm+crossover+simplex"
                if craw["status"] is Status.OPTIMAL:
                    cold = float(craw["x"][self.lam_col]) * self.d
                    rel = abs(cold - lam) / max(abs(cold), 1e-12)
            if not math.isfinite(rel) or rel > o["cold_tol"]:
                cmsg = (f"the final iterate re-solved cold gives lambda = {cold:.9g} against {lam:.9g} warm "
                        f"(HiGHS hot start; status {craw['native_status']})")
                if status == CONVERGED:
                    status, stop, msg = SOLVER_FAILURE, "cold_check_failed", cmsg
                else:
                    cold_note = cmsg
        if status == CONVERGED and eq_res > 1e-6:
            status, stop = SOLVER_FAILURE, "equilibrium_residual"
            msg = f"equilibrium residual {eq_res:.2e} block weights at the final iterate"
        if status == CONVERGED and o["mechanism_band"] and self.mechanism_band is None and o["scheme"] == "a":
            typical = float(np.median([r.seconds for r in self.history[1:]]))
            user = float(o["time_limit"]) if o["time_limit"] is not None else float("inf")
            _, _, self.mechanism_band = self._certify(v, lam, time_limit=min(user, max(1.0, 20.0 * typical)))
        lam_out = lam if status == CONVERGED else float("nan")
        if not msg and status == CYCLING:
            msg = f"the sequence is {stop} (lambda in [{band[0]:.6g}, {band[1]:.6g}])" if band else stop
        elif not msg and status == MAX_ITERATIONS:
            msg = (f"no convergence in {o['max_iterations']} iterations" if stop == "max_iterations"
                   else f"time budget of {o['max_seconds']:g} s spent after {len(self.history) - 1} LPs")
            msg += f" (last window lambda in [{band[0]:.6g}, {band[1]:.6g}])" if band else ""
        elif not msg and status != CONVERGED:
            msg = stop
        if cold_note:
            msg += f"; also, {cold_note}"
        fs = lp.force_scale
        return NonAssocDirection(
            _DIR_NAME[self.d], status, stop, lam_out, lam, None if status == CONVERGED else band, lam_assoc,
            len(self.history) - 1, tuple(self.history), cold, rel, coul, dil, eq_res, int(sliding.sum()),
            n * fs, s * fs, mech, time.perf_counter() - t_start, msg, self.cold_algorithm, self.fallbacks,
            self.mechanism_band,
        )


def _run_limit(be: HighsBackend, seconds: float) -> None:
    """Limit the NEXT run to ``seconds``: HiGHS compares ``time_limit`` with
    the run time accumulated over all runs of the object (measured: a warm run
    stopped after 0.27 s with ``time_limit`` 24 s after 20 s of earlier runs)."""
    h = be.highs
    if math.isfinite(seconds):
        h.setOptionValue("time_limit", float(h.getRunTime()) + float(seconds))
    else:
        h.setOptionValue("time_limit", float("inf"))


def _with_certificate(rec: IterationRecord, found: bool, c_raw: dict[str, Any], coulomb: float) -> IterationRecord:
    """The record with the certificate attempt added (its LP's time and iterations)."""
    import dataclasses

    return dataclasses.replace(
        rec, certificate="certified" if found else "not found",
        certificate_seconds=float(c_raw["seconds"]),
        certificate_iterations=int(c_raw["simplex_iterations"]) + int(c_raw["ipm_iterations"]),
        coulomb_residual=coulomb if math.isfinite(coulomb) else rec.coulomb_residual,
    )


def _detect_cycle(lams: list[float], dns: list[float], tol: float,
                  window: int) -> tuple[str, tuple[float, float]] | None:
    """Cycling tests on the non-associative ``lambda`` sequence (see module docstring).

    Returns:
        ``(reason, (min, max))`` or ``None``.
    """
    k = len(lams)
    lam = np.asarray(lams)
    ref = max(abs(lam[-1]), 1e-12)
    # repeating sequence of period 2..6, seen twice in a row, not constant
    for p in range(2, 7):
        if k >= 2 * p:
            a = lam[-p:]
            b = lam[-2 * p : -p]
            if np.all(np.abs(a - b) <= tol * ref) and np.ptp(a) > tol * ref:
                return "repeating", (float(a.min()), float(a.max()))
    if k >= 2 * window:
        w1, w2 = lam[-2 * window : -window], lam[-window:]
        b1, b2 = float(np.ptp(w1)), float(np.ptp(w2))
        if b2 > tol * ref and b2 >= 0.5 * b1:
            return "oscillating", (float(w2.min()), float(w2.max()))
        d1, d2 = min(dns[-2 * window : -window]), min(dns[-window:])
        if b2 <= tol * ref and d2 >= 0.5 * d1:
            return "stagnation", (float(w2.min()), float(w2.max()))
    return None


def contact_states(result: NonAssocDirection) -> tuple[str, ...] | None:
    """Contact state names of a direction's final mechanism."""
    if result.mechanism is None:
        return None
    return tuple(CONTACT_STATE_NAMES[i] for i in result.mechanism.contact_state)


def verify_collapse_state(lp: LimitLP, result: NonAssocDirection) -> dict[str, float]:
    """Check a direction's final state against the non-associative collapse
    conditions, independently of how it was found (scaled units).

    Args:
        lp: the LP of the wall (:func:`micro.assemble`).
        result: a direction with forces and a mechanism.

    Returns:
        Residuals (0 when exact): ``equilibrium`` (block weights),
        ``coulomb`` (``max(|s| - mu n)`` / ``max n``), ``interpenetration``
        (``-min opening rate`` / largest rate), ``dilatancy``
        (``max |n * opening rate|`` / (``max n`` x largest rate)),
        ``slip_off_yield`` (``max ||s| - mu n|`` over slipping points /
        ``max n``), ``friction_direction`` (``max(s * slip rate)``, positive
        when friction would drive the slip, / (``max n`` x largest rate)),
        ``energy`` (``lambda * live work + dead work - dissipation``
        relative to ``lambda``) and ``slipping_points``.

    Raises:
        ValueError: the result has no forces or mechanism (it failed).
    """
    if result.normal is None or result.shear is None or result.mechanism is None:
        raise ValueError(f"direction {result.direction} has no final state ({result.status})")
    d = 1 if result.direction == "+x" else -1
    lam = result.last_load_factor
    n = result.normal / lp.force_scale
    s = result.shear / lp.force_scale
    mech = result.mechanism
    dn, ds = mech.opening_rate, mech.slip_rate
    rate = max(float(np.max(np.abs(dn), initial=0.0)), float(np.max(np.abs(ds), initial=0.0)), 1e-300)
    nsc = max(float(np.max(n, initial=0.0)), 1e-300)
    slip = np.abs(ds) > STATE_TOL * rate
    eq = lp.Bn @ n + lp.Bs @ s + (lam * d) * lp.live - lp.rhs
    dissipation = -float(ds @ s)
    return {
        "equilibrium": float(np.max(np.abs(eq), initial=0.0)),
        "coulomb": max(float(np.max(np.abs(s) - lp.mu * n, initial=0.0)), 0.0) / nsc,
        "interpenetration": max(-float(np.min(dn, initial=0.0)), 0.0) / rate,
        "dilatancy": float(np.max(np.abs(n * dn), initial=0.0)) / (nsc * rate),
        "slip_off_yield": float(np.max(np.abs(np.abs(s[slip]) - lp.mu[slip] * n[slip]), initial=0.0)) / nsc,
        "friction_direction": max(float(np.max(s[slip] * ds[slip], initial=0.0)), 0.0) / (nsc * rate),
        "energy": abs(lam * mech.live_work + mech.dead_work - dissipation) / max(abs(lam), 1e-12),
        "slipping_points": float(slip.sum()),
    }
