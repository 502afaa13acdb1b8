"""The stability study's summary and files: ``stability.csv``, ``stability.md``, ``stability.png``."""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from comparison.stability.study import GRID, MAX_SIMPLEX_ITERATIONS, StudyRun
from comparison.utilities.outputs import csv_text, write_text
from micro.plot import save_figure

#: The statuses a run of the study can end with (counted per setting), and their colours in the chart.
STATUS_COLOURS = {
    "converged": "tab:green",
    "cycling": "tab:orange",
    "max_iterations": "tab:red",
    "time_limit": "tab:purple",
    "solver_failure": "black",
}


def _val(v: float) -> str:
    return {1 / 3: "1/3", 1 / 2: "1/2"}.get(v, f"{v:g}")


def _fmt(v: float, spec: str = ".4f") -> str:
    return "—" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def summarise(runs: Sequence[StudyRun]) -> dict[str, Any]:
    """Per-setting statistics and per-wall spreads."""
    settings = list(dict.fromkeys(r.setting.label for r in runs))
    walls = list(dict.fromkeys(r.wall.label for r in runs))
    per = {s: _setting_summary([r for r in runs if r.setting.label == s]) for s in settings}
    spreads = [_wall_spread([r for r in runs if r.wall.label == w]) for w in walls]
    return {"settings": settings, "per": per, "spreads": spreads, "walls": walls}


def _setting_summary(rs: Sequence[StudyRun]) -> dict[str, Any]:
    """Counts, LPs, times, residuals and bands of one setting's runs."""
    conv = [r for r in rs if r.converged]
    counts = {k: sum(1 for r in rs if r.status == k) for k in STATUS_COLOURS}
    it = [r.total_iterations for r in conv]
    above = [r for r in rs if math.isfinite(r.last_load_factor) and r.last_load_factor > r.lambda_assoc * (1 + 1e-7)]
    return {
        "n": len(rs),
        "counts": counts,
        "rate": len(conv) / len(rs) if rs else math.nan,
        "it_median": statistics.median(it) if it else math.nan,
        "it_max": max(it) if it else math.nan,
        "sec_median": statistics.median(r.seconds for r in rs) if rs else math.nan,
        "sec_max": max((r.seconds for r in rs), default=math.nan),
        "warm_cold_max": max(
            (
                r.result.warm_cold_rel_diff
                for r in rs
                if r.result is not None and math.isfinite(r.result.warm_cold_rel_diff)
            ),
            default=math.nan,
        ),
        "coulomb_max_conv": max((r.result.coulomb_residual for r in conv if r.result is not None), default=math.nan),
        "dilatancy_max_conv": max(
            (r.result.dilatancy_residual for r in conv if r.result is not None), default=math.nan
        ),
        "failed_walls": [r.wall.label for r in rs if not r.converged],
        "above_assoc": [r.wall.label for r in above],
        "ratio_median": statistics.median(r.load_factor / r.lambda_assoc for r in conv) if conv else math.nan,
        "certified": sum(1 for r in conv if r.stop_reason == "certified"),
        "band_median": statistics.median(bands)
        if (
            bands := [
                (r.band[1] - r.band[0]) / r.band[0]
                for r in rs
                if r.status == "cycling" and math.isfinite(r.band[0]) and r.band[0] > 0
            ]
        )
        else math.nan,
        "band_max": max(bands) if bands else math.nan,
        "mband_median": statistics.median(mb)
        if (
            mb := [
                (r.mechanism_band[1] - r.mechanism_band[0]) / r.load_factor
                for r in conv
                if all(math.isfinite(x) for x in r.mechanism_band)
            ]
        )
        else math.nan,
        "mband_max": max(mb) if mb else math.nan,
    }


