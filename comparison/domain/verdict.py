"""One wall, both models, and what may be concluded: the macro λ against the micro one, the verdict and its proof.

:func:`compare` solves the macro-block model and the rigid-block (micro) model of one wall and says whether
the macro model is on the safe side for it, and how that is known: the rule is :func:`comparison.domain.proof.judge`
(its module says why each proof holds). The associative LP runs first; when the macro λ is above it, the
verdict is settled and the non-associative solve is skipped (unless ``full``).

Every micro solve goes through :func:`solve_micro` (one place to change how the micro model is asked),
and each method through :func:`comparison.domain.wall_mechanism.solve_wall_mechanism`. Every number compared, and every
proof, is of the **wall as built** (:meth:`comparison.domain.wall.WallSpec.to_micro`): where a sliver's local
mechanism governs it (a wall of cut ends, :mod:`micro.local_mechanisms`), the held wall's λ is reported beside it
(``local_mechanism``), never in its place, and the verdict sentence says so.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal, cast, overload

from comparison.domain.proof import (
    ASSOCIATIVE_BOUND,
    GLOBAL_CLOSED,
    above,
    judge,
    refuting_below,
)
from comparison.domain.wall import WallSpec

if TYPE_CHECKING:  # pragma: no cover - typing only
    from collections.abc import Callable

    import macro
    import micro
    from comparison.domain.comparison_record import ComparisonRecord
    from comparison.domain.wall_mechanism import WallMechanism

    #: :func:`compare`'s ``progress``: a line when a model has its value, each non-associative LP as it finishes.
    CompareProgress = Callable[["str | micro.nonassociative.LPProgress"], None]

#: Values of :attr:`Comparison.status`: every method that ran gave its value, or one failed.
OK, FAILED = "ok", "failed"
#: Values of :attr:`CompareOptions.first_course` and :attr:`CompareOptions.head_joints`.
FIRST_COURSES = ("full", "half")
HEAD_JOINTS = ("frictional", "frictionless")


@dataclass(frozen=True)
class CompareOptions:
    """What :func:`compare` computes.

    Attributes:
        first_course, head_joints: the micro wall's bond (:meth:`comparison.domain.wall.WallSpec.to_micro`).
        full: every number, also the non-associative solve when the associative bound settles the verdict, and
            its whole search for the lowest certified state when a certified state below the macro λ already
            proves the macro model unsafe (without it the search stops at that first state).
        global_: after the non-associative solve, the global search by branch and bound (a lower bound: the
            only way to a "safe" verdict; a reference tool for walls of a few blocks).
        lowest: the descent to the lowest certified collapse state (the value to quote); ``False``: the
            iterated LP's state only.
        time_limit: seconds per LP solve, and of each direction's branch and bound (``None``: none; a
            wall-clock limit the user gives, whose numbers depend on the machine).
        node_limit: branch-and-bound nodes per direction of the global search (``None``: the budget of the
            wall's size, :func:`micro.global_search.default_node_limit`): where it stops, on every machine.
    """

    first_course: Literal["full", "half"] = "full"
    head_joints: Literal["frictional", "frictionless"] = "frictional"
    full: bool = False
    global_: bool = False
    lowest: bool = True
    time_limit: float | None = None
    node_limit: int | None = None

    def __post_init__(self) -> None:
        if self.first_course not in FIRST_COURSES:
            raise ValueError(f"first_course must be one of {', '.join(FIRST_COURSES)}, got {self.first_course!r}")
        if self.head_joints not in HEAD_JOINTS:
            raise ValueError(f"head_joints must be one of {', '.join(HEAD_JOINTS)}, got {self.head_joints!r}")
        t = self.time_limit
        if t is not None and (isinstance(t, bool) or not isinstance(t, (int, float)) or not 0 < t < math.inf):
            raise ValueError(f"time_limit must be a positive number of seconds, got {t!r}")
        n = self.node_limit
        if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n < 1):
            raise ValueError(f"node_limit must be a positive integer, got {n!r}")
        if n is not None and not self.global_:
            raise ValueError("node_limit applies to global_ only (the branch and bound's nodes)")


@dataclass(frozen=True)
class Seconds:
    """Wall time of each stage (NaN: the stage did not run)."""

    macro: float
    associative: float
    nonassociative: float
    total: float


@dataclass(frozen=True, eq=False)
class Comparison:
    """One wall by both models, and the verdict on the macro model.

    Attributes:
        status: :data:`OK` (every method that ran gave its value) or :data:`FAILED` (one failed:
            ``diagnostics`` say which and what the verdict then rests on).
        diagnostics: what was not computed or failed, and why, one sentence each.
        verdict: :data:`UNSAFE`, :data:`NOT_REFUTED`, :data:`SAFE` or ``None`` (:func:`judge`).
        proof: :data:`ASSOCIATIVE_BOUND`, :data:`CERTIFIED_STATE`, :data:`GLOBAL_BOUND` or ``None``.
        macro_load_factor, macro_mechanism: the macro model's λ and mechanism (NaN, ``None`` when it failed).
        associative_load_factor: the associative LP's λ, an upper bound of every non-associative collapse
            load (NaN when it failed).
        micro_load_factor: the non-associative λ to quote, the value compared (the lowest certified state,
            else the iterated LP's); NaN when the solve was skipped or failed.
        micro_quoted: which that is, ``"lowest certified"`` or ``"iterated"`` (``None`` without one).
        certified_load_factor: the lowest λ of a certified collapse state found (the quoted one when it is
            certified, or the global search's best state when lower); NaN without one.
        iterated_load_factor, mechanism_band: the iterated LP's λ and the band of λ over the collapse states
            of its mechanism (NaN, ``None`` without them).
        difference_percent: ``(macro − micro) / micro · 100`` (NaN without both).
        global_status, global_lower_bound: the global search's status and proven lower bound (``None``, NaN
            when it did not run). A text field that has no value is ``None`` here and ``null`` in
            :meth:`to_dict`, the same absence in Python and in JSON.
        local_mechanism: where a sliver's local mechanism governs the wall as built by the method the verdict
            rests on (``None``: none): that method, the mechanism's description, its λ (``load_factor``, the
            wall as built's), the moving blocks and their weight share, the slivers held and the held wall's λ
            (``held_load_factor``: another structure, reported beside the wall as built, never compared).
        seconds: each stage's wall time.
        blocks: blocks of the micro wall.
        wall, options: what was compared, and how.
        macro_result, associative_result, nonassociative_result: the models' own results (``None`` where a
            stage did not run), for plots and states.
        associative_wall, nonassociative_wall: the micro wall those results are of, the wall as built.
    """

    status: str
    diagnostics: tuple[str, ...]
    verdict: str | None
    proof: str | None
    macro_load_factor: float
    macro_mechanism: str | None
    associative_load_factor: float
    micro_load_factor: float
    micro_quoted: str | None
    certified_load_factor: float
    iterated_load_factor: float
    mechanism_band: tuple[float, float] | None
    difference_percent: float
    global_status: str | None
    global_lower_bound: float
    seconds: Seconds
    blocks: int
    wall: WallSpec = field(repr=False)
    options: CompareOptions = field(repr=False)
    local_mechanism: Any | None = None
    macro_result: macro.MacroResult | None = field(default=None, repr=False)
    associative_result: micro.LimitResult | None = field(default=None, repr=False)
    nonassociative_result: micro.NonAssociativeResult | None = field(default=None, repr=False)
    associative_wall: micro.BlockWall | None = field(default=None, repr=False)
    nonassociative_wall: micro.BlockWall | None = field(default=None, repr=False)

    @property
    def nonassociative_run(self) -> bool:
        """Whether the non-associative solve ran (it is skipped when the associative bound settles the
        verdict and ``full`` was not asked)."""
        return self.nonassociative_result is not None

    @property
    def search_stopped(self) -> bool:
        """Whether the non-associative search stopped at the first certified state below the macro λ (which
        proves it unsafe) rather than searching on for the lowest (``full`` does)."""
        from micro.nonassociative.descent.lowest_direction import TARGET

        r = self.nonassociative_result
        return r is not None and any(low.stop == TARGET for low in r.lowest)

    @property
    def held_load_factor(self) -> float:
        """The held wall's λ beside the wall as built's where a sliver's local mechanism governs it (NaN: none,
        or its analysis failed)."""
        loc = self.local_mechanism
        held = None if loc is None else loc.get("held_load_factor")
        return math.nan if held is None else float(held)

    @property
    def local_description(self) -> str:
        """What a sliver lets collapse in the wall as built (``""``: nothing local governs)."""
        return "" if self.local_mechanism is None else str(self.local_mechanism["description"])

    def sentence(self) -> str:
        """The verdict and its proof in one sentence (the first line of ``xcheck compare``):
        :func:`comparison.domain.verdict_words.verdict_sentence`."""
        from comparison.domain.verdict_words import verdict_sentence

        return verdict_sentence(self)

    def to_record(self) -> ComparisonRecord:
        """The flat record: a read-only mapping of the numbers, the verdict and the bond
        (:class:`comparison.domain.comparison_record.ComparisonRecord`); ``to_record().to_dict()`` its JSON form."""
        from comparison.domain.comparison_record import comparison_record

        return comparison_record(self)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (NaN -> ``None``), in the field names of ``docs/schemas/compare.schema.json``."""
        from micro.columns import json_number as num  # the one NaN-to-null conversion

        nonassoc = self.nonassociative_result
        return {
            "verdict": self.verdict,
            "proof": self.proof,
            "status": self.status,
            "diagnostics": list(self.diagnostics),
            "macro_load_factor": num(self.macro_load_factor),
            "micro_load_factor": num(self.micro_load_factor),
            "difference_percent": num(self.difference_percent),
            "associative_load_factor": num(self.associative_load_factor),
            "certified_load_factor": num(self.certified_load_factor),
            "micro_quoted": self.micro_quoted,
            "iterated_load_factor": num(self.iterated_load_factor),
            "mechanism_band": None if self.mechanism_band is None else [num(x) for x in self.mechanism_band],
            "macro_mechanism": self.macro_mechanism,
            "macro_status": None if self.macro_result is None else self.macro_result.status,
            "associative_status": None if self.associative_result is None else self.associative_result.status,
            "nonassociative_status": None if nonassoc is None else nonassoc.status,
            "global_status": self.global_status,
            "global_lower_bound": num(self.global_lower_bound),
            "local_mechanism": self.local_mechanism,
            "blocks": self.blocks,
            "first_course": self.options.first_course,
            "head_joints": self.options.head_joints,
            "ends": self.wall.ends,
            "full": self.options.full,
            "search_stopped": self.search_stopped,
            "seconds": {k: num(v) for k, v in self.seconds.__dict__.items()},
        }


