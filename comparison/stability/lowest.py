"""How far is the iterated LP from the lowest collapse load? (issue 14, item 3)

On Table 7's walls, on the walls of the stability grid and on a grid of tiny
walls (2-4 rows), :func:`micro.solve_nonassociative` runs with its defaults
(scheme a, relaxation 0.6, certified) and the descent to the lowest certified
state; the global search (branch and bound, started from the lowest state)
runs on Table 7's walls and on every wall of at most
:data:`GLOBAL_MAX_BLOCKS` blocks, stopped by a NODE limit so that every
number reproduces on another machine. Each run is one typed
:class:`LowestRun`; :mod:`comparison.stability.lowest_render` writes
``lowest.md``, ``lowest.csv`` and ``lowest.png``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

from comparison.domain.cases import cases_in_table
from comparison.runner.executor import LocalExecutor, Task
from comparison.stability.study import GRID, WallCase, grid_walls

#: The tiny walls: the MIP proves the global minimum on walls of a few blocks
#: only, and the stability grid's smallest walls have 9 blocks.
TINY_GRID: dict[str, tuple[float, ...]] = {
    "t": (0.5, 1.0, 2.0),
    "m": (1 / 3, 1 / 2, 1.0),
    "rows": (2, 3, 4),
    "f": (0.6, 0.75),
    "storeys": (1,),
}
#: Walls of at most this many blocks get the global search (on 12-21 blocks a search
#: of a minute left the bound at 0; on 9 blocks it closed in 5,000-8,500 nodes).
GLOBAL_MAX_BLOCKS = 10
#: Branch-and-bound nodes per direction on those walls.
GLOBAL_NODES = 10_000
#: Nodes per direction on Table 7's walls (54-150 blocks), default bond only:
#: enough to show the bound (it stays 0 there).
TABLE7_NODES = 20
#: Big-M policy of every search: one LP for the bound on the normal forces
#: (per-point bounds cost one LP per contact point, minutes on Table 7's
#: walls, and closed no search that the uniform bound did not).
GLOBAL_BOUNDS: Literal["per_point", "uniform"] = "uniform"
#: (first_course, head_joints) of Table 7's walls in the study.
TABLE7_BONDS = (("full", "frictional"), ("half", "frictional"), ("full", "frictionless"), ("half", "frictionless"))
#: A lowest state within this relative distance of the proven global minimum counts as global.
GLOBAL_MATCH = 1e-6


@dataclass(frozen=True)
class LowestCase:
    """One wall of the study.

    Attributes:
        group: ``"table7"``, ``"grid"`` or ``"tiny"``.
        wall: its nondimensional parameters.
        first_course, head_joints: the bond variant.
        nodes: nodes per direction of the global search (0: none).
        published: Orduña's micro load factor (Table 7; NaN otherwise).
        label: e.g. ``"Set 12"`` or the wall's label.
    """

    group: str
    wall: WallCase
    first_course: str = "full"
    head_joints: str = "frictional"
    nodes: int = 0
    published: float = math.nan
    label: str = ""

    @property
    def name(self) -> str:
        """The label with the bond variant when it is not the default."""
        base = self.label or self.wall.label
        bond = [] if self.first_course == "full" else ["half first"]
        bond += [] if self.head_joints == "frictional" else ["frictionless heads"]
        return f"{base} ({', '.join(bond)})" if bond else base


@dataclass(frozen=True)
class LowestRun:
    """One wall: the iterated LP, the lowest certified state, the global search.

    Attributes:
        case: the wall.
        blocks: its blocks.
        status: the iterated LP's status (``"error: ..."`` when it raised).
        iterated: the iterated LP's load factor (NaN unless converged).
        band: the mechanism band of its final state (NaN when not computed).
        lowest: the lowest certified load factor (NaN when not found).
        lowest_moves: moves between mechanisms that led to it.
        global_status: ``""`` (not run), ``"optimal"``, ``"node_limit"``, ...
        global_best: the search's best collapse state (NaN without one).
        global_bound: its proven lower bound.
        global_gap: ``(best - bound) / best``.
        nodes: its branch-and-bound nodes.
        it_seconds, lowest_seconds, global_seconds: wall time of each part.
        it_lps, lowest_lps: LPs of the iterated LP (both directions) and of the descent.
        macro: the macro-block model's load factor of the wall (Table 7's walls; NaN otherwise).
    """

    case: LowestCase
    blocks: int
    status: str
    iterated: float
    band: tuple[float, float]
    lowest: float
    lowest_moves: int
    global_status: str
    global_best: float
    global_bound: float
    global_gap: float
    nodes: int
    it_seconds: float
    lowest_seconds: float
    global_seconds: float
    it_lps: int
    lowest_lps: int
    macro: float = math.nan

    @property
    def closed(self) -> bool:
        """The global search proved the global minimum."""
        return self.global_status == "optimal"

    @property
    def global_min(self) -> float:
        """The proven global minimum (NaN unless :attr:`closed`)."""
        return self.global_best if self.closed else math.nan

    def excess(self, value: float) -> float:
        """``(value - reference) / reference`` with the global minimum as
        reference where it is proven, else the lowest certified state."""
        ref = self.global_min if self.closed else self.lowest
        return (value - ref) / ref if math.isfinite(ref) and ref > 0 and math.isfinite(value) else math.nan

    def row(self) -> dict[str, Any]:
        """The run as one CSV row."""
        c, w = self.case, self.case.wall
        return {
            "group": c.group, "wall": c.name, "t": w.t, "m": w.m, "rows": w.rows, "f": w.f, "storeys": w.storeys,
            "first_course": c.first_course, "head_joints": c.head_joints, "blocks": self.blocks,
            "orduna": c.published, "status": self.status, "lambda_iterated": self.iterated,
            "band_lo": self.band[0], "band_hi": self.band[1], "lambda_lowest": self.lowest,
            "lowest_moves": self.lowest_moves, "global_status": self.global_status,
            "global_best": self.global_best, "global_bound": self.global_bound, "global_gap": self.global_gap,
            "global_nodes": self.nodes, "iterated_over_lowest": _rel(self.iterated, self.lowest),
            "iterated_over_global": _rel(self.iterated, self.global_min),
            "lowest_over_global": _rel(self.lowest, self.global_min), "iterated_seconds": self.it_seconds,
            "lowest_seconds": self.lowest_seconds, "global_seconds": self.global_seconds,
            "iterated_lps": self.it_lps, "lowest_lps": self.lowest_lps, "lambda_macro": self.macro,
            "macro_safe": safe_side(self.macro, min(self.lowest, self.global_best), self.global_bound),
        }


def _rel(value: float, ref: float) -> float:
    return (value - ref) / ref if math.isfinite(value) and math.isfinite(ref) and ref > 0 else math.nan


def safe_side(macro: float, best: float, bound: float) -> str:
    """Is the macro model's load factor on the safe side of the micro model's (non-associative) collapse load?

    Args:
        macro: the macro model's load factor.
        best: the least load factor of an exact (verified) micro collapse state.
        bound: a proven lower bound of every micro collapse load factor.

    Returns:
        ``"yes"`` (proven: ``macro <= bound``), ``"no"`` (an exact collapse
        state lies below ``macro``), ``"unproven"`` (``bound < macro <= best``)
        or ``""`` (no macro value).
    """
    if not math.isfinite(macro):
        return ""
    if math.isfinite(bound) and macro <= bound:
        return "yes"
    if math.isfinite(best) and best < macro:
        return "no"
    return "unproven"


def macro_load_factor(case: LowestCase) -> float:
    """The macro model's load factor of a Table 7 wall (NaN for other groups, or when it fails)."""
    if case.group != "table7":
        return math.nan
    import macro

    r = macro.solve(case.wall.spec().to_macro())
    return float(r.load_factor) if r.status == "optimal" else math.nan


