"""Issue 55's first route, measured: a certified state from a guessed mechanism instead of the iterated LP.

Run from the repository's root (about two minutes of CPU on one core):

    python docs/research/2026-11-29-mechanism-start.py [WALL ...]

For each of the paper's walls (default: Table 5's and Table 7's, ``Ref`` and ``1`` .. ``14``) it starts the
descent to the lowest certified state (``micro.nonassociative.descent.lowest``) from three guesses, in the
``+x`` direction, and prints one line per guess:

* ``assoc``: the associative LP's mechanism (Clarabel), its pattern read as the descent reads any
  mechanism, then the descent (the lower end of the pattern's band, the polish, the proposals);
* ``gilbert``: the mechanism of one Gilbert LP at the associative normal forces (``|s| <= mu n_assoc``,
  the iterated LP's first LP, solved cold), then the same descent;
* ``compatible``: a mechanism exactly compatible with the associative force field (the descent's
  mechanism LP), then the polish.

The value each gives is set beside the lowest certified value of the committed report
(``reports/all_cases.csv``).
"""

from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

import numpy as np

WALLS = ("Ref", *(str(k) for k in range(1, 15)))


def committed() -> dict[str, float]:
    """The lowest certified value of each paper wall in the committed report."""
    with Path("reports/all_cases.csv").open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    column = "micro-nonassoc (lowest certified) λ"
    return {r["Case"].removeprefix("Set "): float(r[column]) for r in rows
            if r[column].replace(".", "", 1).isdigit()}


def main(names: list[str]) -> None:
    import micro
    from comparison.domain.cases import case
    from micro.backends.roles import InteriorLP
    from micro.limit_result import DirectionResult
    from micro.mechanism import mechanism_from_duals
    from micro.nonassociative.config import resolve
    from micro.nonassociative.descent.lowest import Descent, lowest_state
    from micro.nonassociative.descent.states import ForceField
    from micro.nonassociative.model import IterationModel, restart

    ref = committed()
    for name in names:
        wall = case(name).spec().to_micro()
        lp, d = micro.assemble(wall), 1
        fs = lp.force_scale
        resolved = resolve(wall.n_blocks)
        assoc = InteriorLP(lp).solve(d)
        assert assoc.n is not None and assoc.s is not None and assoc.duals is not None
        starts = {"assoc": (assoc.n, assoc.s, float(assoc.load_factor), np.asarray(assoc.duals[: lp.n_eq]))}
        model = IterationModel(lp, d, "a", 0.0)
        model.set_capacity(assoc.n, 0.0, 0.0, 0.0)
        out = restart(model.model)
        if out.x is not None and out.duals is not None:
            n1, s1 = model.forces(out.x)
            starts["gilbert"] = (n1, s1, float(model.load_factor(out.x)), np.asarray(out.duals[: lp.n_eq]))
        for guess, (n, s, lam, v) in starts.items():
            t0 = time.process_time()
            start = DirectionResult(direction="+x", status="converged", load_factor=lam, iterations=0, seconds=0.0,
                                    normal=n * fs, shear=s * fs, mechanism=mechanism_from_duals(lp, v, d))
            low = lowest_state(lp, start, resolved, None, proposals=True)
            print(f"{name:4s} {wall.n_blocks:5d} {guess:10s} guess lambda {lam:.7f}: {low.status}, "
                  f"{low.load_factor:.7f} ({low.lps} LPs, {time.process_time() - t0:.1f} s); "
                  f"committed lowest {ref.get(name, float('nan')):.7f}", flush=True)
        # a mechanism exactly compatible with the associative field, then the polish
        t0 = time.process_time()
        mu = np.where(lp.mu > 0, lp.mu, 1.0)
        gp = np.where(lp.mu > 0, (assoc.n + assoc.s / mu) / 2, assoc.n / 2)
        gm = np.where(lp.mu > 0, (assoc.n - assoc.s / mu) / 2, assoc.n / 2)
        field = ForceField(np.concatenate([gp, gm]), assoc.n, assoc.s, float(assoc.load_factor),
                           np.zeros(2 * lp.n_points), None)
        descent = Descent(lp, d, resolved, resolved.options.lowest_budget, None, proposals=True)
        v = descent.mechanisms.compatible(field)
        state = None if v is None else descent.polish(v, "compatible")
        text = "no compatible mechanism" if v is None else "no state" if state is None else f"{state.load_factor:.7f}"
        print(f"{name:4s} {wall.n_blocks:5d} compatible {text} ({descent.lps} LPs, {time.process_time() - t0:.1f} s)",
              flush=True)


if __name__ == "__main__":
    main(sys.argv[1:] or list(WALLS))