def _nonassociative_values(result: micro.NonAssociativeResult) -> tuple[float, float]:
    """``(the value to quote, the iterated LP's λ)`` of a non-associative result (the one place that reads
    them by name)."""
    return result.load_factor, result.iterated_load_factor


@overload
def solve_micro(wall: micro.BlockWall, friction: Literal["associative"], options: CompareOptions, *,
                stop_below: float | None = None, progress: micro.nonassociative.Progress | None = None
                ) -> micro.LimitResult:
    ...


@overload
def solve_micro(wall: micro.BlockWall, friction: Literal["nonassociative"], options: CompareOptions, *,
                stop_below: float | None = None, progress: micro.nonassociative.Progress | None = None
                ) -> micro.NonAssociativeResult:
    ...


def solve_micro(wall: micro.BlockWall, friction: str, options: CompareOptions, *, stop_below: float | None = None,
                progress: micro.nonassociative.Progress | None = None) -> Any:
    """The micro model of ``wall`` with ``friction`` (``"associative"``: the LP with the library's default
    back end; ``"nonassociative"``: the report's method, with the descent as ``options`` ask, stopped at the
    first certified state below ``stop_below`` (``None``: the whole search), its LPs told to ``progress``; the
    global search is composed after it, :func:`solve_global_search`). Every micro solve of :func:`compare`
    goes through here."""
    import micro

    if friction == "associative":
        return micro.solve_associative(wall, time_limit=options.time_limit)
    limit: dict[str, Any] = {} if options.time_limit is None else {"time_limit": options.time_limit}
    return micro.solve_nonassociative(wall, lowest=options.lowest, stop_below=stop_below, progress=progress,
                                      **limit)


