"""Interleaved timing of the associative back ends (docs/research/2026-11-25-associative-default.md).

Every run is a fresh process (``--one WALL CANDIDATE``) that assembles the LP,
builds the back end and solves the live load in +x once (the three walls are
mirror-symmetric, so ``micro.solve_associative`` solves that direction only); it
prints one JSON line: wall and CPU seconds of that work, the load factor, its
error relative to the pinned reference (tests/micro/associative_reference.json),
iterations, status. The driver alternates the candidates (the starting one
rotates every round), walls from small to large, appends every record to
``--out`` as it comes, and ``--summary`` prints the medians.

HiGHS's own new interior point (HiPO, ``solver="hipo"``) needs the
``highspy-extras`` package, whose only release (1.15.1) loads into highspy
1.15.1 only: give a Python with those two installed as ``--hipo-python`` to
measure it, in the same run.

Usage::

    python docs/research/2026-11-25-associative-default.py --out runs.jsonl [--hipo-python PY]
    python docs/research/2026-11-25-associative-default.py --summary runs.jsonl
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "tests" / "micro" / "associative_reference.json"
WALLS = {"1230": "w1230 full frictional", "3630": "w3630 full frictional", "7575": "w7575 full frictional"}
#: Rounds per wall.
ROUNDS = {"1230": 5, "3630": 3, "7575": 3}
#: Candidates: back-end names of make_backend, and HiGHS configurations built here.
CANDIDATES = ("normal-ipm", "clarabel", "highs-ipx", "highs-hipo")
#: Fewer rounds: HiGHS IPX takes minutes on 7,575 blocks (227 s in the issue)
#: and misses the 1e-6 accuracy there anyway.
CAP = {("highs-ipx", "7575"): 1}


def one(wall_key: str, candidate: str) -> dict[str, object]:
    """Assemble, set up and solve one wall with one candidate; the record."""
    import micro
    from comparison.domain.wall import WallSpec
    from micro.backends.highs import HighsBackend

    entry = json.loads(REFERENCE.read_text())["walls"][WALLS[wall_key]]
    ref = entry["directions"]["1"]["load_factor"]
    wall = WallSpec.from_paper(**entry["paper"]).to_micro()
    t0, c0 = time.perf_counter(), time.process_time()
    lp = micro.assemble(wall)
    if candidate.startswith("highs-"):
        backend = HighsBackend(lp, algorithm="ipm")  # IPX, crossover off
        if candidate == "highs-hipo":
            h = backend.model._highs
            assert str(h.setOptionValue("solver", "hipo")).endswith("kOk"), "HiPO unavailable (highspy-extras)"
    else:
        backend = micro.make_backend(lp, candidate)
    out = backend.solve(1)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    lam = out.load_factor
    return {"wall": wall_key, "candidate": candidate, "blocks": wall.n_blocks, "status": str(out.status),
            "seconds": seconds, "cpu": cpu, "load_factor": lam, "reference": ref, "error": (lam - ref) / ref,
            "iterations": out.iterations, "fallback": out.info.get("fallback", ""),
            "residual": out.info.get("primal_residual")}


def drive(out: Path, hipo_python: str | None) -> None:
    """The interleaved run (module docstring)."""
    cands = [c for c in CANDIDATES if c != "highs-hipo" or hipo_python]
    k = 0
    for wall_key, rounds in ROUNDS.items():
        for r in range(rounds):
            order = cands[k % len(cands):] + cands[: k % len(cands)]
            k += 1
            for cand in order:
                if r >= CAP.get((cand, wall_key), rounds):
                    continue
                py = hipo_python if cand == "highs-hipo" and hipo_python else sys.executable
                t0 = time.perf_counter()
                p = subprocess.run([py, __file__, "--one", wall_key, cand], capture_output=True, text=True,
                                   cwd=ROOT, check=False)
                process = time.perf_counter() - t0
                lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
                rec = json.loads(lines[-1]) if lines else {"wall": wall_key, "candidate": cand,
                                                           "status": f"failed: {p.stderr[-300:]}"}
                rec.update(round=r, process=process, load=Path("/proc/loadavg").read_text().split()[0])
                with out.open("a") as f:
                    f.write(json.dumps(rec) + "\n")
                print(json.dumps(rec), flush=True)


def summary(path: Path) -> None:
    """Medians per wall and candidate (markdown)."""
    recs = [json.loads(ln) for ln in path.read_text().splitlines() if ln.strip()]
    print("| blocks | candidate | runs | wall s (median) | CPU s (median) | process s (median) | iterations | "
          "error vs reference | normal-ipm's advantage (wall, CPU) |")
    print("|--:|---|--:|--:|--:|--:|--:|--:|--:|")
    for wall_key in WALLS:
        rows = {c: [r for r in recs if r["wall"] == wall_key and r["candidate"] == c and "seconds" in r]
                for c in CANDIDATES}
        base = rows["normal-ipm"]
        for c, rs in rows.items():
            if not rs:
                continue
            w, cpu = statistics.median(r["seconds"] for r in rs), statistics.median(r["cpu"] for r in rs)
            proc = statistics.median(r["process"] for r in rs)
            errs = sorted({f"{r['error']:+.1e}" for r in rs})
            ratio = ""
            if base and c != "normal-ipm":
                ratio = (f"{w / statistics.median(r['seconds'] for r in base):.1f}x, "
                         f"{cpu / statistics.median(r['cpu'] for r in base):.1f}x")
            its = sorted({r["iterations"] for r in rs})
            print(f"| {wall_key} | {c} | {len(rs)} | {w:.2f} | {cpu:.2f} | {proc:.2f} | "
                  f"{', '.join(map(str, its))} | {', '.join(errs)} | {ratio} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--one", nargs=2, metavar=("WALL", "CANDIDATE"))
    ap.add_argument("--out", type=Path)
    ap.add_argument("--hipo-python")
    ap.add_argument("--summary", type=Path)
    a = ap.parse_args()
    if a.one:
        print(json.dumps(one(*a.one)))
    elif a.summary:
        summary(a.summary)
    else:
        drive(a.out, a.hipo_python)


if __name__ == "__main__":
    main()
