"""Stability study of the iterated non-associative LP (issue 4).

Runs :func:`micro.solve_nonassociative` on a grid of small walls (``t``,
``m``, ``f``, rows, storeys) for several settings (scheme x relaxation) and
summarises: convergence rate, iterations, the spread of the load factor
between settings, and the walls on which each setting fails. Writes
``stability.csv`` (one row per wall and setting), ``stability.md`` (tables)
and ``stability.png`` (chart) to the output folder.
"""

from __future__ import annotations

import csv
import itertools
import math
import os
import statistics
import time
from collections.abc import Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

#: Grid of the study: every valid combination (a length that is not a whole
#: number of half blocks is skipped). 104 walls of 12-294 blocks.
GRID: dict[str, tuple[float, ...]] = {
    "t": (0.5, 0.75, 1.0, 1.5, 2.0),
    "m": (1 / 3, 1 / 2, 1.0),
    "rows": (6, 12),
    "f": (0.6, 0.75),
    "storeys": (1, 2),
}


#: Time budget per run and direction (scheme (b) once spent 190 s on a
#: 294-block wall in fallback steps); a run that spends it is reported as
#: ``max_iterations`` / ``time_budget``.
MAX_SECONDS = 20.0


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

    scheme: str
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
    Setting("a", 1.0, False), Setting("a", 0.6, False), Setting("a", 1.0), Setting("a", 0.6), Setting("a", 0.3),
    Setting("b", 1.0), Setting("b", 0.6),
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
    def label(self) -> str:
        """Short name, e.g. ``t1 m1/3 r12 f0.75 s1``."""
        mm = {1 / 3: "1/3", 1 / 2: "1/2", 1.0: "1"}.get(self.m, f"{self.m:g}")
        return f"t{self.t:g} m{mm} r{self.rows} f{self.f:g} s{self.storeys}"


def grid_walls(grid: dict[str, tuple[float, ...]] | None = None) -> list[WallCase]:
    """The valid walls of ``grid`` (default :data:`GRID`)."""
    from comparison.spec import WallSpec

    g = GRID if grid is None else grid
    out: list[WallCase] = []
    for t, m, rows, f, st in itertools.product(g["t"], g["m"], g["rows"], g["f"], g["storeys"]):
        case = WallCase(float(t), float(m), int(rows), float(f), int(st))
        try:
            WallSpec.from_paper(t=case.t, m=case.m, rows=case.rows, f=case.f, p=0, storeys=case.storeys).to_micro()
        except ValueError:
            continue
        out.append(case)
    return out


def _run_one(args: tuple[WallCase, tuple[Setting, ...], int]) -> list[dict[str, Any]]:
    """All settings on one wall (one worker task)."""
    import micro
    from comparison.spec import WallSpec

    case, settings, max_iterations = args
    wall = WallSpec.from_paper(t=case.t, m=case.m, rows=case.rows, f=case.f, p=0,
                               storeys=case.storeys).to_micro()
    assoc = micro.solve_associative(wall)
    rows: list[dict[str, Any]] = []
    for s in settings:
        t0 = time.perf_counter()
        try:
            r = micro.solve_nonassociative(wall, scheme=s.scheme, relaxation=s.relaxation,  # type: ignore[arg-type]
                                           max_iterations=max_iterations, max_seconds=MAX_SECONDS,
                                           certify=s.certify)
            err = ""
        except Exception as exc:  # noqa: BLE001 - recorded as a failure of the setting
            r, err = None, f"{type(exc).__name__}: {exc}"
        secs = time.perf_counter() - t0
        row: dict[str, Any] = {
            "wall": case.label, "t": case.t, "m": case.m, "rows": case.rows, "f": case.f,
            "storeys": case.storeys, "blocks": wall.n_blocks, "setting": s.label, "scheme": s.scheme,
            "relaxation": s.relaxation, "lambda_assoc": assoc.load_factor, "seconds": secs,
        }
        if r is None:
            row.update(status="solver_failure", stop_reason="exception", load_factor=math.nan,
                       last_load_factor=math.nan, band_lo=math.nan, band_hi=math.nan, mband_lo=math.nan,
                       mband_hi=math.nan, iterations=0,
                       warm_cold=math.nan, coulomb=math.nan, dilatancy=math.nan, fallbacks=0, message=err)
        else:
            band = r.lambda_band or (math.nan, math.nan)
            row.update(status=r.status, stop_reason=r.stop_reason, load_factor=r.load_factor,
                       last_load_factor=r.last_load_factor, band_lo=band[0], band_hi=band[1],
                       mband_lo=(r.mechanism_band or (math.nan, math.nan))[0],
                       mband_hi=(r.mechanism_band or (math.nan, math.nan))[1],
                       iterations=r.total_iterations, warm_cold=r.warm_cold_rel_diff,
                       coulomb=r.coulomb_residual, dilatancy=r.dilatancy_residual,
                       fallbacks=r.to_record().fallback_steps, message=r.message)
        rows.append(row)
    return rows