def solve_global_search(wall: micro.BlockWall, result: micro.NonAssociativeResult,
                        options: CompareOptions) -> micro.GlobalResult | None:
    """The global search on ``wall`` started from the non-associative ``result`` of the same wall, where
    ``options.global_`` asks for it (``None`` otherwise); ``options.time_limit`` is its limit per direction
    as well, ``options.node_limit`` its nodes per direction."""
    if not options.global_:
        return None
    from micro.global_search import GlobalOptions, solve_global

    n, t = options.node_limit, options.time_limit
    opts = GlobalOptions(node_limit=n) if t is None else GlobalOptions(node_limit=n, direction_time_limit=t)
    return solve_global(wall, start=result, options=opts)


def solve_wall(wall: micro.BlockWall, friction: str, options: CompareOptions, **kw: Any) -> WallMechanism:
    """The micro method ``friction`` on the wall as built, with a local mechanism told apart and the held wall
    analysed beside it (:func:`comparison.domain.wall_mechanism.solve_wall_mechanism`); every solve through
    :func:`solve_micro` (``kw``: its ``stop_below`` and ``progress``)."""
    from comparison.domain.wall_mechanism import solve_wall_mechanism

    return solve_wall_mechanism(wall, lambda w: solve_micro(w, friction, options, **kw))  # type: ignore[call-overload]


