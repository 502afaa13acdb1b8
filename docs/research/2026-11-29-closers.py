"""How a course ends when the wall's length is not a whole number of half blocks: closers against cut ends.

Run from the repository's root (about two minutes of CPU on 2 cores):

    python docs/research/2026-11-29-closers.py

It writes

* ``docs/figures/ends-layout.png``: the right end of two walls built both ways;
* ``docs/figures/ends-continuity.png``: lambda (associative and non-associative) against the wall's length in
  half blocks across several whole lengths, cut ends beside closers;
* ``docs/research/2026-11-29-closers.csv``: the numbers of that figure;
* the table of the issue's pairs (a wall a few per cent off a whole length and the whole one) on stdout.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
#: The walls scanned: (label, rows, storeys, m, f, first and last length in half blocks).
SCANS = [
    ("10 rows, m = 0.4, f = 0.6", 10, 1, 0.4, 0.6, 5, 8),
    ("12 rows, m = 1/3, f = 0.75 (Set 12 at 8)", 12, 1, 1 / 3, 0.75, 6, 10),
    ("24 rows, m = 1/4, f = 0.7", 24, 1, 0.25, 0.7, 11, 14),
    ("12 rows, m = 1, f = 0.6", 12, 1, 1.0, 0.6, 22, 25),
]
STEP = 0.125
#: The issue's pairs, and more: (rows, storeys, m, f, t, t of the whole wall beside it).
PAIRS = [
    (10, 1, 0.4, 0.6, 1.3, 4 / 3),
    (10, 1, 0.4, 0.6, 1.36, 4 / 3),
    (20, 1, 0.25, 0.7, 0.75, 10 / 13),
    (24, 2, 1 / 3, 0.65, 1.1, 16 / 15),
    (12, 1, 1 / 3, 0.75, 0.97, 1.0),
    (12, 1, 1.0, 0.6, 1.03, 1.0),
    (8, 1, 0.5, 0.65, 1.55, 1.6),
    (2, 1, 1.0, 0.6, 40 / 31, 4 / 3),
]


def _lambdas(spec, ends: str) -> tuple[float, float, int]:
    import micro

    w = spec.to_micro(ends=ends)
    return micro.solve_associative(w).load_factor, micro.solve_nonassociative(w).load_factor, w.n_blocks


def scan() -> list[dict[str, object]]:
    from comparison.domain.wall import WallSpec

    rows_out = []
    for label, rows, storeys, m, f, lo, hi in SCANS:
        height = rows * storeys * m  # in block lengths (b = m l)
        for x in np.arange(lo, hi + 1e-9, STEP):
            t = height / (0.5 * x)
            spec = WallSpec.from_paper(t=t, m=m, rows=rows * storeys, f=f, storeys=storeys)
            row: dict[str, object] = {"wall": label, "half_blocks": round(float(x), 6), "t": t}
            for ends in ("cut", "closers"):
                a, n, blocks = _lambdas(spec, ends)
                row.update({f"{ends}_associative": a, f"{ends}_nonassociative": n, f"{ends}_blocks": blocks})
            rows_out.append(row)
            print(label, f"{x:.3f}", " ".join(f"{k}={v:.4f}" for k, v in row.items() if k.endswith("ative")),
                  flush=True)
    return rows_out


def plot_continuity(rows: list[dict[str, object]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(SCANS), 2, figsize=(10, 2.6 * len(SCANS)), sharex="row")
    for i, (label, *_rest) in enumerate(SCANS):
        sel = [r for r in rows if r["wall"] == label]
        x = np.array([r["half_blocks"] for r in sel], dtype=float)
        for j, friction in enumerate(("associative", "nonassociative")):
            ax = axes[i, j]
            for ends, style in (("cut", dict(color="tab:red", marker="x", ls=":", label="cut ends")),
                                ("closers", dict(color="tab:blue", marker="o", ms=3, label="closers (default)"))):
                ax.plot(x, [r[f"{ends}_{friction}"] for r in sel], **style)
            for whole in range(int(np.ceil(x.min())), int(np.floor(x.max())) + 1):
                ax.axvline(whole, color="0.85", lw=0.8, zorder=0)
            ax.set_title(f"{label}: {friction}", fontsize=9)
            ax.set_ylabel("λ")
            if i == len(SCANS) - 1:
                ax.set_xlabel("wall length L in half blocks (grey: whole lengths)")
            if i == 0 and j == 0:
                ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def plot_layout(path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    from comparison.domain.wall import WallSpec

    cases = [("t = 1.3, m = 0.4, 10 rows, f = 0.6: L = 6.15 half blocks",
              WallSpec.from_paper(t=1.3, m=0.4, rows=10, f=0.6)),
             ("Set 8 (t = 3, m = 1/3, f = 0.6): L = 13.33 half blocks, top 6 of 60 courses",
              WallSpec.from_paper(t=3.0, m=1 / 3, rows=60, f=0.6, storeys=3))]
    fig, axes = plt.subplots(len(cases), 2, figsize=(10, 5.2))
    for i, (title, spec) in enumerate(cases):
        for j, ends in enumerate(("cut", "closers")):
            w = spec.to_micro(ends=ends)
            ax = axes[i, j]
            top = w.n_courses
            shown = (w.course >= top - 6) & (w.x1 >= w.length - 2.6 * w.block_length)
            for b in np.flatnonzero(shown):
                width = w.x1[b] - w.x0[b]
                thin = width < 0.25 * w.block_length
                ax.add_patch(Rectangle((w.x0[b], w.y0[b]), width, w.y1[b] - w.y0[b], facecolor="tab:red" if thin
                                       else "0.9" if abs(width - w.block_length) < 1e-9 else "tab:blue",
                                       edgecolor="k", lw=0.8, alpha=0.8 if thin else 0.5))
                left = w.length - 2.6 * w.block_length
                if w.x0[b] + width / 2 > left + 0.1 * w.block_length:
                    ax.text(max(w.x0[b], left) / 2 + w.x1[b] / 2, (w.y0[b] + w.y1[b]) / 2,
                            f"{width / w.block_length:.2g}", ha="center", va="center", fontsize=7)
            ax.set_xlim(w.length - 2.6 * w.block_length, w.length + 0.1 * w.block_length)
            ax.set_ylim(w.block_height * (top - 6), w.block_height * top)
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(f"{title}\n{'cut ends' if ends == 'cut' else 'closers (the default)'}", fontsize=8)
    fig.suptitle("The right end of two walls: pieces labelled in blocks (red: a sliver, narrower than a closer; "
                 "blue: a closer or a long last unit; grey: a full block)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def pairs() -> None:
    from comparison.domain.wall import WallSpec

    print("| wall (rows, storeys, m, f) | t | half blocks | cut: assoc / non-assoc | closers: assoc / non-assoc "
          "| whole t | whole: assoc / non-assoc | closers vs whole, non-assoc |")
    print("|---|--:|--:|--:|--:|--:|--:|--:|")
    for rows, storeys, m, f, t, tw in PAIRS:
        spec = WallSpec.from_paper(t=t, m=m, rows=rows, f=f, storeys=storeys)
        whole = WallSpec.from_paper(t=tw, m=m, rows=rows, f=f, storeys=storeys)
        ca, cn, _ = _lambdas(spec, "cut")
        ka, kn, _ = _lambdas(spec, "closers")
        wa, wn, _ = _lambdas(whole, "closers")
        hb = spec.to_micro().half_blocks
        print(f"| {rows}, {storeys}, {m:.4g}, {f:g} | {t:.4g} | {hb:.3f} | {ca:.4f} / {cn:.4f} | {ka:.4f} / {kn:.4f} "
              f"| {tw:.4g} | {wa:.4f} / {wn:.4f} | {100 * (kn / wn - 1):+.1f} % |", flush=True)


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    plot_layout(ROOT / "docs" / "figures" / "ends-layout.png")
    if sys.argv[1:] == ["layout"]:
        sys.exit(0)
    pairs()
    data = scan()
    with (ROOT / "docs" / "research" / "2026-11-29-closers.csv").open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(data[0]))
        writer.writeheader()
        writer.writerows(data)
    plot_continuity(data, ROOT / "docs" / "figures" / "ends-continuity.png")
