"""What a run of the iterated LP is configured by, in one place: one options object and its resolution.

* :class:`NonAssociativeOptions`, what a user of :func:`micro.solve_nonassociative`
  sets (directions, caps, time limits, the descent and its budget), with its
  ``tuning``:
* :class:`Tuning`, the research knobs (the rebuilt yield condition, the
  relaxation, the selections, fusing, the continuation, the certificate): their
  defaults are the report's method, and a user needs none of them
  (``docs/micro/tuning.md``);
* :func:`resolve`, the one function from the options to what the stages read
  (:class:`Resolved`): the options as given, and the choices they leave to the
  wall's size (fusing, the continuation) and to each sequence (its selection,
  its cap) decided. Nothing is copied: a stage reads ``resolved.options.time_limit``
  or ``resolved.tuning.scheme``, so a new setting is one field of the options or
  of the tuning, with its test.

Neither the method itself (scheme, selections, fusing, tolerances) nor the
search for the global minimum is an option: the first lives in the tuning, the
second is composed by the caller after the run
(:func:`micro.global_search.solve_global` with ``start=result``). The module's
constants are the defaults the knobs resolve to and the tolerances several
modules share; every other policy constant lives beside its only user.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal, get_args

import numpy as np

from micro.backends.base import check_integer, finite_real
from micro.backends.roles import ROLE_NAMES
from micro.limit_result import Directions, check_directions

# ------------------------------------------------------------------ the tuning
#: Published rebuilt yield conditions implemented here.
SCHEMES = ("a", "b")
#: Default relaxation ``beta`` per scheme (``nbar = beta n_k + (1 - beta) n_(k-1)``).
DEFAULT_RELAXATION = {"a": 0.6, "b": 0.6}
#: How the next ``nbar`` follows from an LP: its vertex's forces (``"vertex"``),
#: or ``nbar`` moved towards the optimal field nearest to it (``"proximal"``);
#: ``"vertex+proximal"``: the vertex sequence, and the proximal one where it fails.
SelectionName = Literal["vertex", "proximal", "vertex+proximal"]
SELECTIONS: tuple[str, ...] = get_args(SelectionName)
#: The default selection of scheme (a): the vertex sequence, and the proximal
#: one from its last normal forces on a direction where it cycles or hits its
#: cap (Sets 2 and 9 of Table 5 cycle with vertices; the proximal sequence
#: certifies them). Scheme (b) has only the vertex selection.
DEFAULT_SELECTION: SelectionName = "vertex+proximal"
#: Cap on the LPs of that second sequence per direction.
RETRY_LPS = 40
#: Walls of more than this many blocks run fused with the continuation
#: (``fuse`` and ``continuation`` left ``None``): Set 10 (3,630 blocks) is
#: certified that way; the walls of up to 2,000 blocks keep the wall's own
#: sequences.
FUSE_BLOCKS = 2000
#: Walls of more than this many blocks try the reduced wall first (``reduce`` left ``None``;
#: :mod:`micro.nonassociative.reduced`, which says why): the committed error map runs the iterated LP on
#: walls of up to 1,500 blocks, and their values are the wall's own chain's.
REDUCE_BLOCKS = 1500

# ------------------------------------------ tolerances shared by several modules
#: Largest closing rate (relative to the largest rate) that the certificate
#: and the descent still read as dual noise rather than interpenetration.
INTERPENETRATION = 1e-3
#: Largest primal residual (block weights) of a state found by an interior
#: point: one that stopped short of it found no state.
STATE_RESIDUAL = 1e-7
#: Largest equilibrium residual (block weights) of a converged final state;
#: beyond it the run is a ``solver_failure``.
EQUILIBRIUM_RESIDUAL = 1e-6
#: Floor of the scales that residuals are divided by.
TINY = 1e-12


def continuation_allowed(scheme: str, selection: str) -> bool:
    """Whether ``continuation`` can run: it needs scheme (a) and a vertex
    sequence (``"vertex"`` or ``"vertex+proximal"``; the proximal retry runs
    without it)."""
    return scheme == "a" and selection.startswith("vertex")


@dataclass(frozen=True)
class Tuning:
    """The research knobs of the iterated LP (validated on construction).

    The defaults are the report's method; ``docs/micro/tuning.md`` describes
    each knob and what it was measured to do. A new knob is one field here
    (with its check in ``__post_init__`` where it needs one): a stage reads it
    as ``resolved.tuning.<knob>``; the record, the CLI's ``--tuning`` and the
    cache key take it from the fields.

    Attributes:
        scheme: rebuilt yield condition, ``"a"`` or ``"b"`` (package docstring).
        selection: how the next ``nbar`` follows from an LP: ``"vertex"``
            (the simplex's vertex, Gilbert et al.'s iteration),
            ``"proximal"`` (``nbar`` moved towards the field closest to it
            that carries the LP's load), or ``"vertex+proximal"`` (the vertex
            sequence, then the proximal one from its last forces where it
            ends :data:`RETRY_STATUSES`). ``None``: :data:`DEFAULT_SELECTION`
            for scheme (a), ``"vertex"`` for (b). All but ``"vertex"`` need scheme (a).
        relaxation: ``beta`` in ``(0, 1]`` (``None``: :data:`DEFAULT_RELAXATION`).
        retry_iterations: cap on the LPs of the proximal sequence of ``"vertex+proximal"``.
        max_simplex_iterations: cap on the simplex iterations per direction
            (``None``: none): a deterministic work budget; a sequence that
            spends it stops as ``max_iterations`` (``"work_budget"``).
        start: iterate 0 by ``"interior"`` (Clarabel, a point near the centre
            of the optimal face) or ``"vertex"`` (HiGHS IPM + crossover).
        certify: try the certificate once ``lambda`` has settled; ``False``:
            only the exact stop converges (the plain sequence).
        mechanism_band: for a converged scheme (a) sequence, also compute the
            band of load factors of the final mechanism.
        fuse: run the sequence on the fused wall (blocks that the associative
            mechanism moves as one rigid body are one body; a state counts
            only when the whole wall's certificate extends it). ``None``: on
            walls of more than :data:`FUSE_BLOCKS` blocks with scheme (a) and
            a vertex sequence.
        continuation: reach scheme (a) by continuation from associative
            friction (``CONT_*`` constants). ``None``: as ``fuse``'s default.
        fused_retry: with ``"vertex+proximal"`` and scheme (a), where both
            sequences fail on a direction, a third run on the fused wall with
            the continuation.
        reduce: try the reduced wall first (:mod:`micro.nonassociative.reduced`:
            the chain on models of the associative mechanism's rigid parts, every
            mechanism lifted onto the wall; where that mechanism has a dominant
            rigid part). ``None``: on walls of more than
            :data:`REDUCE_BLOCKS` blocks with scheme
            (a) and a vertex sequence.

    Raises:
        ValueError: a bad knob (the message names it).
    """

    scheme: Literal["a", "b"] = "a"
    selection: SelectionName | None = None
    relaxation: float | None = None
    retry_iterations: int = RETRY_LPS
    max_simplex_iterations: int | None = None
    start: Literal["interior", "vertex"] = "interior"
    certify: bool = True
    mechanism_band: bool = True
    fuse: bool | None = None
    continuation: bool | None = None
    fused_retry: bool = True
    reduce: bool | None = None

    def __post_init__(self) -> None:
        if self.scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {', '.join(SCHEMES)}, got {self.scheme!r}")
        if self.selection is not None and self.selection not in SELECTIONS:
            raise ValueError(f"selection must be one of {', '.join(SELECTIONS)}, got {self.selection!r}")
        if self.resolved_selection != "vertex" and self.scheme != "a":
            raise ValueError(f"selection {self.selection!r} needs scheme 'a' "
                             "(the proximal projection bounds s by mu nbar)")
        if self.continuation and not continuation_allowed(self.scheme, self.resolved_selection):
            raise ValueError("continuation needs scheme 'a' and a vertex sequence (selection 'vertex' or "
                             f"'vertex+proximal'), got scheme {self.scheme!r}, "
                             f"selection {self.resolved_selection!r}")
        if self.start not in ("interior", "vertex"):
            raise ValueError(f"start must be one of interior, vertex, got {self.start!r}")
        beta = self.relaxation
        if beta is not None and ((x := finite_real(beta)) is None or not (0.0 < x <= 1.0)):
            raise ValueError(f"relaxation must be a number in (0, 1], got {beta!r}")
        check_integer("retry_iterations", self.retry_iterations, 2)
        if self.max_simplex_iterations is not None:
            check_integer("max_simplex_iterations", self.max_simplex_iterations, 1)
        if beta is not None:
            object.__setattr__(self, "relaxation", float(beta))
        by_size = ("fuse", "continuation", "reduce")
        for name in ("certify", "mechanism_band", "fused_retry", *by_size):
            value = getattr(self, name)
            if value is None and name in by_size:
                continue
            if not isinstance(value, (bool, np.bool_)):  # certify="no" was read as True
                may_be_none = " or None (by the wall's size)" if name in by_size else ""
                raise ValueError(f"{name} must be True or False{may_be_none}, got {value!r}")
            object.__setattr__(self, name, bool(value))

    @property
    def resolved_selection(self) -> SelectionName:
        """:attr:`selection`, or the scheme's default."""
        if self.selection is not None:
            return self.selection
        return DEFAULT_SELECTION if self.scheme == "a" else "vertex"

    @property
    def beta(self) -> float:
        """The relaxation used: :attr:`relaxation` or the scheme's default."""
        return DEFAULT_RELAXATION[self.scheme] if self.relaxation is None else float(self.relaxation)

    def reduced_wall(self, blocks: int) -> bool:
        """Whether ``reduce`` left at ``None`` is on for a wall of ``blocks`` blocks (more than
        :data:`REDUCE_BLOCKS`, scheme (a), a vertex sequence)."""
        return blocks > REDUCE_BLOCKS and continuation_allowed(self.scheme, self.resolved_selection)

    def large_wall(self, blocks: int) -> bool:
        """Whether ``fuse`` and ``continuation`` left at ``None`` are on for a
        wall of ``blocks`` blocks (more than :data:`FUSE_BLOCKS`, scheme (a),
        a vertex sequence)."""
        return blocks > FUSE_BLOCKS and continuation_allowed(self.scheme, self.resolved_selection)

    def with_overrides(self, **overrides: Any) -> Tuning:
        """A copy with some knobs changed (validated again).

        Raises:
            TypeError: an unknown knob (the message lists the knobs).
        """
        unknown = sorted(set(overrides) - set(TUNING_KNOBS))
        if unknown:
            raise TypeError(f"unknown tuning knob(s) {', '.join(unknown)}; the knobs are {', '.join(TUNING_KNOBS)}")
        return dataclasses.replace(self, **overrides)

    def changed(self) -> dict[str, Any]:
        """The knobs that change the computation from the defaults' (the report's
        method: ``{}``; a selection or relaxation that names the default is no change)."""
        default = Tuning(scheme=self.scheme)
        same = {"selection": self.resolved_selection == default.resolved_selection,
                "relaxation": self.beta == default.beta}
        return {k: getattr(self, k) for k in TUNING_KNOBS
                if getattr(self, k) != getattr(Tuning(), k) and not same.get(k, False)}

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return dataclasses.asdict(self)


#: The names of the knobs of :class:`Tuning`.
TUNING_KNOBS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(Tuning))