def _local(assoc: WallMechanism, nonassoc: WallMechanism | None, proof: str | None) -> dict[str, Any] | None:
    """What a sliver lets collapse in the wall as built, for :attr:`Comparison.local_mechanism`: of the method the
    verdict rests on (the associative LP's where its bound proves it, else the non-associative method's when it
    ran); ``None`` when that method's mechanism is not local."""
    use_assoc = nonassoc is None or proof == ASSOCIATIVE_BOUND
    wm, method = (assoc, "associative") if use_assoc else (nonassoc, "nonassociative")
    if wm is None or wm.local is None:
        return None
    d = wm.to_dict()
    return {"method": method, **d["local_mechanism"], "held_load_factor": d["held_load_factor"]}


def compare(wall: WallSpec, options: CompareOptions | None = None, *, progress: CompareProgress | None = None,
            **overrides: Any) -> Comparison:
    """The macro model against the micro model on ``wall``, and the verdict (module docstring).

    Computes no more than the verdict needs: the macro model, the associative LP, and the non-associative
    solve only when the associative bound does not settle the verdict (or ``full``), its search stopped at the
    first certified state below the macro λ (which proves it unsafe; ``full`` or ``global_`` search on for
    the lowest state).

    Args:
        wall: the wall (:meth:`WallSpec.from_paper`, :func:`comparison.domain.scene.load_scene`).
        options: what to compute (``None``: the defaults).
        progress: told what is done as it is done: a line (``str``) when a model has its value, each LP of
            the non-associative solve (:class:`micro.nonassociative.LPProgress`) as it finishes (``None``: nobody).
        **overrides: fields of :class:`CompareOptions` to change (``full=True``).

    Raises:
        ValueError: a bad option, or a wall a model refuses (too large for the memory, a micro wall that
            cannot be built): the message names it.

    Examples:
        >>> import comparison
        >>> from comparison.domain.wall import WallSpec
        >>> c = comparison.compare(WallSpec.from_paper(t=1, m=1/2, rows=12, f=0.75))
        >>> c.verdict, c.proof, round(c.macro_load_factor, 4), round(c.micro_load_factor, 4), c.search_stopped
        ('unsafe', 'certified state', 0.4914, 0.4913, True)
        >>> round(comparison.compare(c.wall, full=True).micro_load_factor, 4)  # searched on: the lowest state
        0.4895
    """
    import macro

    if not isinstance(wall, WallSpec):
        raise TypeError(f"wall must be a comparison.domain.wall.WallSpec, got {type(wall).__name__}")
    o = replace(options or CompareOptions(), **overrides)
    notes: list[str] = []
    start = time.perf_counter()
    macro_result = macro.solve(wall.to_macro())
    t_macro = time.perf_counter() - start
    macro_ok = macro_result.status == "optimal"
    lam_macro = macro_result.load_factor if macro_ok else math.nan
    tell = progress or (lambda _: None)
    if not macro_ok:
        notes.append(f"the macro model gave no load factor (status {macro_result.status})")
    else:
        tell(f"macro model: lambda = {lam_macro:.6f} ({macro_result.mechanism}), {t_macro:.1f} s")
    block_wall = wall.to_micro(first_course=o.first_course, head_joints=o.head_joints)
    t0 = time.perf_counter()
    assoc_wall = solve_wall(block_wall, "associative", o)
    assoc = cast("micro.LimitResult", assoc_wall.result)
    t_assoc = time.perf_counter() - t0
    lam_assoc = assoc.load_factor if assoc.ok else math.nan
    tell(f"associative LP ({block_wall.n_blocks:,} blocks): " + (f"lambda = {lam_assoc:.6f}" if assoc.ok else
                                                                  f"{assoc.status}") + f", {t_assoc:.1f} s")
    if not assoc.ok:
        notes.append(f"the associative LP failed (status {assoc.status}: {assoc.message}); no bound checked")
    elif assoc_wall.message:
        notes.append(f"associative LP, held wall: {assoc_wall.message}")
    settled = above(lam_macro, lam_assoc)
    nonassoc = None
    nonassoc_wall = None
    search = None
    t_nonassoc = math.nan
    if macro_ok and settled and not o.full:
        notes.append("the non-associative solve was skipped: the associative bound settles the verdict "
                     "(--full, full=True, computes it)")
    elif macro_ok or o.full:
        t0 = time.perf_counter()
        from micro.nonassociative.descent.lowest_direction import TARGET

        search_all = o.full or o.global_ or not macro_ok
        nonassoc_wall = solve_wall(block_wall, "nonassociative", o, progress=progress,
                                   stop_below=None if search_all else refuting_below(lam_macro))
        nonassoc = cast("micro.NonAssociativeResult", nonassoc_wall.result)
        search = solve_global_search(block_wall, nonassoc, o)
        if nonassoc.ok and nonassoc_wall.message:
            notes.append(f"non-associative solve, held wall: {nonassoc_wall.message}")
        if nonassoc.ok and any(low.stop == TARGET for low in nonassoc.lowest):
            notes.append("the non-associative search stopped at the first certified state below the macro λ, which "
                         "proves it unsafe (--full, full=True, searches on for the lowest)")
        t_nonassoc = time.perf_counter() - t0
    values = _micro_values(nonassoc, search, notes)
    certified = values["certified_load_factor"]
    micro_lam = values["micro_load_factor"]
    verdict, proof = judge(lam_macro, lam_assoc, certified, found_load_factor=micro_lam,
                           global_lower_bound=values["closed_bound"])
    failed = not macro_ok or not assoc.ok or (nonassoc is not None and not nonassoc.ok)
    return Comparison(
        status=FAILED if failed else OK,
        diagnostics=tuple(notes),
        verdict=verdict,
        proof=proof,
        macro_load_factor=lam_macro,
        macro_mechanism=macro_result.mechanism if macro_ok else None,
        associative_load_factor=lam_assoc,
        micro_load_factor=micro_lam,
        micro_quoted=values["micro_quoted"],
        certified_load_factor=certified,
        iterated_load_factor=values["iterated_load_factor"],
        mechanism_band=values["mechanism_band"],
        difference_percent=100.0 * (lam_macro - micro_lam) / micro_lam if math.isfinite(micro_lam) else math.nan,
        global_status=values["global_status"],
        global_lower_bound=values["global_lower_bound"],
        seconds=Seconds(t_macro, t_assoc, t_nonassoc, time.perf_counter() - start),
        blocks=block_wall.n_blocks,
        wall=wall,
        options=o,
        local_mechanism=_local(assoc_wall, nonassoc_wall, proof),
        macro_result=macro_result,
        associative_result=assoc,
        nonassociative_result=nonassoc,
        associative_wall=block_wall,
        nonassociative_wall=None if nonassoc_wall is None else block_wall,
    )