def _wall_spread(rs: Sequence[StudyRun]) -> dict[str, Any]:
    """How far the settings' load factors lie apart on one wall."""
    lams = [r.load_factor for r in rs if r.converged]
    last = [r.last_load_factor for r in rs if math.isfinite(r.last_load_factor)]
    return {
        "wall": rs[0].wall.label,
        "blocks": rs[0].blocks,
        "lambda_assoc": rs[0].lambda_assoc,
        "n_converged": len(lams),
        "spread_converged": (max(lams) - min(lams)) / min(lams) if len(lams) >= 2 else math.nan,
        "spread_last": (max(last) - min(last)) / min(last) if len(last) >= 2 else math.nan,
        "all_fail": not lams,
    }


def write_rows(rows: Sequence[Mapping[str, Any]], path: Path) -> None:
    """Write ``rows`` (dicts with the same keys, in order) as a CSV table with a header."""
    names = list(rows[0])
    write_text(path, csv_text([names, *([row.get(k, "") for k in names] for row in rows)]))


def write_reports(runs: Sequence[StudyRun], out: Path, *, seconds: float, processes: int) -> dict[str, Path]:
    """Write ``stability.csv``, ``stability.md`` and ``stability.png`` to ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    paths = {"csv": out / "stability.csv", "md": out / "stability.md", "png": out / "stability.png"}
    rows = [r.row() for r in runs]
    write_rows(rows, paths["csv"])
    s = summarise(runs)
    lines = _intro(s, len(rows), seconds, processes) + _per_setting(s) + _spread(s) + _failures(runs, s)
    write_text(paths["md"], "\n".join(lines))
    _chart(runs, s, paths["png"])
    return paths


def _intro(s: dict[str, Any], n_runs: int, seconds: float, processes: int) -> list[str]:
    return [
        "# Stability of the iterated non-associative LP",
        "",
        f"Generated by `xcheck stability`: {len(s['walls'])} walls x {len(s['settings'])} settings "
        f"= {n_runs} runs in {seconds:.0f} s on {processes} processes. Grid: "
        + ", ".join(f"{k} in {{{', '.join(_val(v) for v in vals)}}}" for k, vals in GRID.items())
        + " (p = 0; a length that is not a whole number of half blocks ends its courses in closers, the "
        "builder's default). "
        "Setting = scheme/relaxation beta; scheme (a) `|s| <= mu nbar`, scheme (b) line of slope "
        "-alpha through (nbar, mu nbar), alpha halved 0.3 -> 1e-3; start: interior-point associative solution; "
        f"cap 100 LPs and {MAX_SIMPLEX_ITERATIONS:,} simplex iterations per direction; no clock (a stalled HiGHS "
        "run is interrupted by a count, `micro.backends.highs_runs.StallGuard`, and recovered like a failed LP). "
        "A wall counts as converged only if every direction solved converged. "
        "`plain`: the iterated LP alone, converged only when an LP's own forces satisfy Coulomb. Otherwise, "
        "once lambda has settled (spread <= 1e-3 over 3 iterates), the current LP's mechanism is tested for an "
        "exact non-associative collapse state at its lambda among all force fields (`certified`; "
        "micro.nonassociative.certificate). Mechanism band: the load factors of all collapse states "
        "with the final mechanism.",
        "",
    ]


def _per_setting(s: dict[str, Any]) -> list[str]:
    per = s["per"]
    lines = [
        "## Per setting",
        "",
        "| setting | runs | converged | cycling | max_iterations | time_limit | solver_failure | rate "
        "| LPs median (max) of converged "
        "| seconds median (max) | lambda/lambda_assoc median | max warm/cold diff | max Coulomb residual (converged) "
        "| max dilatancy residual (converged) | of which certified | cycling band (max-min)/min median (max) "
        "| mechanism band (max-min)/lambda median (max) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in s["settings"]:
        p = per[name]
        c = p["counts"]
        lines.append(
            f"| {name} | {p['n']} | {c['converged']} | {c['cycling']} | {c['max_iterations']} | {c['time_limit']} | "
            f"{c['solver_failure']} | {p['rate'] * 100:.0f} % | {_fmt(p['it_median'], '.0f')} "
            f"({_fmt(p['it_max'], '.0f')}) | {_fmt(p['sec_median'], '.2f')} ({_fmt(p['sec_max'], '.2f')}) | "
            f"{_fmt(p['ratio_median'], '.4f')} | {_fmt(p['warm_cold_max'], '.1e')} | "
            f"{_fmt(p['coulomb_max_conv'], '.1e')} | {_fmt(p['dilatancy_max_conv'], '.1e')} | {p['certified']} | "
            f"{_fmt(p['band_median'], '.2%')} ({_fmt(p['band_max'], '.2%')}) | "
            f"{_fmt(p['mband_median'], '.2%')} ({_fmt(p['mband_max'], '.2%')}) |"
        )
    return lines


def _spread(s: dict[str, Any]) -> list[str]:
    per, spreads = s["per"], s["spreads"]
    sp_conv = [x["spread_converged"] for x in spreads if math.isfinite(x["spread_converged"])]
    sp_last = [x["spread_last"] for x in spreads if math.isfinite(x["spread_last"])]
    return [
        "",
        "## Spread of lambda between settings",
        "",
        f"Over the walls where at least two settings converged ({len(sp_conv)} walls): relative spread "
        "(max - min)/min of the converged load factors: "
        f"median {_fmt(statistics.median(sp_conv) if sp_conv else math.nan, '.2%')}, "
        f"max {_fmt(max(sp_conv) if sp_conv else math.nan, '.2%')}. Over all walls, spread of the last iterates "
        f"(converged or not): median {_fmt(statistics.median(sp_last) if sp_last else math.nan, '.2%')}, "
        f"max {_fmt(max(sp_last) if sp_last else math.nan, '.2%')}.",
        "",
        f"Walls on which no setting converged: {sum(1 for x in spreads if x['all_fail'])}: "
        + (", ".join(x["wall"] for x in spreads if x["all_fail"]) or "none")
        + ".",
        "",
        "Final iterates above the associative load factor (should be none for scheme a; scheme b's cohesion "
        "c0 may add ~1e-6): " + "; ".join(f"{k}: {len(v['above_assoc'])}" for k, v in per.items()) + ".",
        "",
        "## Walls where each setting does not converge",
        "",
    ]


def _failures(runs: Sequence[StudyRun], s: dict[str, Any]) -> list[str]:
    lines = []
    by_wall = {(r.wall.label, r.setting.label): r for r in runs}
    for name in s["settings"]:
        fw = s["per"][name]["failed_walls"]
        lines.append(
            f"- **{name}** ({len(fw)}): "
            + (", ".join(f"{w} ({by_wall[w, name].status}/{by_wall[w, name].stop_reason})" for w in fw) or "none")
        )
    return [*lines, "", "![stability](stability.png)", ""]


def _chart(runs: Sequence[StudyRun], s: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    settings = s["settings"]
    per = s["per"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    ax = axes[0]
    bottoms = [0.0] * len(settings)
    for status, col in STATUS_COLOURS.items():
        vals = [per[x]["counts"][status] for x in settings]
        ax.bar(settings, vals, bottom=bottoms, color=col, label=status)
        bottoms = [b + v for b, v in zip(bottoms, vals, strict=True)]
    ax.set_ylabel("walls")
    ax.set_title("outcome per setting (scheme/relaxation)")
    ax.legend(fontsize=8)
    ax = axes[1]
    data = [[r.total_iterations for r in runs if r.setting.label == x and r.converged] or [0] for x in settings]
    ax.boxplot(data, tick_labels=settings)
    ax.set_ylabel("LPs to converge (both directions)")
    ax.set_title("iterations of the converged runs")
    ax = axes[2]
    for x in settings:
        rs = [r for r in runs if r.setting.label == x]
        ax.scatter(
            [r.lambda_assoc for r in rs], [r.last_load_factor / r.lambda_assoc for r in rs], s=10, label=x, alpha=0.7
        )
    ax.axhline(1.0, color="grey", lw=0.8)
    ax.set_xlabel("lambda associative")
    ax.set_ylabel("last lambda / associative")
    ax.set_title("non-associative / associative")
    ax.legend(fontsize=8)
    fig.tight_layout()
    try:
        save_figure(fig, path, dpi=110)  # whole or not at all
    finally:
        plt.close(fig)