def study_cases(quick: bool = False) -> list[LowestCase]:
    """Table 7's walls (every bond variant), the stability grid and the tiny grid.

    Args:
        quick: Table 7's default walls and the tiny walls of at most 4 blocks only.
    """
    out = []
    for c in cases_in_table("7"):
        value = c.value("orduna_micro")
        wall = WallCase(c.t, c.m, c.rows, c.f, c.storeys)
        for i, (fc, hj) in enumerate(TABLE7_BONDS[: 1 if quick else None]):
            out.append(LowestCase("table7", wall, fc, hj, 0 if i else TABLE7_NODES,
                                  value.value if value else math.nan, f"Set {c.case}"))
    tiny = grid_walls(TINY_GRID)
    blocks = {w: w.spec().to_micro().n_blocks for w in tiny}
    for w in tiny:
        if not quick or blocks[w] <= 4:
            out.append(LowestCase("tiny", w, nodes=GLOBAL_NODES if blocks[w] <= GLOBAL_MAX_BLOCKS else 0))
    if not quick:
        for w in grid_walls(GRID):
            small = w.spec().to_micro().n_blocks <= GLOBAL_MAX_BLOCKS
            out.append(LowestCase("grid", w, nodes=GLOBAL_NODES if small else 0))
    return out


def run_case(case: LowestCase) -> LowestRun:
    """The iterated LP, the descent and (with ``case.nodes``) the global search on one wall."""
    import micro
    from micro.global_search import GlobalOptions, solve_global

    wall = case.wall.spec().to_micro(first_course=case.first_course, head_joints=case.head_joints)
    nan = math.nan
    try:
        r = micro.solve_nonassociative(wall)
        g = solve_global(wall, start=r, options=GlobalOptions(node_limit=case.nodes, direction_time_limit=None,
                                                                bounds=GLOBAL_BOUNDS)) if case.nodes else None
    except Exception as exc:  # noqa: BLE001 - recorded as the run's status
        return _failed(case, wall.n_blocks, f"error: {type(exc).__name__}: {exc}")
    rec = r.to_record(search=g)
    band = r.mechanism_band if r.converged and r.mechanism_band is not None else (nan, nan)
    return LowestRun(
        case, wall.n_blocks, r.status, r.iterated_load_factor, band, rec.lowest_load_factor, rec.lowest_moves,
        rec.global_status, rec.global_load_factor, rec.global_lower_bound, rec.global_gap,
        0 if g is None else g.nodes, sum(d.seconds for d in r.directions),
        rec.lowest_seconds, nan if g is None else g.seconds, r.total_iterations, rec.lowest_lps,
        macro_load_factor(case),
    )