# ------------------------------------------------------------------ the options
#: Default of :attr:`NonAssociativeOptions.lowest_budget`: LPs per direction.
#: The descent ends by its own rules well within it on every wall measured
#: (the walls of ``xcheck stability --lowest`` and of Table 5), so the budget
#: is a guard, not a stop that shapes the answer: the counts are on
#: the research page on the re-cut of the non-associative package (``docs/research/``) ("Figures moved from the code").
LOWEST_BUDGET = 100


@dataclass(frozen=True)
class NonAssociativeOptions:
    """Options of :func:`micro.solve_nonassociative` (validated on construction).

    Attributes:
        directions: ``"auto"`` (both unless mirror-symmetric), ``"both"``,
            ``"+x"`` or ``"-x"``.
        max_iterations: cap on the non-associative LPs of a direction's first
            sequence; a sequence that reaches it ends ``max_iterations``.
        time_limit: optional wall-clock limit per LP in seconds (``None``:
            none); an LP it stops ends the run with status ``time_limit``,
            no final answer.
        max_seconds: optional wall-clock stop per direction (``None``: none);
            a sequence it stops has status ``time_limit``. No other decision
            depends on time: the same wall gives the same numbers everywhere.
        lowest: after a converged run, descend to the lowest certified
            collapse state (``lowest_load_factor``, the value to quote;
            :mod:`micro.nonassociative.descent.lowest`); ``False``: the iterated
            LP's state only.
        lowest_budget: the most LPs the descent may solve per direction
            (one more gives the band of the state it returns); a descent
            that spends it returns the lowest certified state found so far
            (``lowest_stop="budget"``). It counts LPs, not seconds: the same
            wall stops at the same state on every machine.
        stop_below: stop the search as soon as a certified collapse state
            with ``lambda`` below this value is found (``None``: search on):
            that state is returned (``lowest_stop="target"``), the directions
            not yet solved are skipped. A load factor above it is refuted by
            that state, which needs no lower one (``xcheck compare`` passes the
            macro model's ``lambda``).
        tuning: the research knobs (:class:`Tuning`; ``None``: the report's method).

    Raises:
        ValueError: a bad option (the message names it).
    """

    directions: Directions = "auto"
    max_iterations: int = 100
    time_limit: float | None = None
    max_seconds: float | None = None
    lowest: bool = True
    lowest_budget: int = LOWEST_BUDGET
    stop_below: float | None = None
    tuning: Tuning = field(default_factory=Tuning)

    def __post_init__(self) -> None:
        if self.tuning is None:
            object.__setattr__(self, "tuning", Tuning())
        if not isinstance(self.tuning, Tuning):
            raise TypeError(f"tuning must be a micro.Tuning or None, got {self.tuning!r} "
                            f"({type(self.tuning).__name__})")
        check_directions(self.directions)
        check_integer("max_iterations", self.max_iterations, 2)
        for name in ("time_limit", "max_seconds"):
            tl = getattr(self, name)
            if tl is not None and ((x := finite_real(tl)) is None or x <= 0):
                raise ValueError(f"{name} must be a positive number of seconds, got {tl!r}")
            if tl is not None:
                object.__setattr__(self, name, float(tl))
        check_integer("lowest_budget", self.lowest_budget, 0)
        if self.stop_below is not None:
            if (x := finite_real(self.stop_below)) is None:
                raise ValueError(f"stop_below must be a finite number or None, got {self.stop_below!r}")
            object.__setattr__(self, "stop_below", float(x))
        if not isinstance(self.lowest, (bool, np.bool_)):
            raise ValueError(f"lowest must be True or False, got {self.lowest!r}")
        object.__setattr__(self, "lowest", bool(self.lowest))

    @property
    def user_limit(self) -> float:
        """:attr:`time_limit` in seconds, ``inf`` for none."""
        return float(self.time_limit) if self.time_limit is not None else math.inf

    def below_target(self, load_factor: float) -> bool:
        """Whether a certified state at ``load_factor`` ends the search (:attr:`stop_below`)."""
        return self.stop_below is not None and load_factor < self.stop_below

    def with_overrides(self, **overrides: Any) -> NonAssociativeOptions:
        """A copy with some options changed (validated again).

        Raises:
            TypeError: an unknown option name (the message lists the options).
        """
        unknown = sorted(set(overrides) - set(OPTION_NAMES))
        if unknown:
            raise TypeError(f"unknown option(s) {', '.join(unknown)}; the options are {', '.join(OPTION_NAMES)} "
                            "(research knobs: tuning=micro.Tuning(...))")
        return dataclasses.replace(self, **overrides)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return dataclasses.asdict(self)


