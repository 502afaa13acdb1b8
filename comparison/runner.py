"""Run the models on walls, with results cached on disk.

A :class:`Runner` computes one method on one wall and returns a flat
:class:`Record` (numbers and strings, JSON-ready). Records are cached under
``cache_dir`` keyed by the wall, the method and its options, and the *code
version* of every package the method runs (a hash of their source files), so
that a re-run computes only what changed: editing ``micro`` recomputes the
micro results and keeps the macro ones. Micro mechanisms (block velocities)
are cached beside their records for the figures.
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from functools import cache
from pathlib import Path
from typing import Any, Literal

import numpy as np

from comparison.spec import WallSpec

Kind = Literal["macro", "micro-assoc", "micro-nonassoc"]
_PACKAGES = {"macro": ("macro",), "micro-assoc": ("micro",), "micro-nonassoc": ("micro",)}
_ROOT = Path(__file__).resolve().parents[1]


@cache
def code_version(*packages: str) -> str:
    """Hash of the source of ``packages`` and of this module and the failure-mode code."""
    h = hashlib.sha256()
    files = [p for pkg in packages for p in sorted((_ROOT / pkg).rglob("*.py"))]
    files += [_ROOT / "comparison" / "runner.py", _ROOT / "comparison" / "failure.py"]
    for path in files:
        h.update(path.relative_to(_ROOT).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


@dataclass(frozen=True)
class Method:
    """A way of computing the load factor, with its options.

    Attributes:
        kind: ``"macro"``, ``"micro-assoc"`` or ``"micro-nonassoc"``.
        solver: micro back end (see :data:`micro.SOLVERS`).
        scheme: non-associative scheme (``"a"`` or ``"b"``).
        first_course: micro bond phase, ``"full"`` or ``"half"``.
        head_joints: ``"frictional"`` or ``"frictionless"``.
    """

    kind: Kind
    solver: str = "highs"
    scheme: str = "a"
    first_course: str = "full"
    head_joints: str = "frictional"

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
        return f"{self.kind} ({', '.join(opts)})"

    def key(self) -> dict[str, str]:
        """The options that change the result."""
        if self.kind == "macro":
            return {"kind": "macro"}
        d = asdict(self)
        if self.kind == "micro-assoc":
            d.pop("scheme")
        return d


MACRO = Method("macro")
MICRO_ASSOC = Method("micro-assoc")
MICRO_NONASSOC = Method("micro-nonassoc")

#: Time budget of the iterated LP per direction in the runner: a sequence that
#: spends it stops as ``max_iterations`` (``time_budget``) with its last band.
NONASSOC_SECONDS = 180.0


@dataclass(frozen=True)
class Record:
    """One method's result on one wall (JSON-ready).

    Attributes:
        wall: the wall's name.
        method: :attr:`Method.label`.
        load_factor: ``lambda`` (NaN when the method failed or does not apply).
        status: the method's status (``optimal``, ``converged``, ``cycling``,
            ``not_applicable``, ...).
        seconds: wall time of the computation (not of a cache hit).
        values: every other number the method reports (sizes, iterations,
            angles, hinge storey, failure mode, ...).
        cached: True when read from the cache.
    """

    wall: str
    method: str
    load_factor: float
    status: str
    seconds: float
    values: dict[str, Any] = field(default_factory=dict)
    cached: bool = False

    def get(self, key: str, default: Any = None) -> Any:
        """A value by name, including the top-level fields."""
        if key in ("load_factor", "status", "seconds"):
            return getattr(self, key)
        return self.values.get(key, default)


def _wall_key(spec: WallSpec) -> dict[str, Any]:
    d = asdict(spec)
    d.pop("name", None)
    return d


def _finite(x: float) -> float | None:
    return x if isinstance(x, (int, float)) and math.isfinite(x) else None


class Runner:
    """Compute methods on walls, caching records on disk.

    Args:
        cache_dir: where records live (``None``: no cache).
        progress: called with one line per computation (``None``: silent).
    """

    def __init__(
        self,
        cache_dir: Path | None = Path(".xcheck-cache"),
        progress: Callable[[str], None] | None = None,
        *,
        plan_only: bool = False,
    ) -> None:
        self.cache_dir = cache_dir
        self.progress = progress
        self.plan_only = plan_only
        self.planned: dict[Path, tuple[WallSpec, Method]] = {}
        self.computed = 0
        self.hits = 0

    def _path(self, spec: WallSpec, method: Method) -> Path | None:
        if self.cache_dir is None:
            return None
        key = {"wall": _wall_key(spec), "method": method.key(), "code": code_version(*_PACKAGES[method.kind])}
        digest = hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:24]
        return self.cache_dir / method.kind / f"{digest}.json"

    def run(self, spec: WallSpec, method: Method) -> Record:
        """The record of ``method`` on ``spec``, from the cache when it is there."""
        path = self._path(spec, method)
        if self.plan_only:
            if path is not None and not path.exists():
                self.planned.setdefault(path, (spec, method))
            return Record(spec.name or "wall", method.label, float("nan"), "planned", 0.0)
        if path is not None and path.exists():
            d = json.loads(path.read_text())
            self.hits += 1
            return Record(spec.name or d["wall"], method.label, _nan(d["load_factor"]), d["status"], d["seconds"], d["values"], cached=True)
        record, mechanism = _compute(spec, method)
        self.computed += 1
        if self.progress:
            self.progress(f"{spec.name or 'wall'}: {method.label}: lambda = {record.load_factor:.4f} ({record.status}) in {record.seconds:.2f} s")
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            d = asdict(record)
            d["load_factor"] = _finite(record.load_factor)
            path.write_text(json.dumps(d, indent=1, default=_json_default))
            if mechanism is not None:
                np.savez_compressed(path.with_suffix(".npz"), **mechanism)
        return record

    def prefetch(self, items: list[tuple[WallSpec, Method]], workers: int) -> None:
        """Compute the records of ``items`` missing from the cache in ``workers`` processes.

        The largest walls go first, so that the processes finish together.
        """
        if self.cache_dir is None or not items:
            return
        from concurrent.futures import ProcessPoolExecutor, as_completed

        order = sorted(items, key=lambda it: -sum(s.rows for s in it[0].storeys) * it[0].length / it[0].block_length)
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(_prefetch_one, self.cache_dir, spec, method) for spec, method in order]
            for done, fut in enumerate(as_completed(futures), start=1):
                line = fut.result()
                self.computed += 1
                if self.progress:
                    self.progress(f"[{done}/{len(futures)}] {line}")

    def mechanism(self, spec: WallSpec, method: Method) -> dict[str, np.ndarray] | None:
        """The cached mechanism arrays of a micro record (``velocities``), if any."""
        if self.plan_only:
            return None
        path = self._path(spec, method)
        if path is None:
            _, mech = _compute(spec, method)
            return mech
        npz = path.with_suffix(".npz")
        if not npz.exists():
            self.run(spec, method)
        if not npz.exists():
            return None
        with np.load(npz) as data:
            return {k: data[k] for k in data.files}


def _prefetch_one(cache_dir: Path, spec: WallSpec, method: Method) -> str:
    lines: list[str] = []
    Runner(cache_dir, lines.append).run(spec, method)
    return lines[0] if lines else f"{spec.name}: {method.label}: cached"


def _nan(x: float | None) -> float:
    return float("nan") if x is None else float(x)


def _json_default(o: Any) -> Any:
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.floating,)):
        return _finite(float(o))
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def _compute(spec: WallSpec, method: Method) -> tuple[Record, dict[str, np.ndarray] | None]:
    name = spec.name or "wall"
    t0 = time.perf_counter()
    if method.kind == "macro":
        import macro

        r = macro.solve(spec.to_macro())
        values = {
            "rocking_load_factor": r.rocking_load_factor,
            "sliding_load_factor": r.sliding_load_factor,
            "alpha_c_deg": r.alpha_c_deg,
            "alpha_c_star_deg": math.degrees(math.atan(r.tan_alpha_c - r.wall.overlap / (sum(r.wall.rows[: r.hinge_storey]) * r.wall.block_height))),
            "alpha_ratio": r.alpha_ratio,
            "hinge_storey": r.hinge_storey,
            "mechanism": r.mechanism,
        }
        return Record(name, method.label, r.load_factor, r.status, time.perf_counter() - t0, values), None
    import micro

    try:
        wall = spec.to_micro(first_course=method.first_course, head_joints=method.head_joints)
    except ValueError as exc:
        return Record(name, method.label, float("nan"), "not_applicable", 0.0, {"message": str(exc)}), None
    if method.kind == "micro-assoc":
        res = micro.solve_associative(wall, solver=method.solver)
        values = {k: v for k, v in res.summary().items() if k not in ("load_factor", "status", "directions")}
        values["lambda_by_direction"] = {d.direction: _finite(d.load_factor) for d in res.directions}
        lam, status, velocities, direction = res.load_factor, res.status, res.velocities, res.direction
    else:
        res = micro.solve_nonassociative(wall, scheme=method.scheme,  # type: ignore[attr-defined]
                                         max_seconds=NONASSOC_SECONDS)
        gov = next((d for d in res.directions if d.direction == res.direction), None)
        values = {
            "solver": "clarabel (start, certificate) + highs-simplex (iterated) + highs-ipm (cold check)",
            "scheme": res.scheme,
            "converged": res.converged,
            "iterations": res.iterations,
            "band": list(res.lambda_band) if res.lambda_band else None,
            "mechanism_band": list(res.mechanism_band) if res.mechanism_band else None,
            "stop_reason": res.stop_reason,
            "associative_load_factor": res.associative_load_factor,
            "warm_cold_rel_diff": res.warm_cold_rel_diff,
            "coulomb_residual": res.coulomb_residual,
            "dilatancy_residual": res.dilatancy_residual,
            "blocks": res.blocks,
            "contacts": res.contacts,
            "build_seconds": res.build_seconds,
            "solve_seconds": res.solve_seconds,
            "history_load_factor": [h.load_factor for h in res.history],
            "message": res.message,
        }
        lam, status, direction = res.load_factor, res.status, res.direction
        velocities = None
        if gov is not None and gov.mechanism is not None:
            velocities = gov.mechanism.velocities
            values["contact_states"] = gov.mechanism.state_counts()
    mech = None
    if velocities is not None and direction:
        from comparison.failure import failure_mode

        try:
            fm = failure_mode(wall, velocities, direction)
            values.update({f"failure_{k}": v for k, v in asdict(fm).items()})
        except ValueError as exc:
            values["failure_message"] = str(exc)
        mech = {"velocities": np.asarray(velocities), "direction": np.array(direction)}
    return Record(name, method.label, lam, status, time.perf_counter() - t0, values), mech


def stderr_progress(line: str) -> None:
    """Progress printer for long runs."""
    print(line, file=sys.stderr, flush=True)