def _failed(case: LowestCase, blocks: int, status: str) -> LowestRun:
    """The run of a case that gave no result (``status`` says why)."""
    nan = math.nan
    return LowestRun(case, blocks, status, nan, (nan, nan), nan, 0, "", nan, nan, nan, 0, nan, nan, nan, 0, 0)


def run_cases(cases: Sequence[LowestCase], processes: int = 2) -> list[LowestRun]:
    """Every case, largest searches first: in this process (``processes <= 1``) or on a
    :class:`~comparison.runner.executor.LocalExecutor` (Ctrl-C and a dead parent end its workers)."""
    if processes <= 1:
        order = sorted(range(len(cases)), key=lambda i: -cases[i].nodes)
        by_index = {i: run_case(cases[i]) for i in order}
        return [by_index[i] for i in range(len(cases))]
    tasks = [Task(i, run_case, (c,), c.nodes, 0, c.name) for i, c in enumerate(cases)]
    done: dict[int, LowestRun] = {}
    with LocalExecutor(processes) as executor:
        for outcome in executor.run(tasks):
            i = outcome.task.key
            assert isinstance(i, int)
            done[i] = outcome.value if outcome.ok else _failed(cases[i], 0, f"{outcome.kind}: {outcome.error}")
    return [done[i] for i in range(len(cases))]
