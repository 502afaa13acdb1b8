"""The report's run plan: every (wall, method) the report needs, built before anything runs.

:func:`build_plan` lists the walls of every table and figure (the paper's cases,
the bond variants of Table 7, the sensitivity sweeps, the speed-accuracy
resolutions) and the methods run on each. The report computes exactly the
plan (missing cache entries in parallel processes first), and the tables,
figures and text then read the results; a table that asked for a pair outside
the plan would fail, not compute.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

from comparison.domain.cases import CASES, PaperCase, cases_in_table
from comparison.domain.wall import WallSpec
from comparison.runner import MICRO_ASSOC, MICRO_NONASSOC, Method, ResultCache, approximate_blocks
from micro.backends.registry import timed_solvers

#: The report runs the iterated non-associative LP on the walls of its sweeps
#: and of the speed-accuracy study of at most this many blocks: the Table 5
#: walls of up to 1,830 blocks (the runner caps a sequence at
#: :data:`comparison.runner.NONASSOC_MAX_LPS`; their times: docs/speed.md) ...
NONASSOC_MAX_BLOCKS = 2000
#: ... and on the paper's walls of at most this many: Set 10 (3,630 blocks)
#: runs fused with the continuation (:data:`micro.nonassociative.config.FUSE_BLOCKS`);
#: the 7,575-block Table 9 walls stay out (no method here has settled on them, see
#: ``docs/micro/nonassociative.md``; what their first LPs cost: docs/speed.md).
NONASSOC_MAX_BLOCKS_CASES = 4000

#: Base walls of the sensitivity sweeps and of the speed-accuracy study.
BASE_FULL: Mapping[str, float] = {"t": 1.0, "m": 1 / 3, "rows": 60, "f": 0.6, "p": 0.0, "storeys": 3}
BASE_QUICK: Mapping[str, float] = {"t": 1.0, "m": 1 / 3, "rows": 12, "f": 0.75, "p": 0.0, "storeys": 1}

#: The values of each parameter in the sensitivity sweeps.
SWEEPS_FULL: Mapping[str, tuple[float, ...]] = {
    "f": (0.4, 0.5, 0.6, 0.7, 0.8),
    "t": (0.5, 1.0, 1.25, 2.0, 2.5, 3.0),
    "m": (0.25, 1 / 3, 0.5, 1.0),
    "rows": (12, 24, 36, 45, 60),
    "p": (0.0, 1.0, 2.0, 4.0, 8.0),
}
SWEEPS_QUICK: Mapping[str, tuple[float, ...]] = {
    "f": (0.5, 0.6, 0.75, 0.9),
    "t": (0.5, 1.0, 2.0),
    "m": (0.25, 1 / 3, 0.5, 1.0),
    "rows": (6, 9, 12, 18, 24),
    "p": (0.0, 1.0, 4.0),
}


def micro_methods() -> tuple[Method, ...]:
    """The micro methods of the report: the associative LP by the library's
    default back end (:data:`micro.DEFAULT_SOLVER`, ``docs/micro/associative.md``)
    and the iterated non-associative LP."""
    return (MICRO_ASSOC, MICRO_NONASSOC)


#: The bond variants the suite builds: (first course, head joints), the paper's bond first.
BONDS: tuple[tuple[str, str], ...] = (("full", "frictional"), ("half", "frictional"), ("full", "frictionless"),
                                      ("half", "frictionless"))


def bond_variants(method: Method) -> tuple[Method, ...]:
    """``method`` as it is, then with every other bond of :data:`BONDS`."""
    return (method, *[replace(method, first_course=fc, head_joints=hj) for fc, hj in BONDS[1:]])


@dataclass(frozen=True)
class PlanItem:
    """One (wall, method) of the plan.

    Attributes:
        spec: the wall.
        method: the method.
        skip: why the report does not run it (``""``: it runs).
    """

    spec: WallSpec
    method: Method
    skip: str = ""


@dataclass(frozen=True)
class Plan:
    """What the report computes.

    Attributes:
        quick: small walls only for the micro model.
        methods: the micro methods, the reference (the non-associative LP) last.
        cases: the paper's cases the micro model runs on.
        base: the paper parameters of the base wall of the sweeps and of the speed study.
        sweeps: the values of each parameter in the sensitivity sweeps.
        resolutions: the rows of the speed-accuracy walls, ascending; the reference is the finest
            one the non-associative LP runs on (:attr:`reference_rows`), the finer ones (up to 7,575
            blocks) run the associative back ends only.
        solvers: the associative back ends of the speed-accuracy study.
    """

    quick: bool
    methods: tuple[Method, ...]
    cases: tuple[PaperCase, ...]
    base: Mapping[str, float]
    sweeps: Mapping[str, tuple[float, ...]]
    resolutions: tuple[int, ...]
    solvers: tuple[str, ...]

    @property
    def reference(self) -> Method:
        """The best micro reference: the non-associative LP."""
        return self.methods[-1]

    @property
    def reference_rows(self) -> int:
        """The rows of the speed-accuracy reference: the finest resolution the reference method runs on."""
        return max(r for r in self.resolutions if not _skip(self.speed_spec(r), self.reference))

    def sweep_spec(self, param: str, value: float) -> WallSpec:
        """The base wall with ``param`` set to ``value``."""
        return WallSpec.from_paper(**{**self.base, param: value}, name=f"{param}={value:.4g}")  # type: ignore[arg-type]

    def speed_spec(self, rows: int, name: str | None = None) -> WallSpec:
        """The base wall with ``rows`` rows."""
        return WallSpec.from_paper(**{**self.base, "rows": rows}, name=name or f"{rows} rows")  # type: ignore[arg-type]

    def slender_spec(self) -> WallSpec:
        """The base wall shortened to one block (``t = o m``), where Eq. (10) meets the rigid overturning bound."""
        one_block = self.base["rows"] * self.base["m"]
        return WallSpec.from_paper(**{**self.base, "t": one_block}, name="one block long")  # type: ignore[arg-type]

    def rows_specs(self) -> list[WallSpec]:
        """The base wall with each number of rows of the rows sweep (the same wall of ever smaller blocks)."""
        return [self.sweep_spec("rows", v) for v in self.sweeps.get("rows", ())]

    def macro_specs(self) -> list[WallSpec]:
        """The walls the macro model runs on: every case, Table 9 with ``m = 1/2``, Table 5 with the other
        reading of ``p``, the sweeps, the speed base, the slender base wall."""
        specs = [c.spec() for c in CASES] + [table9_alternative(c) for c in cases_in_table("9")]
        specs += [c.spec("storey") for c in cases_in_table("5") if c.p > 0]  # the other reading of p
        specs += [self.sweep_spec(p, v) for p, values in self.sweeps.items() for v in values]
        return [*specs, self.speed_spec(int(self.base["rows"]), "macro"), self.slender_spec()]

    def items(self) -> list[PlanItem]:
        """Every (wall, method) pair the micro tables and figures read, each once."""
        pairs = [(c.spec(), m) for c in self.cases for m in self.methods]
        pairs += [(c.spec(), v) for c in cases_in_table("7") for m in self.methods for v in bond_variants(m)[1:]]
        # how robust the macro-vs-micro finding is: the rows sequence of the base wall in every bond
        pairs += [(s, v) for s in self.rows_specs() for v in bond_variants(self.reference)[1:]]
        pairs += [(self.sweep_spec(p, v), m) for p, values in self.sweeps.items() for v in values for m in self.methods]
        for rows in self.resolutions:
            spec = self.speed_spec(rows)
            pairs += [(spec, replace(MICRO_ASSOC, solver=s)) for s in self.solvers]
            pairs += [(spec, m) for m in self.methods[1:]]
        unique = dict.fromkeys(pairs)
        cases = {c.spec() for c in self.cases}
        return [PlanItem(spec, m, _skip(spec, m, NONASSOC_MAX_BLOCKS_CASES if spec in cases else NONASSOC_MAX_BLOCKS))
                for spec, m in unique]

    def pending(self, cache: ResultCache) -> list[PlanItem]:
        """The items that run and are missing from ``cache``."""
        return [it for it in self.items() if not it.skip and (it.spec, it.method) not in cache]


def _skip(spec: WallSpec, method: Method, limit: int = NONASSOC_MAX_BLOCKS) -> str:
    blocks = approximate_blocks(spec)
    if method.kind == "micro-nonassoc" and blocks > limit:
        return f"about {blocks} blocks: above {limit}"
    return ""


def table9_alternative(case: PaperCase) -> WallSpec:
    """A Table 9 wall with ``m = 1/2`` instead of Table 6's 1/3 (the value that reproduces the paper)."""
    return WallSpec.from_paper(t=case.t, m=0.5, rows=case.rows, f=case.f, p=case.p, storeys=case.storeys)


def build_plan(quick: bool = False) -> Plan:
    """The plan of the full report, or of the quick one (the micro model on walls of at most 12 rows)."""
    return Plan(
        quick=quick,
        methods=micro_methods(),
        cases=tuple(c for c in CASES if not quick or c.rows <= 12),
        base=BASE_QUICK if quick else BASE_FULL,
        sweeps=SWEEPS_QUICK if quick else SWEEPS_FULL,
        resolutions=(3, 6, 9, 12) if quick else (12, 24, 36, 60, 102, 150),
        solvers=timed_solvers(quick),  # the registry's (micro/backends/registry.py), installed
    )
