"""The figure of ``docs/speed.md``, "Cost against blocks": each micro computation of the committed error map
against its blocks, with the least-squares power law of each method.

Run from the repository's root (a second):

    python docs/research/2026-11-29-cost-vs-blocks.py

It reads ``reports/sweeps/errormap.csv`` (one point per block wall: a one- and a three-storey wall share
theirs; answered computations only), writes ``docs/figures/cost-vs-blocks.png`` and prints each method's
points and exponent ``k`` of ``seconds ~ blocks^k``.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

ANSWERED = ("optimal", "converged")


def points(rows: list[dict[str, str]], kind: str) -> tuple[np.ndarray, np.ndarray]:
    """Blocks and seconds of the answered computations of ``kind``, one per block wall."""
    seen: dict[tuple[str, ...], dict[str, str]] = {}
    for r in rows:
        if r["kind"] == kind and r["status"] in ANSWERED and r["seconds"] not in ("", "nan"):
            seen.setdefault((r["t"], r["m"], r["rows"], r["f"]), r)
    return (np.array([float(r["blocks"]) for r in seen.values()]),
            np.array([float(r["seconds"]) for r in seen.values()]))


def main() -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with Path("reports/sweeps/errormap.csv").open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    fig, ax = plt.subplots(figsize=(7.2, 4.8))
    for kind, label, colour in (("micro-assoc", "micro-assoc (clarabel)", "C0"),
                                ("micro-nonassoc", "micro-nonassoc (scheme a)", "C1")):
        b, s = points(rows, kind)
        k, c = np.polyfit(np.log(b), np.log(s), 1)
        grid = np.geomspace(b.min(), b.max(), 50)
        ax.loglog(b, s, "o", color=colour, label=f"{label} (fit: seconds ~ blocks^{k:.2f})")
        ax.loglog(grid, np.exp(c) * grid**k, "--", color=colour)
        print(f"{kind}: {len(b)} points, {b.min():.0f}-{b.max():.0f} blocks, k = {k:.3f}")
    ax.set_xlabel("blocks")
    ax.set_ylabel("seconds (as computed)")
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig("docs/figures/cost-vs-blocks.png", dpi=110)


if __name__ == "__main__":
    main()