def _micro_values(result: micro.NonAssociativeResult | None, g: micro.GlobalResult | None,
                  notes: list[str]) -> dict[str, Any]:
    """The non-associative numbers a :class:`Comparison` holds (NaN and ``None`` where there are none),
    the global search's (``g``, started from ``result``) bound when it closed (``closed_bound``); what is
    missing goes to ``notes``."""
    out: dict[str, Any] = {"micro_load_factor": math.nan, "micro_quoted": None, "certified_load_factor": math.nan,
                           "iterated_load_factor": math.nan, "mechanism_band": None, "global_status": None,
                           "global_lower_bound": math.nan, "closed_bound": math.nan}
    if result is None:
        return out
    if not result.ok:
        notes.append(f"the non-associative solve failed (status {result.status}: {result.message}); "
                     "no collapse state to compare")
        return out
    from micro.nonassociative.nonassociative_result import QUOTED_LOWEST

    quoted, iterated = _nonassociative_values(result)
    certified = result.quoted == QUOTED_LOWEST or result.sequence.stop_reason == "certified"
    if not certified:
        notes.append(f"the value quoted is the iterated LP's, whose state is not certified (it stopped "
                     f"{result.sequence.stop_reason}): no proof by a certified state")
    states = [quoted] if certified else []
    if g is not None:
        out.update(global_status=g.status, global_lower_bound=g.lower_bound)
        if math.isfinite(g.load_factor):
            states.append(g.load_factor)
        if g.status == GLOBAL_CLOSED:
            out["closed_bound"] = g.lower_bound
        else:
            notes.append(f"the global search did not close (status {g.status}): its lower bound "
                         f"{g.lower_bound:.6g} is not proven to the gap")
    out.update(micro_load_factor=quoted, micro_quoted=result.quoted or None, iterated_load_factor=iterated,
               mechanism_band=result.mechanism_band,
               certified_load_factor=min(states) if states else math.nan)
    return out
