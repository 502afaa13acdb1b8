"""The stability study: the iterated non-associative LP on a grid of small walls, per setting.

Runs :func:`micro.solve_nonassociative` on a grid of small walls (``t``,
``m``, ``f``, rows, storeys) for several settings (scheme x relaxation x
certificate); every run is a typed :class:`StudyRun`. The summary and the
files (``stability.csv``, ``stability.md``, ``stability.png``) are written by
:mod:`comparison.stability.render`.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

from comparison.domain.wall import WallSpec
from comparison.runner.executor import LocalExecutor, Task
from comparison.runner.pool import approximate_blocks
from comparison.utilities.progress import Progress
from micro.records import NonAssociativeRecord

#: Grid of the study: every combination that builds (all of them: the 16 whose
#: length is not a whole number of half blocks end every course with a cut
#: block). 120 walls of 9-294 blocks.
GRID: dict[str, tuple[float, ...]] = {
    "t": (0.5, 0.75, 1.0, 1.5, 2.0),
    "m": (1 / 3, 1 / 2, 1.0),
    "rows": (6, 12),
    "f": (0.6, 0.75),
    "storeys": (1, 2),
}


#: Work budget per run and direction, in simplex iterations (scheme (b) can spend
#: minutes on a 294-block wall in fallback steps, each after a warm run of up to
#: 20,000 iterations that fails: docs/speed.md); a run that spends it is reported as
#: ``max_iterations`` / ``work_budget``. A count, not seconds, so the study gives
#: the same table on every machine.
MAX_SIMPLEX_ITERATIONS = 200_000


@dataclass(frozen=True)
class Setting:
    """One setting of the iterated LP.

    Attributes:
        scheme: ``"a"`` or ``"b"``.
        relaxation: ``beta``.
        certify: stop on a certified collapse state once lambda settles
            (``False``: the plain iterated LP, which stops as converged only
            when an LP's own forces satisfy Coulomb).
    """

    scheme: Literal["a", "b"]
    relaxation: float
    certify: bool = True

    @property
    def label(self) -> str:
        """Short name, e.g. ``a/0.6`` or ``a/1 plain``."""
        return f"{self.scheme}/{self.relaxation:g}" + ("" if self.certify else " plain")


#: Settings of the study: the plain iterated LP (scheme a, no relaxation, no
#: certificate) and with relaxation, then with the certificate: no relaxation,
#: the default (a, 0.6), stronger relaxation, and scheme (b).
SETTINGS: tuple[Setting, ...] = (
    Setting("a", 1.0, False),
    Setting("a", 0.6, False),
    Setting("a", 1.0),
    Setting("a", 0.6),
    Setting("a", 0.3),
    Setting("b", 1.0),
    Setting("b", 0.6),
)


@dataclass(frozen=True)
class WallCase:
    """One wall of the grid (the paper's nondimensional parameters)."""

    t: float
    m: float
    rows: int
    f: float
    storeys: int

    @property
    def m_label(self) -> str:
        """``m`` as the paper writes it (``1/3``, ``1/2``, ``1``)."""
        return {1 / 3: "1/3", 1 / 2: "1/2", 1.0: "1"}.get(self.m, f"{self.m:g}")

    @property
    def label(self) -> str:
        """Short name, e.g. ``t1 m1/3 r12 f0.75 s1``."""
        return f"t{self.t:g} m{self.m_label} r{self.rows} f{self.f:g} s{self.storeys}"

    def spec(self) -> WallSpec:
        """The dimensional wall (no overload)."""
        return WallSpec.from_paper(t=self.t, m=self.m, rows=self.rows, f=self.f, p=0, storeys=self.storeys)


def grid_walls(grid: dict[str, tuple[float, ...]] | None = None) -> list[WallCase]:
    """The valid walls of ``grid`` (default :data:`GRID`)."""
    g = GRID if grid is None else grid
    out: list[WallCase] = []
    for t, m, rows, f, st in itertools.product(g["t"], g["m"], g["rows"], g["f"], g["storeys"]):
        case = WallCase(float(t), float(m), int(rows), float(f), int(st))
        try:
            case.spec().to_micro()
        except ValueError:
            continue
        out.append(case)
    return out


@dataclass(frozen=True)
class StudyRun:
    """One setting on one wall.

    Attributes:
        wall: the wall.
        setting: the setting.
        blocks: blocks of the wall.
        lambda_assoc: the associative load factor of the wall.
        seconds: wall time of the run.
        result: the record of the run (``None`` when it raised).
        error: the exception of a run that raised (``""`` otherwise).
    """

    wall: WallCase
    setting: Setting
    blocks: int
    lambda_assoc: float
    seconds: float
    result: NonAssociativeRecord | None
    error: str = ""

    @property
    def status(self) -> str:
        """The run's status (``solver_failure`` when it raised)."""
        return "solver_failure" if self.result is None else self.result.status

    @property
    def converged(self) -> bool:
        """The run converged."""
        return self.status == "converged"

    @property
    def stop_reason(self) -> str:
        """What stopped the sequence (``exception`` when it raised)."""
        return "exception" if self.result is None else self.result.stop_reason

    @property
    def load_factor(self) -> float:
        """The iterated LP's converged load factor (NaN otherwise; the study runs without the descent)."""
        return math.nan if self.result is None else self.result.iterated_load_factor

    @property
    def last_load_factor(self) -> float:
        """The load factor of the last successful iterate."""
        return math.nan if self.result is None else self.result.last_load_factor

    @property
    def band(self) -> tuple[float, float]:
        """``(min, max)`` of the load factor of a sequence that did not converge (NaN otherwise)."""
        band = None if self.result is None else self.result.lambda_band
        return (math.nan, math.nan) if band is None else band

    @property
    def mechanism_band(self) -> tuple[float, float]:
        """The load factors of the collapse states with the final mechanism (NaN when not computed)."""
        band = None if self.result is None else self.result.mechanism_band
        return (math.nan, math.nan) if band is None else band

    @property
    def total_iterations(self) -> int:
        """Non-associative LPs summed over the directions solved."""
        return 0 if self.result is None else self.result.total_iterations

    def row(self) -> dict[str, Any]:
        """The run as one CSV row."""
        r, w, s = self.result, self.wall, self.setting
        nan = math.nan
        return {
            "wall": w.label,
            "t": w.t,
            "m": w.m,
            "rows": w.rows,
            "f": w.f,
            "storeys": w.storeys,
            "blocks": self.blocks,
            "setting": s.label,
            "scheme": s.scheme,
            "relaxation": s.relaxation,
            "lambda_assoc": self.lambda_assoc,
            "seconds": self.seconds,
            "status": self.status,
            "stop_reason": self.stop_reason,
            "load_factor": self.load_factor,
            "last_load_factor": self.last_load_factor,
            "band_lo": self.band[0],
            "band_hi": self.band[1],
            "mband_lo": self.mechanism_band[0],
            "mband_hi": self.mechanism_band[1],
            "total_iterations": self.total_iterations,
            "warm_cold": nan if r is None else r.warm_cold_rel_diff,
            "coulomb": nan if r is None else r.coulomb_residual,
            "dilatancy": nan if r is None else r.dilatancy_residual,
            "fallbacks": 0 if r is None else r.fallback_steps,
            "message": self.error if r is None else r.message,
        }


def _run_one(args: tuple[WallCase, tuple[Setting, ...], int]) -> list[StudyRun]:
    """All settings on one wall (one worker task)."""
    import micro

    case, settings, max_iterations = args
    wall = case.spec().to_micro()
    assoc = micro.solve_associative(wall).load_factor
    runs: list[StudyRun] = []
    for s in settings:
        t0 = time.perf_counter()
        try:
            # the plain vertex sequence under each setting (the study's subject), not the report's method
            tuning = micro.Tuning(scheme=s.scheme, relaxation=s.relaxation, certify=s.certify, selection="vertex",
                                  max_simplex_iterations=MAX_SIMPLEX_ITERATIONS)
            # lowest=False: the iterated LP's own convergence; the descent: `xcheck stability --lowest`
            r = micro.solve_nonassociative(wall, tuning=tuning, max_iterations=max_iterations, lowest=False)
            record, err = r.to_record(), ""
        except Exception as exc:  # noqa: BLE001 - recorded as a failure of the setting
            record, err = None, f"{type(exc).__name__}: {exc}"
        runs.append(StudyRun(case, s, wall.n_blocks, assoc, time.perf_counter() - t0, record, err))
    return runs


def run_study(
    walls: Sequence[WallCase],
    settings: Sequence[Setting] = SETTINGS,
    *,
    processes: int = 2,
    max_iterations: int = 100,
    progress: Progress | None = None,
) -> list[StudyRun]:
    """Run every setting on every wall in ``processes`` worker processes, largest walls first.

    A wall whose task fails as a whole (its associative solve raised, or its
    worker died) gets one run per setting with the error; the runs come back in
    the order of ``walls``.
    """
    job = (tuple(settings), max_iterations)
    tasks = [Task(i, _run_one, ((w, *job),), approximate_blocks(w.spec()), 0, w.label) for i, w in enumerate(walls)]
    results: dict[int, list[StudyRun]] = {}
    with LocalExecutor(processes) as executor:
        for outcome in executor.run(tasks):
            i = outcome.task.key
            assert isinstance(i, int)
            results[i] = outcome.value if outcome.ok else [
                StudyRun(walls[i], s, 0, math.nan, outcome.seconds, None, f"{outcome.kind}: {outcome.error}")
                for s in settings
            ]
            if progress is not None:
                progress.advance(f"{walls[i].label}: {outcome.kind} in {outcome.seconds:.1f} s")
    return [run for i in range(len(walls)) for run in results[i]]
