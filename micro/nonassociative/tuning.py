"""The research knobs of the iterated LP (:class:`Tuning`), their defaults, the tolerances several modules share.

:class:`Tuning` holds what the method's developers vary: the rebuilt yield
condition, the relaxation, the selections, fusing and the continuation,
tolerances. Its defaults are the method of ``xcheck report`` (what
:func:`micro.solve_nonassociative` runs with no options); a user needs none of
them (the options a user sets are :class:`~micro.nonassociative.options.NonAssociativeOptions`).
The module's constants are the defaults those knobs resolve to and the
tolerances several modules share; every other policy constant lives beside
its only user (every knob: ``docs/micro/tuning.md``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np

from micro.backends.base import check_integer, finite_real

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
    with its line below: the recipe carries the whole object.

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
        for name in ("certify", "mechanism_band", "fused_retry", "fuse", "continuation"):
            value = getattr(self, name)
            if value is None and name in ("fuse", "continuation"):
                continue
            if not isinstance(value, (bool, np.bool_)):  # certify="no" was read as True
                may_be_none = " or None (by the wall's size)" if name in ("fuse", "continuation") else ""
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
