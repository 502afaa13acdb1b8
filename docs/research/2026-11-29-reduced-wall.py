"""Measurements of the research page 2026-11-29-reduced-wall.md: the reduced wall against the wall's own chain.

Usage (from the repository's root, one BLAS/OpenMP thread; CPU seconds of this process)::

    OMP_NUM_THREADS=1 .venv/bin/python docs/research/2026-11-29-reduced-wall.py large  OUT.csv
    OMP_NUM_THREADS=1 .venv/bin/python docs/research/2026-11-29-reduced-wall.py small  OUT.csv
    OMP_NUM_THREADS=1 .venv/bin/python docs/research/2026-11-29-reduced-wall.py shares OUT.csv

``large``: the error map's 12 block walls of square blocks above 1,500 blocks (its 24 walls without a
verdict: a one- and a three-storey wall are the same block wall) and Table 5's Set 10, by the default
(the reduced wall), with the associative LP by ``normal-ipm`` timed in the same process.
``small``: the error map's square-block walls of up to 1,500 blocks, by the reduced wall forced on
(``Tuning(reduce=True)``), against the committed value of the wall's own chain
(``reports/sweeps/errormap.csv``).
``shares``: the associative mechanism's largest rigid part (share of the moving blocks) of the report's
large walls, the quantity that decides where the reduced wall is tried.
"""

from __future__ import annotations

import csv
import sys
import time
from fractions import Fraction
from pathlib import Path

import numpy as np

import micro
from comparison.domain.cases import case
from comparison.domain.wall import WallSpec
from micro.backends.roles import InteriorLP
from micro.nonassociative.fusion import rigid_bodies
from micro.nonassociative.reduced import REDUCE_TOLS, dominant_share

ROOT = Path(__file__).resolve().parents[2]
LARGE = [(2, 60), ("2/3", 36), (1, 48), ("1/2", 36), ("2/5", 36), ("2/3", 48), ("1/2", 48), ("2/3", 60),
         ("2/5", 48), (1, 60), ("1/2", 60), ("2/5", 60)]
SMALL = [(t, o) for t in ("2/5", "1/2", "2/3", 1, 2) for o in (12, 24, 36, 48)]


def square(t: object, rows: int) -> WallSpec:
    """The error map's wall of square blocks (m = 1, f = 0.6, one storey: its three-storey twin is the same)."""
    return WallSpec.from_paper(t=float(Fraction(str(t))), m=1.0, rows=rows, f=0.6)


def committed() -> dict[tuple[str, str], float]:
    """The committed non-associative values of the error map by (t, rows), m = 1, one storey."""
    out = {}
    for r in csv.DictReader((ROOT / "reports" / "sweeps" / "errormap.csv").open()):
        if r["kind"] == "micro-nonassoc" and r["m"] == "1.0" and r["storeys"] == "1" and r["status"] == "converged":
            out[(f"{float(r['t']):.4f}", r["rows"])] = float(r["load_factor"])
    return out


def run(spec: WallSpec, **options: object) -> dict[str, object]:
    wall = spec.to_micro()
    t0 = time.process_time()
    assoc = micro.solve_associative(wall)
    t_assoc = time.process_time() - t0
    t0 = time.process_time()
    r = micro.solve_nonassociative(wall, **options)  # type: ignore[arg-type]
    t_na = time.process_time() - t0
    d = r.directions[0]
    return {"blocks": wall.n_blocks, "assoc_s": round(t_assoc, 3), "nonassoc_s": round(t_na, 2),
            "ratio": round(t_na / t_assoc, 1), "status": r.status, "load_factor": r.load_factor,
            "reduced": bool(getattr(d.sequence, "reduced", False)), "lps": d.iterations,
            "associative": assoc.load_factor}


def main(part: str, out: Path) -> None:
    rows: list[dict[str, object]] = []
    if part == "large":
        for name, spec in [*((f"t={t} o={o}", square(t, o)) for t, o in LARGE), ("Set 10", case("Set 10").spec())]:
            rows.append({"wall": name, **run(spec)})
            print(rows[-1], flush=True)
    elif part == "small":
        old = committed()
        for t, o in SMALL:
            spec = square(t, o)
            row = {"wall": f"t={t} o={o}", **run(spec, tuning=micro.Tuning(reduce=True))}
            row["committed"] = old.get((f"{float(Fraction(str(t))):.4f}", str(o)))
            rows.append(row)
            print(rows[-1], flush=True)
    elif part == "shares":
        for name in ("Ref", "Set 2", "Set 9", "Set 10", "Set 15", "Set 16", "Set 17"):
            wall = case(name).spec().to_micro()
            lp = micro.assemble(wall)
            a = InteriorLP(lp).solve(1)
            body, n = rigid_bodies(lp, np.asarray(a.duals[: lp.n_eq]), REDUCE_TOLS[0], single_band=False)
            rows.append({"wall": name, "blocks": wall.n_blocks, "bodies": n, "moving": int((body >= 0).sum()),
                         "share": round(dominant_share(body), 3)})
            print(rows[-1], flush=True)
    else:
        raise SystemExit(f"unknown part {part!r}: large, small or shares")
    with out.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(dict.fromkeys(k for r in rows for k in r)))
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main(sys.argv[1], Path(sys.argv[2]))
