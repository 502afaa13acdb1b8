"""Options of the iterated LP and its policy constants, in one place.

:class:`NonAssociativeOptions` holds what a caller may choose (validated on
construction); the module constants below are the fixed policy of the
iteration (when to solve cold, how long a run may take, what counts as noise),
each with the measurement that set it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Literal, get_args

from micro.backends.base import check_integer, check_number
from micro.backends.clarabel import CLARABEL_RETRY
from micro.nonassociative.global_bounds import POLICIES as BIG_M_POLICIES
from micro.results import Directions, check_directions

#: Published rebuilt yield conditions implemented here.
SCHEMES = ("a", "b")
#: Default relaxation ``beta`` per scheme (``nbar = beta n_k + (1 - beta) n_(k-1)``).
DEFAULT_RELAXATION = {"a": 0.6, "b": 0.6}
#: How an iterate picks its forces among the optimal fields of its LP, or
#: (``"proximal"``) the next ``nbar`` near them (``"vertex+lazy"``,
#: ``"vertex+proximal"``: the vertex sequence, and the other where it fails).
Selection = Literal["vertex", "lazy", "proximal", "vertex+lazy", "vertex+proximal"]
SELECTIONS: tuple[str, ...] = get_args(Selection)


def continuation_allowed(scheme: str, selection: str) -> bool:
    """Whether ``continuation`` can run: it needs scheme (a) and a vertex
    sequence (``"vertex"``, ``"vertex+lazy"`` or ``"vertex+proximal"``; the
    retry of the last two runs without it)."""
    return scheme == "a" and selection.startswith("vertex")
#: ``"vertex+lazy"`` runs the lazy sequence on a direction whose vertex
#: sequence ended with one of these statuses.
RETRY_STATUSES = ("cycling", "max_iterations")
#: The lazy selection's cost per unit of ``|n - nbar|`` (scaled units: block
#: weights, against a cost of 1 on ``lambda``). Small enough that the lazy
#: LP's ``lambda`` lies below Gilbert's by at most ``LAZY_WEIGHT`` times the
#: 1-norm distance of Gilbert's vertex from ``nbar`` (on Table 7's Set 13, 78
#: blocks: the same ``lambda`` to 1e-16, at distances of 113 and 305 block
#: weights), large enough for HiGHS' dual simplex to see (its dual feasibility tolerance here is 1e-10,
#: ``micro.backends.highs.SIMPLEX_TOLERANCE``). The only value tried. The
#: mechanism of such an LP is perturbed by it (energy residuals 6e-6 to
#: 1.5e-3), so the certificate asks the plain LP at the same ``nbar`` (this
#: cost switched off) for its mechanism.
LAZY_WEIGHT = 1e-7
#: The proximal selection's margin below the LP's optimum: its QP asks for the
#: field closest to ``nbar`` that carries ``lambda* (1 - PROX_MARGIN)``
#: (:mod:`micro.nonassociative.proximal`). At 1e-5 Clarabel stopped at its
#: iteration cap ("AlmostSolved", 200 iterations) on most QPs of Sets 2 and 9
#: (the feasible set is too thin); at 1e-3 Set 9's sequence had not been
#: certified after 40 LPs; at 1e-4 it was after 38 (and Set 2 after 21).
PROX_MARGIN = 1e-4
#: Clarabel settings of the proximal QP: a projection needs no more than
#: 1e-8 (it only chooses the next ``nbar``; the certificate decides
#: convergence); QDLDL named as for the LPs (``CLARABEL_TIGHT``).
PROX_CLARABEL: dict[str, Any] = {
    "direct_solve_method": "qdldl",
    "tol_gap_abs": 1e-8,
    "tol_gap_rel": 1e-8,
    "tol_feas": 1e-8,
    "max_iter": 400,
}

# ------------------------------------------------------------ warm / cold policy
# Every decision of the sequence is taken on deterministic work measures
# (simplex and interior-point iteration counts, LP counts), never on seconds:
# a loaded or slower machine follows the same path to the same numbers.
#: On large walls a warm dual simplex can cost more than a cold solve (7,575
#: blocks: 78,000-104,000 simplex iterations, 170-200 s, against 45 s for
#: interior point + crossover; 1,230 blocks: 514-1,423, 2-6 x faster than
#: cold). Scheme (a) solves an iterate cold while the last warm run took more
#: than this many simplex iterations per equilibrium row of the wall ...
COLD_SWITCH_PIVOTS = 2.0
#: ... and goes back to warm after this many cold iterates in a row, a number
#: doubled each time the warm run after a cold streak is slow again (or stopped
#: at its limit below).
COLD_STREAK = 3
#: A warm run that takes more than this many simplex iterations per
#: equilibrium row is stuck (seen: 13 s to declare a 150-block LP
#: infeasible): it is stopped and recovered ...
WARM_LIMIT_PIVOTS = 10.0
#: ... with at least this many iterations on small walls.
MIN_WARM_LIMIT = 20_000
#: Interior-point iterations allowed to each certificate LP (HiGHS'
#: ``ipm_iteration_limit``; Clarabel's ``max_iter`` of the tight settings is
#: the same 400): the only limit of a certificate try besides the user's
#: ``time_limit``.
STATE_IPM_ITERATIONS = 400

# --------------------------------------------------------------- certificate
#: Clarabel settings of the certificate LPs: their ends are checked for
#: feasibility, so optimality to 1e-9 is enough (the tight settings stopped
#: short on every certificate LP of the Table 7 walls and were retried).
STATE_CLARABEL = CLARABEL_RETRY
#: Largest closing rate (relative to the largest rate) that the certificate
#: still reads as dual noise rather than interpenetration.
INTERPENETRATION = 1e-3
#: Largest primal residual (block weights) of a state found by HiGHS IPM: an
#: interior point that stopped short of it found no state.
STATE_RESIDUAL = 1e-7
#: Relative slack of the test "the iterate's lambda lies in the mechanism band".
BAND_SLACK = 1e-7

# ------------------------------------------------------------ continuation
#: The continuation (``continuation=True``) reaches scheme (a)'s vertex
#: sequence from associative friction: LP ``k`` bounds the shear by the line
#: ``|s| <= c0 + (1 - gamma) mu nbar + gamma mu n`` through ``(nbar, mu nbar)``
#: (``gamma = 1``: associative Coulomb; ``gamma = 0``: scheme (a)) in scheme
#: (b)'s friction rows, ``gamma = CONT_GAMMA0`` at the first LP ...
CONT_GAMMA0 = 0.9
#: ... times this at every LP ...
CONT_FACTOR = 0.8
#: ... and 0 once it would fall to this or below (LP 32 on).
CONT_GAMMA_MIN = 1e-3
#: Its cohesion ``c0``, relative to the largest normal force it starts from
#: (scheme (b) has ``cohesion``, 1e-6: with it the fused Set 9's first LP gave
#: lambda = 5.46 against 0.394 associative).
CONT_COHESION = 1e-9
#: Its warm runs are not cut short (a cap would make the path depend on it):
#: the fused Set 10's second LP took 60,122 simplex iterations, 40 s.
WARM_UNLIMITED = 2**31 - 1

# ------------------------------------------------------------------ fusion
#: A contact is rigid, and the blocks it joins are fused into one body
#: (:mod:`micro.nonassociative.fusion`), when its opening and slip rates in the
#: associative mechanism (Clarabel's interior point) are below this fraction
#: of the largest rate. That mechanism has no clean zero: on Set 10 (10,710
#: contacts) 27 contacts are rigid at 1e-8, 2,598 at 1e-7, 7,189 at 1e-6,
#: 8,335 at 1e-5 and 9,148 at 1e-4. At 1e-4 the fused Set 9 converged at the
#: very end of its mechanism band, where the certificate of the whole wall
#: missed it by 4e-7; at 1e-5 both Sets 2 and 9 are certified on the wall.
FUSE_RIGID_TOL = 1e-5

# -------------------------------------------------------------- cycles
#: Periods of the repeating-sequence test (a period seen twice in a row).
PERIODS = range(2, 7)
#: Oscillation: the last window's spread of lambda is at least this fraction
#: of the window before (no contraction). Stagnation: the smallest change of
#: the forces over the last window is at least this fraction of the window
#: before (no progress).
NO_PROGRESS = 0.5

# ----------------------------------------------------------- final state
#: Largest equilibrium residual (block weights) of a converged final state;
#: beyond it the run is a ``solver_failure``.
EQUILIBRIUM_RESIDUAL = 1e-6
#: A point is in contact when its normal force exceeds this fraction of the
#: largest one (for the dilatancy residual).
CONTACT_FORCE = 1e-9
#: Floor of the scales that residuals are divided by.
TINY = 1e-12


@dataclass(frozen=True)
class NonAssociativeOptions:
    """Options of :func:`micro.solve_nonassociative` (validated on construction).

    Attributes:
        scheme: rebuilt yield condition, ``"a"`` or ``"b"`` (package docstring).
        selection: which of an LP's optimal force fields an iterate takes
            (scheme (a) only for ``"lazy"``): ``"vertex"`` (the simplex's
            vertex, Gilbert et al.'s iteration) or ``"lazy"`` (the field
            closest to ``nbar`` in the 1-norm, by the cost
            :data:`LAZY_WEIGHT` on ``|n - nbar|``: the forces of the parts
            that do not move stop jumping from one vertex to another: on
            Set 2, which cycles with vertices, the sequence contracts and is
            certified after 30 LPs; a lazy sequence ends converged only by
            the certificate, with the mechanism of the plain LP at the last
            ``nbar``). The two end at different states, the lazy one mostly
            higher: on the 120 walls of ``xcheck stability`` higher on 94
            of the 118 where both converge, by 3.7 % (median), 35 % at
            most; it cycles on 2, where the vertex default converges.
            ``"vertex+lazy"``: the vertex sequence, and on a direction
            where it ends ``cycling`` or ``max_iterations``
            (:data:`RETRY_STATUSES`) the lazy one, ``nbar`` started from
            the vertex sequence's last normal forces (the
            direction's ``sequence.vertex_attempt`` keeps the first; what
            ``xcheck report`` runs: Set 2 of Table 5 cycles with vertices
            and is certified by the lazy sequence).
            ``"proximal"`` (scheme (a) only): the LP's vertex gives
            ``lambda*`` and the mechanism, and the next ``nbar`` moves by
            ``beta`` towards the field closest to ``nbar`` that carries
            ``lambda* (1 - PROX_MARGIN)`` with the same capacities (a QP,
            :mod:`micro.nonassociative.proximal`); the certificate is tried
            at every iterate, and the sequence stops as ``stagnation`` when
            its steps stop shrinking. It certified Set 9 (1,830 blocks),
            which cycles with every other selection. ``"vertex+proximal"``:
            as ``"vertex+lazy"`` with the proximal sequence second.
        relaxation: ``beta`` in ``(0, 1]`` (``None``: :data:`DEFAULT_RELAXATION`;
            :attr:`beta` is the value used).
        alpha0, alpha_min, alpha_factor: slope schedule of scheme (b):
            ``alpha_(k+1) = max(alpha_min, alpha_factor * alpha_k)``.
        cohesion: ``c0`` of scheme (b) relative to the largest normal force
            of the associative solution (scale-free; default one millionth
            of the force level).
        max_iterations: cap on non-associative LPs per direction.
        retry_iterations: ``"vertex+lazy"``, ``"vertex+proximal"``: cap on
            the second sequence's LPs
            (``None``: :attr:`max_iterations`).
        max_simplex_iterations: cap on the simplex iterations (warm runs,
            crossovers and clean-ups) of the non-associative LPs per
            direction (``None``: none): a deterministic work budget; when
            spent the sequence stops with status ``max_iterations``
            (``stop_reason="work_budget"``) and its last band.
        max_seconds: optional wall-clock stop per direction (``None``: none).
            A sequence stopped by it has status ``time_limit``
            (``stop_reason="time_budget"``): another machine would have gone
            further, so it is no final answer (the runner's cache does not
            keep it). No other decision of the sequence depends on time.
        lambda_tol: relative change of ``lambda`` for convergence.
        force_tol: largest change of the normal forces, relative to the
            largest normal force, for convergence.
        coulomb_tol: ``max(|s| - mu n, 0) / max n`` accepted as "Coulomb holds".
        window: iterations per window of the oscillation / stagnation tests.
        directions: ``"auto"`` (both unless mirror-symmetric), ``"both"``,
            ``"+x"`` or ``"-x"``.
        start: how the associative LP (iterate 0, which gives the first
            ``nbar``) is solved: ``"interior"`` (Clarabel's interior point
            with tight tolerances, HiGHS IPM if it fails: a point near the
            centre of the optimal face, 0.4 s on 1,230 blocks) or
            ``"vertex"`` (HiGHS IPM + crossover + dual simplex: a basic
            optimal solution as a simplex code returns). The first
            non-associative LP is solved by IPM + crossover + dual simplex
            either way. The non-associative solution is not unique and the
            two starts can end at different load factors (~1-2 %).
        certify: once ``lambda`` has settled (its spread over the last
            ``settle_window`` iterates is at most ``settle_tol`` relative),
            ask whether the current iterate's mechanism admits an exact
            collapse state at the current ``lambda``
            (:mod:`micro.nonassociative.certificate`; at most one try per
            ``settle_window`` iterates). If it does, the sequence stops,
            converged, with ``stop_reason="certified"`` and that state's
            forces. ``False``: only the exact test (Coulomb with the LP's
            own forces) ends a sequence as converged.
        settle_tol, settle_window: when to try the certificate (above).
        mechanism_band: for a converged scheme (a) sequence, also compute
            the band of load factors over all collapse states with the final
            mechanism (two more interior-point LPs).
        state_solver: interior point of the certificate LPs: ``"clarabel"``
            or ``"highs"`` (HiGHS IPM on a persistent model).
        cold_check: re-solve the final iterate cold and compare.
        cold_tol: relative warm/cold difference beyond which the result is a
            ``solver_failure``.
        time_limit: optional wall-clock limit per LP in seconds (``None``:
            none); an LP stopped by it ends the sequence with status
            ``time_limit``.
        lowest: after a converged run, descend from its state to the lowest
            certified collapse state reachable
            (:mod:`micro.nonassociative.lowest`; ``lowest_load_factor``). On
            the walls of ``xcheck stability --lowest`` it took 1.3 times the
            iterated LP's time (median; 3.2 on walls of over 160 blocks).
        global_: then search for the global minimum of the collapse load by
            branch and bound, started from the lowest state
            (:mod:`micro.nonassociative.global_mip`; a reference tool for
            walls of a few blocks: on larger walls its lower bound stays 0).
        global_time_limit: seconds of branch and bound per direction
            (``None``: none). A search it stops reports its bound and gap
            (``time_limit``); such numbers depend on the machine.
        global_node_limit: branch-and-bound nodes per direction (``None``:
            none); unlike the time limit it gives the same answer on every
            machine (``node_limit``).
        global_bounds: the global search's big-M policy for the normal
            forces (:class:`~micro.nonassociative.global_mip.GlobalOptions`):
            ``"per_point"`` (one LP per contact point) or ``"uniform"`` (one
            LP; cheaper, and as good on the walls tried).
        fuse: run the sequence on the fused wall: the blocks that the
            associative mechanism moves as one rigid body are one body
            (:mod:`micro.nonassociative.fusion`), and a converged state is
            accepted only when the certificate of the whole wall extends it
            to every block. Fewer rows and points (Set 9: 6,368 of 10,680
            points, 71 s against 335 s; but Set 3 84 s against 12 s), and
            only the mechanisms of the bodies can form (measurements in the
            module).
        continuation: reach scheme (a) by continuation from associative
            friction (:data:`CONT_GAMMA0` and after): the vertex sequence's
            LPs bound the shear by a line of slope ``gamma mu`` through
            ``(nbar, mu nbar)``, ``gamma`` from 0.9 down to 0 over 31 LPs,
            ``nbar`` moved by ``beta`` towards each LP's forces; from
            ``gamma = 0`` on the certificate is tried at every LP and only
            it or the cap ends the sequence. With ``fuse``, it starts from the
            wall's associative forces. Scheme (a) and a vertex sequence only
            (the proximal or lazy retry runs without it).
        fused_retry: with ``"vertex+lazy"`` or ``"vertex+proximal"`` and
            scheme (a), on a direction where both sequences end ``cycling``
            or ``max_iterations``, a third run: the fused wall with the
            continuation (``fuse`` and ``continuation``), its state checked
            on the whole wall (:func:`~micro.nonassociative.fusion.solve_chain`).
            It certified the two error-map walls (882 and 1,314 blocks) on
            which the vertex and proximal sequences end at their caps, in
            about 23 s each. Walls on which the first two converge are not
            touched; off with ``fuse`` or ``continuation`` (the chain then
            is that already).

    Raises:
        ValueError: a bad option (the message names it).
    """

    scheme: Literal["a", "b"] = "a"
    selection: Selection = "vertex"
    relaxation: float | None = None
    alpha0: float = 0.3
    alpha_min: float = 1e-3
    alpha_factor: float = 0.5
    cohesion: float = 1e-6
    max_iterations: int = 100
    retry_iterations: int | None = None
    max_simplex_iterations: int | None = None
    max_seconds: float | None = None
    lambda_tol: float = 1e-6
    force_tol: float = 1e-6
    coulomb_tol: float = 1e-6
    window: int = 20
    directions: Directions = "auto"
    start: Literal["interior", "vertex"] = "interior"
    certify: bool = True
    settle_tol: float = 1e-3
    settle_window: int = 3
    mechanism_band: bool = True
    state_solver: Literal["clarabel", "highs"] = "clarabel"
    cold_check: bool = True
    cold_tol: float = 1e-6
    time_limit: float | None = None
    lowest: bool = True
    global_: bool = False
    global_time_limit: float | None = 300.0
    global_node_limit: int | None = None
    global_bounds: Literal["per_point", "uniform"] = "per_point"
    fuse: bool = False
    continuation: bool = False
    fused_retry: bool = True

    def __post_init__(self) -> None:
        if self.scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {', '.join(SCHEMES)}, got {self.scheme!r}")
        if self.selection not in SELECTIONS:
            raise ValueError(f"selection must be one of {', '.join(SELECTIONS)}, got {self.selection!r}")
        if self.selection != "vertex" and self.scheme != "a":
            raise ValueError(f"selection {self.selection!r} needs scheme 'a' "
                             "(the lazy and proximal models bound s by mu nbar)")
        beta = self.relaxation
        if beta is not None and (isinstance(beta, bool) or not isinstance(beta, (int, float))
                                 or not (0.0 < float(beta) <= 1.0)):
            raise ValueError(f"relaxation must be a number in (0, 1], got {beta!r}")
        for name, lo in (("alpha0", 0.0), ("alpha_min", 0.0), ("cohesion", -1.0), ("lambda_tol", 0.0),
                         ("force_tol", 0.0), ("coulomb_tol", 0.0), ("cold_tol", 0.0)):
            check_number(name, getattr(self, name), lo)
        if self.cohesion < 0:
            raise ValueError(f"cohesion must be >= 0, got {self.cohesion!r}")
        if self.alpha_min > self.alpha0:
            raise ValueError(f"alpha_min ({self.alpha_min}) must not exceed alpha0 ({self.alpha0})")
        if not (0.0 < self.alpha_factor <= 1.0):
            raise ValueError(f"alpha_factor must be in (0, 1], got {self.alpha_factor!r}")
        check_integer("max_iterations", self.max_iterations, 2)
        if self.retry_iterations is not None:
            check_integer("retry_iterations", self.retry_iterations, 2)
        if self.max_simplex_iterations is not None:
            check_integer("max_simplex_iterations", self.max_simplex_iterations, 1)
        check_integer("window", self.window, 3)
        check_integer("settle_window", self.settle_window, 2)
        if self.global_node_limit is not None:
            check_integer("global_node_limit", self.global_node_limit, 1)
        self._check_rest()
        self._normalise()

    def _check_rest(self) -> None:
        if self.continuation and not continuation_allowed(self.scheme, self.selection):
            raise ValueError("continuation needs scheme 'a' and a vertex sequence (selection 'vertex', "
                             f"'vertex+lazy' or 'vertex+proximal'), got scheme {self.scheme!r}, "
                             f"selection {self.selection!r}")
        st = self.settle_tol
        if isinstance(st, bool) or not isinstance(st, (int, float)) or not (0.0 <= st < 1.0):
            raise ValueError(f"settle_tol must be a number in [0, 1), got {st!r}")
        check_directions(self.directions)
        if self.global_bounds not in BIG_M_POLICIES:
            raise ValueError(f"global_bounds must be one of {', '.join(BIG_M_POLICIES)}, got {self.global_bounds!r}")
        ms = self.max_seconds
        if ms is not None and (isinstance(ms, bool) or not isinstance(ms, (int, float))
                               or not math.isfinite(ms) or ms <= 0):
            raise ValueError(f"max_seconds must be a positive number of seconds, got {ms!r}")
        if self.state_solver not in ("clarabel", "highs"):
            raise ValueError(f"state_solver must be 'clarabel' or 'highs', got {self.state_solver!r}")
        if self.start not in ("interior", "vertex"):
            raise ValueError(f"start must be 'interior' or 'vertex', got {self.start!r}")
        for name in ("time_limit", "global_time_limit"):
            tl = getattr(self, name)
            if tl is not None and (isinstance(tl, bool) or not isinstance(tl, (int, float))
                                   or not math.isfinite(tl) or tl <= 0):
                raise ValueError(f"{name} must be a positive number of seconds, got {tl!r}")

    def _normalise(self) -> None:
        """Numbers as floats, flags as bools (the dataclass is frozen)."""
        for name in ("alpha0", "alpha_min", "alpha_factor", "cohesion", "lambda_tol", "force_tol", "coulomb_tol",
                     "settle_tol", "cold_tol"):
            object.__setattr__(self, name, float(getattr(self, name)))
        for name in ("max_seconds", "relaxation", "global_time_limit"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, float(getattr(self, name)))
        object.__setattr__(self, "certify", bool(self.certify))
        for name in ("mechanism_band", "lowest", "global_", "fuse", "continuation", "fused_retry"):
            object.__setattr__(self, name, bool(getattr(self, name)))

    @property
    def beta(self) -> float:
        """The relaxation used: :attr:`relaxation` or the scheme's default."""
        return DEFAULT_RELAXATION[self.scheme] if self.relaxation is None else float(self.relaxation)

    @property
    def user_limit(self) -> float:
        """:attr:`time_limit` in seconds, ``inf`` for none."""
        return float(self.time_limit) if self.time_limit is not None else math.inf

    def with_overrides(self, **overrides: Any) -> NonAssociativeOptions:
        """A copy with some fields changed (validated again).

        Raises:
            TypeError: an unknown option name.
        """
        names = {f.name for f in dataclasses.fields(self)}
        unknown = sorted(set(overrides) - names)
        if unknown:
            raise TypeError(f"unknown option(s) {', '.join(unknown)}; the options are {', '.join(sorted(names))}")
        return dataclasses.replace(self, **overrides)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (``relaxation`` resolved to :attr:`beta`)."""
        return {**dataclasses.asdict(self), "relaxation": self.beta}
