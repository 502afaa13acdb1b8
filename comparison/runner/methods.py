"""The methods the runner computes: the macro model and the two micro LPs, with their options."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, Literal

from micro import DEFAULT_SOLVER
from micro.nonassociative.config import RETRY_LPS, NonAssociativeOptions

Kind = Literal["macro", "micro-assoc", "micro-nonassoc"]

#: The library's caps on the iterated LP's LPs per direction (the first
#: sequence, and the proximal one after it), quoted by the report's text.
NONASSOC_MAX_LPS = NonAssociativeOptions().max_iterations
NONASSOC_RETRY_LPS = RETRY_LPS


@dataclass(frozen=True)
class Method:
    """A way of computing the load factor, with its options.

    The non-associative method is :func:`micro.solve_nonassociative` with its
    defaults (the recipe lives in ``micro``); only a sweep that studies the
    method itself changes its research knobs (:attr:`tuning`).

    Attributes:
        kind: ``"macro"``, ``"micro-assoc"`` or ``"micro-nonassoc"``.
        solver: micro back end (see :data:`micro.SOLVERS`; default the library's,
            :data:`micro.DEFAULT_SOLVER`).
        first_course: micro bond phase, ``"full"`` or ``"half"``.
        head_joints: ``"frictional"`` or ``"frictionless"``.
        tuning: non-associative: the knobs of :class:`micro.Tuning` that
            differ from its defaults, as sorted ``(name, value)`` pairs
            (``()``: the library's method).
    """

    kind: Kind
    solver: str = DEFAULT_SOLVER
    first_course: str = "full"
    head_joints: str = "frictional"
    tuning: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self) -> None:
        # sorted pairs (JSON gives lists back), so that equal knobs give equal methods
        object.__setattr__(self, "tuning", tuple(sorted((str(k), v) for k, v in self.tuning)))

    @property
    def scheme(self) -> str:
        """The non-associative scheme (``"a"`` unless :attr:`tuning` says otherwise)."""
        return str(dict(self.tuning).get("scheme", "a"))

    def nonassoc_tuning(self) -> Any:
        """The :class:`micro.Tuning` of :attr:`tuning`."""
        import micro

        return micro.Tuning(**dict(self.tuning))

    @property
    def column(self) -> str:
        """The method's name over a column of load factors: its kind, and for the non-associative
        method the value it gives (the lowest certified collapse state, which the docs say to quote)."""
        return f"{self.kind} (lowest certified)" if self.kind == "micro-nonassoc" else self.kind

    @property
    def label(self) -> str:
        """Short name for tables and figures."""
        if self.kind == "macro":
            return "macro"
        opts = [self.solver] if self.kind == "micro-assoc" else [f"scheme {self.scheme}"]
        if self.first_course != "full":
            opts.append("half first")
        if self.head_joints != "frictional":
            opts.append("frictionless heads")
        if self.kind == "micro-nonassoc":
            opts += [f"{v} selection" if k == "selection" else f"{k} {v}" for k, v in self.tuning if k != "scheme"]
        return f"{self.kind} ({', '.join(opts)})"

    def key(self) -> dict[str, Any]:
        """The options that change the result."""
        if self.kind == "macro":
            return {"kind": "macro"}
        d = asdict(self)
        if self.kind == "micro-assoc":
            d.pop("tuning")
        else:
            d["tuning"] = [list(pair) for pair in self.tuning]
        return d


MACRO = Method("macro")
MICRO_ASSOC = Method("micro-assoc")
MICRO_NONASSOC = Method("micro-nonassoc")
