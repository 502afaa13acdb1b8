"""Trace the non-associative default's branching inputs, to compare them bit for bit between BLAS kernels.

Research script of ``docs/research/2026-11-28-blas-independent-descent.md``. It wraps the steps
whose numbers decide the path (every HiGHS run, every Clarabel solve, the proximal projection and
its normal-matrix solves, the refinement of a force LP's vertex, the pattern of a mechanism, the
descent's states) and writes one line per call: the step, and a digest of what it returned
(SHA-1 of the arrays' bytes; load factors with 17 digits). Run it under each kernel and ``diff``
the logs (each line is written as it comes, so that the prefixes of runs stopped early compare
too; the last line is the process's CPU seconds); the first line that differs names the first
step whose result depends on the kernel::

    OPENBLAS_CORETYPE=Prescott python docs/research/2026-11-28-blas-independent-descent.py 5 /tmp/p.log
    OPENBLAS_CORETYPE=Haswell python docs/research/2026-11-28-blas-independent-descent.py 5 /tmp/h.log
    diff /tmp/p.log /tmp/h.log | head

Arguments: a paper case (``5``, ``Ref``, ``9``) or ``t,m,rows,f`` (one storey), the log file, and
optionally ``KEY=VALUE`` tuning knobs (``selection=proximal``).
"""

from __future__ import annotations

import functools
import hashlib
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from threadpoolctl import threadpool_info

import micro
from comparison.domain.cases import case
from comparison.domain.wall import WallSpec
from micro.backends import clarabel as clarabel_backend
from micro.backends import highs, normal_matrix
from micro.nonassociative import proximal
from micro.nonassociative.descent import lowest, states

LOG: list[str] = []
#: the log file, each line written as it comes (a run stopped early can still be compared by prefix)
STREAM: list[Any] = []


def log(line: str) -> None:
    LOG.append(line)
    for fh in STREAM:
        print(line, file=fh, flush=True)


def digest(a: Any) -> str:
    """A short digest of an array (``-`` for ``None``)."""
    if a is None:
        return "-"
    return hashlib.sha1(np.ascontiguousarray(np.asarray(a, dtype=float)).tobytes()).hexdigest()[:12]


def wrap(owner: Any, name: str, show: Callable[..., str]) -> None:
    """Replace ``owner.name`` by a function that logs ``show(result, *args)`` after each call."""
    real = getattr(owner, name)

    @functools.wraps(real)
    def traced(*args: Any, **kwargs: Any) -> Any:
        out = real(*args, **kwargs)
        log(f"{name}: {show(out, *args)}")
        return out

    setattr(owner, name, traced)


def outcome(out: Any, *_: Any) -> str:
    return (f"{out.status.value} it={out.simplex_iterations}+{out.ipm_iterations} "
            f"lam={out.load_factor!r} x={digest(out.x)} y={digest(out.duals)} n={digest(out.n)}")


def main() -> None:
    name, path, *knobs = sys.argv[1:]
    if "," in name:
        t, m, rows, f = (float(v) for v in name.split(","))
        wall = WallSpec.from_paper(t=t, m=m, rows=int(rows), f=f, p=0, storeys=1).to_micro()
    else:
        wall = case(name).spec().to_micro()
    tuning = micro.Tuning(**{k: _value(v) for k, v in (kv.split("=", 1) for kv in knobs)}) if knobs else None
    wrap(highs.PersistentHighsModel, "run", outcome)
    wrap(clarabel_backend.ClarabelStaticBackend, "solve", outcome)
    wrap(normal_matrix.NormalMatrix, "solve", lambda v, *a: digest(v))
    wrap(proximal.Projection, "project", lambda p, *a: f"{p.status} it={p.iterations} n={digest(p.normal)}")
    wrap(states, "refine", lambda x, lp, *a: f"{digest(x)} residual={np.max(np.abs(lp.rhs - lp.A @ x)):.1e}")
    wrap(states, "restricted_columns", lambda r, *a: f"v={digest(a[1])} -> {digest(r)}")
    wrap(lowest, "restricted_columns", lambda r, *a: f"v={digest(a[1])} -> {digest(r)}")
    wrap(lowest.Descent, "settle", lambda s, *a: "-" if s is None else f"{s.load_factor!r} {s.origin}")
    kernels = sorted({str(i.get("architecture")) for i in threadpool_info() if i["internal_api"] == "openblas"})
    with open(path, "w", encoding="utf-8") as fh:
        STREAM.append(fh)
        print(f"# kernels {kernels}", file=fh, flush=True)
        t0 = time.process_time()
        r = micro.solve_nonassociative(wall, tuning=tuning, progress=lambda e: log(
            f"progress: {e.direction} {e.stage} {e.lp} {e.load_factor!r} {e.step!r} {e.algorithm}"))
        cpu = time.process_time() - t0
        for d in r.directions:
            log(f"result {d.direction}: {d.status} {d.load_factor!r}")
        for lo in r.lowest:
            log(f"lowest {lo.direction}: {lo.status} {lo.stop} {lo.load_factor!r} lps={lo.lps} {lo.origin}")
        print(f"# cpu {cpu:.1f} s", file=fh)
    print(f"# kernels {kernels}", f"# cpu {cpu:.1f} s", f"load_factor {r.load_factor!r}",  # noqa: T201
          *LOG[-2 * len(r.directions):], sep="\n")


def _value(text: str) -> Any:
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text.lower(), text)


if __name__ == "__main__":
    main()