#: The names of the fields of :class:`NonAssociativeOptions`.
OPTION_NAMES: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(NonAssociativeOptions))


# ------------------------------------------------------------- what the stages read
@dataclass(frozen=True)
class LPProgress:
    """One LP as it finishes, for a progress display (``progress=`` of
    :func:`micro.solve_nonassociative`).

    Attributes:
        direction: ``"+x"`` or ``"-x"``.
        stage: ``"vertex"``, ``"proximal"``, ``"fused ..."`` (a
            sequence of the iterated LP, on the wall or a model of its bodies), ``"lowest"`` (the descent) or
            ``"reduced lift"`` (the reduced wall's lift of a mechanism onto the wall).
        lp: the LP's number in its stage (0: the associative LP).
        load_factor: its ``lambda`` (NaN when it failed or has none); of a lift, the lowest state of the
            wall lifted so far.
        step: ``max |n_k - n_(k-1)|`` relative to ``max n_k`` (NaN when not defined).
        algorithm: how it was solved.
        seconds: its wall time.
    """

    direction: str
    stage: str
    lp: int
    load_factor: float
    step: float
    algorithm: str
    seconds: float


#: A callback that receives one :class:`LPProgress` per LP.
Progress = Callable[[LPProgress], None]


@dataclass(frozen=True)
class Resolved:
    """What the stages of one sequence read: the options as given, their tuning inside, and the choices
    they leave to the wall and to the sequence, resolved by :func:`resolve`. Nothing is copied: a stage
    reads an option as ``resolved.options.time_limit`` and a knob as ``resolved.tuning.scheme``, so a new
    option or knob is one field of :class:`NonAssociativeOptions` or :class:`Tuning`.

    Attributes:
        options: the user's :class:`NonAssociativeOptions`, as given (with their :class:`Tuning`).
        selection: this sequence's selection: ``tuning.selection`` resolved for the scheme, then
            ``"vertex"`` or ``"proximal"`` for each sequence of ``"vertex+proximal"`` (the stages set it).
        max_lps: this sequence's cap on LPs: ``options.max_iterations``, the proximal retry's
            ``tuning.retry_iterations``.
        fuse, continuation: ``tuning.fuse`` and ``tuning.continuation`` resolved for the wall's size
            (:meth:`Tuning.large_wall`); the stages turn them on or off for a sequence.
        reduce: ``tuning.reduce`` resolved for the wall's size (:meth:`Tuning.reduced_wall`).
        progress: the caller's callback (not part of the method).
    """

    options: NonAssociativeOptions
    selection: SelectionName
    max_lps: int
    fuse: bool
    continuation: bool
    reduce: bool = False
    progress: Progress | None = field(default=None, repr=False, compare=False)

    @property
    def tuning(self) -> Tuning:
        """The research knobs (``options.tuning``)."""
        return self.options.tuning

    def tell(self, event: LPProgress) -> None:
        """Pass ``event`` to the progress callback, if any."""
        if self.progress is not None:
            self.progress(event)

    def solver_description(self) -> str:
        """Which solver does what in the iterated LP, e.g. ``"clarabel (start,
        certificate) + highs-simplex (iterated) + highs-ipm (cold check)"``."""
        interior, persistent = ROLE_NAMES["interior"], ROLE_NAMES["persistent"]
        t = self.tuning
        roles = [(interior if t.start == "interior" else f"{persistent}-ipm+crossover", "start")]
        if t.certify or t.mechanism_band:
            roles.append((interior, "certificate"))
        roles.append((f"{persistent}-simplex", "iterated" + (", fused" if self.fuse else "")))
        roles.append((f"{persistent}-ipm", "cold check"))
        by_solver: dict[str, list[str]] = {}
        for solver, role in roles:
            by_solver.setdefault(solver, []).append(role)
        return " + ".join(f"{solver} ({', '.join(r)})" for solver, r in by_solver.items())

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready, flat: the options and the knobs, with the resolved values in place of theirs
        (``selection``, ``fuse``, ``continuation``; ``relaxation`` and ``beta``: the relaxation used)."""
        given = {k: v for k, v in self.options.as_dict().items() if k != "tuning"}
        return {**given, **self.tuning.as_dict(), "selection": self.selection, "fuse": self.fuse,
                "continuation": self.continuation, "reduce": self.reduce, "relaxation": self.tuning.beta,
                "beta": self.tuning.beta}


def resolve(blocks: int, options: NonAssociativeOptions | None = None,
            progress: Progress | None = None) -> Resolved:
    """What the stages read on a wall of ``blocks`` blocks (:class:`Resolved`): the options as given and
    the choices that depend on the wall's size resolved."""
    o = options or NonAssociativeOptions()
    t = o.tuning
    large = t.large_wall(blocks)
    return Resolved(o, selection=t.resolved_selection, max_lps=o.max_iterations,
                    fuse=large if t.fuse is None else t.fuse,
                    continuation=large if t.continuation is None else t.continuation,
                    reduce=t.reduced_wall(blocks) if t.reduce is None else t.reduce, progress=progress)
