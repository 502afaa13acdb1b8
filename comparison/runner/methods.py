"""The methods the runner computes: the macro model and the two micro LPs, with their options."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Literal

from micro import DEFAULT_SOLVER

if TYPE_CHECKING:
    from micro.nonassociative.options import Selection

Kind = Literal["macro", "micro-assoc", "micro-nonassoc"]

#: The packages whose source decides each kind's results (part of the cache key).
PACKAGES: dict[str, tuple[str, ...]] = {"macro": ("macro",), "micro-assoc": ("micro",), "micro-nonassoc": ("micro",)}

#: Cap on the LPs of the iterated LP per direction in the runner: a sequence
#: that reaches it stops as ``max_iterations`` with its last band. A count of
#: LPs, not seconds: the runner's results are the same on every machine (a
#: former 180 s budget turned Set 9 into ``max_iterations`` on a slower one).
NONASSOC_MAX_LPS = 100

#: The runner descends to the lowest certified state
#: (:mod:`micro.nonassociative.lowest`) on walls of at most this many blocks.
#: The descent cost 1.3 times the iterated LP (median) on the small walls of
#: ``xcheck stability --lowest`` but 676 s (46 LPs, 135 times the iterated LP's
#: 5 s) on a 990-block wall of the sensitivity study, which would take the
#: report far beyond its 20 minutes; Table 7's walls (54-150 blocks) keep it.
NONASSOC_LOWEST_MAX_BLOCKS = 300

#: On walls of more than this many blocks the runner's iterated LP runs on the
#: fused wall (:mod:`micro.nonassociative.fusion`) with the continuation
#: (``continuation=True``): Set 10 (3,630 blocks) is certified after 54 LPs,
#: 475 s on one core, where no unfused sequence settled in 12 minutes. The walls
#: of up to 2,000 blocks keep the unfused sequence and its results.
NONASSOC_FUSE_BLOCKS = 2000

#: How the runner's iterated LP picks its forces (:data:`micro.nonassociative.SELECTIONS`):
#: the vertex sequence, and the proximal one from its last normal forces on a
#: direction where it cycles (Sets 2 and 9 of Table 5 cycle with vertices; the
#: proximal sequence certifies them after 15 and 27 LPs, 77 s and 335 s in all
#: on one core; the lazy sequence, which the report ran before, certified Set 2
#: after 17 LPs, 157 s in all, and ended Set 9 at its cap of 40 LPs after 727 s).
#: Walls where the vertex sequence converges keep its result. Scheme (b) runs
#: ``"vertex"`` (:func:`default_selection`).
NONASSOC_SELECTION: Selection = "vertex+proximal"
#: Cap on the LPs of that proximal sequence per direction (Sets 2 and 9 need
#: 15 and 27; a lazy LP on Set 9 cost ~12 s, a proximal one 3-7 s with its QP).
NONASSOC_RETRY_LPS = 40


def default_selection(scheme: str) -> Selection:
    """The runner's selection for a scheme: :data:`NONASSOC_SELECTION` for
    (a), ``"vertex"`` for (b), which has no lazy or proximal selection."""
    return NONASSOC_SELECTION if scheme == "a" else "vertex"


@dataclass(frozen=True)
class Method:
    """A way of computing the load factor, with its options.

    Attributes:
        kind: ``"macro"``, ``"micro-assoc"`` or ``"micro-nonassoc"``.
        solver: micro back end (see :data:`micro.SOLVERS`; default the library's,
            :data:`micro.DEFAULT_SOLVER`).
        scheme: non-associative scheme (``"a"`` or ``"b"``).
        first_course: micro bond phase, ``"full"`` or ``"half"``.
        head_joints: ``"frictional"`` or ``"frictionless"``.
        lowest_max_blocks: non-associative: the descent to the lowest certified
            state runs on walls of at most this many blocks.
        selection: non-associative: how the iterates pick their forces;
            ``None``: the scheme's default (:attr:`nonassoc_selection`).
        fuse_min_blocks: non-associative, scheme (a): walls of more than
            this many blocks run fused, with the continuation.
    """

    kind: Kind
    solver: str = DEFAULT_SOLVER
    scheme: Literal["a", "b"] = "a"
    first_course: str = "full"
    head_joints: str = "frictional"
    lowest_max_blocks: int = NONASSOC_LOWEST_MAX_BLOCKS
    selection: Selection | None = None
    fuse_min_blocks: int = NONASSOC_FUSE_BLOCKS

    @property
    def nonassoc_selection(self) -> Selection:
        """The selection the iterated LP runs: :attr:`selection`, or
        :func:`default_selection` of the scheme. Resolved here rather than
        stored, so that ``replace(MICRO_NONASSOC, scheme="b")`` gets scheme
        (b)'s default."""
        return default_selection(self.scheme) if self.selection is None else self.selection

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
        if self.kind == "micro-nonassoc" and self.nonassoc_selection != default_selection(self.scheme):
            opts.append(f"{self.selection} selection")
        return f"{self.kind} ({', '.join(opts)})"

    def key(self) -> dict[str, str]:
        """The options that change the result."""
        if self.kind == "macro":
            return {"kind": "macro"}
        d = asdict(self)
        if self.kind == "micro-assoc":
            d.pop("scheme")
            d.pop("lowest_max_blocks")
            d.pop("selection")
            d.pop("fuse_min_blocks")
        else:
            d["selection"] = self.nonassoc_selection  # an explicit default is the same computation
        return d


MACRO = Method("macro")
MICRO_ASSOC = Method("micro-assoc")
MICRO_NONASSOC = Method("micro-nonassoc")