def run_study(walls: Sequence[WallCase], settings: Sequence[Setting] = SETTINGS, *, processes: int = 2,
              max_iterations: int = 100) -> list[dict[str, Any]]:
    """Run every setting on every wall (``processes`` worker processes)."""
    tasks = [(w, tuple(settings), max_iterations) for w in walls]
    if processes <= 1:
        results = [_run_one(t) for t in tasks]
    else:
        with ProcessPoolExecutor(max_workers=processes) as ex:
            results = list(ex.map(_run_one, tasks, chunksize=1))
    return [row for rows in results for row in rows]


def _val(v: float) -> str:
    return {1 / 3: "1/3", 1 / 2: "1/2"}.get(v, f"{v:g}")


def _fmt(v: float, spec: str = ".4f") -> str:
    return "—" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def summarise(rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Per-setting statistics and per-wall spreads."""
    settings = list(dict.fromkeys(r["setting"] for r in rows))
    walls = list(dict.fromkeys(r["wall"] for r in rows))
    per: dict[str, dict[str, Any]] = {}
    for s in settings:
        rs = [r for r in rows if r["setting"] == s]
        conv = [r for r in rs if r["status"] == "converged"]
        counts = {k: sum(1 for r in rs if r["status"] == k)
                  for k in ("converged", "cycling", "max_iterations", "solver_failure")}
        it = [r["iterations"] for r in conv]
        above = [r for r in rs if math.isfinite(r["last_load_factor"])
                 and r["last_load_factor"] > r["lambda_assoc"] * (1 + 1e-7)]
        per[s] = {
            "n": len(rs), "counts": counts, "rate": len(conv) / len(rs) if rs else math.nan,
            "it_median": statistics.median(it) if it else math.nan, "it_max": max(it) if it else math.nan,
            "sec_median": statistics.median(r["seconds"] for r in rs) if rs else math.nan,
            "sec_max": max((r["seconds"] for r in rs), default=math.nan),
            "warm_cold_max": max((r["warm_cold"] for r in rs if math.isfinite(r["warm_cold"])), default=math.nan),
            "coulomb_max_conv": max((r["coulomb"] for r in conv), default=math.nan),
            "dilatancy_max_conv": max((r["dilatancy"] for r in conv), default=math.nan),
            "failed_walls": [r["wall"] for r in rs if r["status"] != "converged"],
            "above_assoc": [r["wall"] for r in above],
            "ratio_median": statistics.median(r["load_factor"] / r["lambda_assoc"] for r in conv) if conv else math.nan,
            "certified": sum(1 for r in conv if r["stop_reason"] == "certified"),
            "band_median": statistics.median(bands) if (bands := [
                (r["band_hi"] - r["band_lo"]) / r["band_lo"] for r in rs
                if r["status"] == "cycling" and math.isfinite(r["band_lo"]) and r["band_lo"] > 0]) else math.nan,
            "band_max": max(bands) if bands else math.nan,
            "mband_median": statistics.median(mb) if (mb := [
                (r["mband_hi"] - r["mband_lo"]) / r["load_factor"] for r in conv
                if math.isfinite(r["mband_lo"]) and math.isfinite(r["mband_hi"])]) else math.nan,
            "mband_max": max(mb) if mb else math.nan,
        }
    spreads = []
    for w in walls:
        rs = [r for r in rows if r["wall"] == w]
        conv = [r["load_factor"] for r in rs if r["status"] == "converged"]
        last = [r["last_load_factor"] for r in rs if math.isfinite(r["last_load_factor"])]
        spreads.append({
            "wall": w, "blocks": rs[0]["blocks"], "lambda_assoc": rs[0]["lambda_assoc"],
            "n_converged": len(conv),
            "spread_converged": (max(conv) - min(conv)) / min(conv) if len(conv) >= 2 else math.nan,
            "spread_last": (max(last) - min(last)) / min(last) if len(last) >= 2 else math.nan,
            "all_fail": not conv,
        })
    return {"settings": settings, "per": per, "spreads": spreads, "walls": walls}


def write_reports(rows: Sequence[dict[str, Any]], out: Path, *, seconds: float, processes: int) -> dict[str, Path]:
    """Write ``stability.csv``, ``stability.md`` and ``stability.png`` to ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    paths = {"csv": out / "stability.csv", "md": out / "stability.md", "png": out / "stability.png"}
    keys = list(rows[0].keys())
    with paths["csv"].open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow(r)
    s = summarise(rows)
    per, spreads = s["per"], s["spreads"]
    sp_conv = [x["spread_converged"] for x in spreads if math.isfinite(x["spread_converged"])]
    sp_last = [x["spread_last"] for x in spreads if math.isfinite(x["spread_last"])]
    lines = [
        "# Stability of the iterated non-associative LP",
        "",
        f"Generated by `xcheck stability`: {len(s['walls'])} walls x {len(s['settings'])} settings "
        f"= {len(rows)} runs in {seconds:.0f} s on {processes} processes. Grid: "
        + ", ".join(f"{k} in {{{', '.join(_val(v) for v in vals)}}}" for k, vals in GRID.items())
        + " (p = 0; combinations whose length is not a whole number of half blocks skipped). "
        "Setting = scheme/relaxation beta; scheme (a) `|s| <= mu nbar`, scheme (b) line of slope "
        "-alpha through (nbar, mu nbar), alpha halved 0.3 -> 1e-3; start: interior-point associative solution; "
        f"cap 100 LPs and {MAX_SECONDS:g} s per direction. A wall counts as converged only if every direction solved converged. "
        "`plain`: the iterated LP alone, converged only when an LP's own forces satisfy Coulomb. Otherwise, "
        "once lambda has settled (spread <= 1e-3 over 3 iterates), the current LP's mechanism is tested for an "
        "exact non-associative collapse state at its lambda among all force fields (`certified`; "
        "micro.nonassociative.certificate). Mechanism band: the load factors of all collapse states "
        "with the final mechanism.",
        "",
        "## Per setting",
        "",
        "| setting | runs | converged | cycling | max_iterations | solver_failure | rate | LPs median (max) of converged "
        "| seconds median (max) | lambda/lambda_assoc median | max warm/cold diff | max Coulomb residual (converged) "
        "| max dilatancy residual (converged) | of which certified | cycling band (max-min)/min median (max) "
        "| mechanism band (max-min)/lambda median (max) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in s["settings"]:
        p = per[name]
        c = p["counts"]
        lines.append(
            f"| {name} | {p['n']} | {c['converged']} | {c['cycling']} | {c['max_iterations']} | "
            f"{c['solver_failure']} | {p['rate'] * 100:.0f} % | {_fmt(p['it_median'], '.0f')} "
            f"({_fmt(p['it_max'], '.0f')}) | {_fmt(p['sec_median'], '.2f')} ({_fmt(p['sec_max'], '.2f')}) | "
            f"{_fmt(p['ratio_median'], '.4f')} | {_fmt(p['warm_cold_max'], '.1e')} | "
            f"{_fmt(p['coulomb_max_conv'], '.1e')} | {_fmt(p['dilatancy_max_conv'], '.1e')} | {p['certified']} | "
            f"{_fmt(p['band_median'], '.2%')} ({_fmt(p['band_max'], '.2%')}) | "
            f"{_fmt(p['mband_median'], '.2%')} ({_fmt(p['mband_max'], '.2%')}) |"
        )
    lines += [
        "",
        "## Spread of lambda between settings",
        "",
        f"Over the walls where at least two settings converged ({len(sp_conv)} walls): relative spread "
        f"(max - min)/min of the converged load factors: median {_fmt(statistics.median(sp_conv) if sp_conv else math.nan, '.2%')}, "
        f"max {_fmt(max(sp_conv) if sp_conv else math.nan, '.2%')}. Over all walls, spread of the last iterates "
        f"(converged or not): median {_fmt(statistics.median(sp_last) if sp_last else math.nan, '.2%')}, "
        f"max {_fmt(max(sp_last) if sp_last else math.nan, '.2%')}.",
        "",
        f"Walls on which no setting converged: {sum(1 for x in spreads if x['all_fail'])}: "
        + (", ".join(x["wall"] for x in spreads if x["all_fail"]) or "none") + ".",
        "",
        "Final iterates above the associative load factor (should be none for scheme a; scheme b's cohesion "
        "c0 may add ~1e-6): "
        + "; ".join(f"{k}: {len(v['above_assoc'])}" for k, v in per.items()) + ".",
        "",
        "## Walls where each setting does not converge",
        "",
    ]
    by_wall = {r["wall"] + "|" + r["setting"]: r for r in rows}
    for name in s["settings"]:
        fw = per[name]["failed_walls"]
        lines.append(f"- **{name}** ({len(fw)}): " + (", ".join(
            f"{w} ({by_wall[w + '|' + name]['status']}/{by_wall[w + '|' + name]['stop_reason']})" for w in fw)
            or "none"))
    lines += ["", "![stability](stability.png)", ""]
    paths["md"].write_text("\n".join(lines))
    _chart(rows, s, paths["png"])
    return paths


def _chart(rows: Sequence[dict[str, Any]], s: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    settings = s["settings"]
    per = s["per"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    ax = axes[0]
    bottoms = [0.0] * len(settings)
    colours = {"converged": "tab:green", "cycling": "tab:orange", "max_iterations": "tab:red",
               "solver_failure": "black"}
    for status, col in colours.items():
        vals = [per[x]["counts"][status] for x in settings]
        ax.bar(settings, vals, bottom=bottoms, color=col, label=status)
        bottoms = [b + v for b, v in zip(bottoms, vals)]
    ax.set_ylabel("walls")
    ax.set_title("outcome per setting (scheme/relaxation)")
    ax.legend(fontsize=8)
    ax = axes[1]
    data = [[r["iterations"] for r in rows if r["setting"] == x and r["status"] == "converged"] or [0]
            for x in settings]
    ax.boxplot(data, tick_labels=settings)
    ax.set_ylabel("LPs to converge (both directions)")
    ax.set_title("iterations of the converged runs")
    ax = axes[2]
    for x in settings:
        rs = [r for r in rows if r["setting"] == x]
        ax.scatter([r["lambda_assoc"] for r in rs], [r["last_load_factor"] / r["lambda_assoc"] for r in rs],
                   s=10, label=x, alpha=0.7)
    ax.axhline(1.0, color="grey", lw=0.8)
    ax.set_xlabel("lambda associative")
    ax.set_ylabel("last lambda / associative")
    ax.set_title("non-associative / associative")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main_study(out: str | os.PathLike[str] = "reports", *, processes: int = 2, quick: bool = False,
               settings: Iterable[Setting] = SETTINGS) -> dict[str, Path]:
    """Run the study and write the reports (``quick``: 12 walls only, for a smoke test)."""
    walls = grid_walls()
    if quick:
        walls = walls[:: max(1, len(walls) // 12)][:12]
    t0 = time.perf_counter()
    rows = run_study(walls, tuple(settings), processes=processes)
    return write_reports(rows, Path(out), seconds=time.perf_counter() - t0, processes=processes)


# ----------------------------------------------------------- Table 7 variants
#: Table 7 of the paper, micro column (Orduna): set -> (t, m, lambda); single
#: storey, 12 rows, f = 0.75.
TABLE7: dict[int, tuple[float, float, float]] = {
    11: (0.5, 1 / 3, 0.69), 12: (1.0, 1 / 3, 0.68), 13: (1.0, 1 / 2, 0.49), 14: (1.0, 1.0, 0.26),
}
#: (scheme, relaxation, start) compared on Table 7.
TABLE7_SETTINGS = (("a", 0.6, "interior", True), ("a", 1.0, "interior", True), ("a", 1.0, "interior", False),
                   ("b", 0.6, "interior", True), ("a", 0.6, "vertex", True))
#: (first_course, head_joints) variants of the wall.
TABLE7_WALLS = (("full", "frictional"), ("half", "frictional"), ("full", "frictionless"), ("half", "frictionless"))


def table7_variants(out: str | os.PathLike[str] = "reports") -> Path:
    """Table 7 (sets 11-14) per setting, bond phase and head-joint friction;
    writes ``table7_nonassoc.md`` and returns its path. Nothing is fitted:
    every wall is built from the paper's parameters."""
    import micro
    from comparison.spec import WallSpec

    lines = [
        "# Table 7, micro column, non-associative friction",
        "",
        "Generated by `xcheck stability --table7`. Sets 11-14 of the paper (single storey, 12 rows, f = 0.75); "
        "published micro-block values (Orduna) 0.69, 0.68, 0.49, 0.26. Each cell: associative lambda / "
        "non-associative lambda (deviation from the published value, LPs) or `cyc [min, max]` when the sequence "
        "cycles (no converged value), and for a converged scheme (a) run the mechanism band: the load factors of "
        "all collapse states with the final mechanism. Bond phase: `full` = the bottom course starts with a full "
        "block; head joints frictional (mu) or frictionless. `plain`: no certificate (the iterated LP alone).",
        "",
    ]
    for scheme, beta, start, certify in TABLE7_SETTINGS:
        lines += [f"## scheme {scheme}, relaxation {beta:g}, start {start}" + ("" if certify else ", plain"), "",
                  "| wall | set 11 (t 0.5, m 1/3) | set 12 (t 1, m 1/3) | set 13 (t 1, m 1/2) | set 14 (t 1, m 1) |",
                  "|---|---|---|---|---|"]
        for fc, hj in TABLE7_WALLS:
            cells = []
            for t, m, ref in TABLE7.values():
                w = WallSpec.from_paper(t=t, m=m, rows=12, f=0.75, p=0, storeys=1).to_micro(
                    first_course=fc, head_joints=hj)
                assoc = micro.solve_associative(w).load_factor
                r = micro.solve_nonassociative(w, scheme=scheme, relaxation=beta, start=start,  # type: ignore[arg-type]
                                               certify=certify)
                if r.converged:
                    mb = r.mechanism_band
                    cells.append(f"{assoc:.4f} / **{r.load_factor:.4f}** ({(r.load_factor / ref - 1) * 100:+.1f} %, "
                                 f"{r.iterations} LPs" + (f"; band [{mb[0]:.4f}, {mb[1]:.4f}]" if mb else "") + ")")
                elif r.lambda_band is not None:
                    cells.append(f"{assoc:.4f} / cyc [{r.lambda_band[0]:.4f}, {r.lambda_band[1]:.4f}]")
                else:
                    cells.append(f"{assoc:.4f} / {r.status}")
            lines.append(f"| {fc} / {hj} | " + " | ".join(cells) + " |")
        lines.append("")
    path = Path(out) / "table7_nonassoc.md"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines))
    return path
