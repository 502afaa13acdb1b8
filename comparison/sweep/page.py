"""A sweep's validation page: ``NAME.md`` beside its table, with its figures as PNG and numbered captions.

Drawn from the table alone (:func:`~comparison.sweep.table.read_table`; the
metadata ``NAME.json`` beside it, when there, only names the user models'
functions), so a sweep resumed from the cache writes the same page, and the
report's error-map section is this page drawn from its committed sweep
(:mod:`comparison.report.errormap`). What it holds:

* a summary: the walls, the micro computations, and per macro column
  (:mod:`~comparison.sweep.wall_comparisons`) how many walls it lies above the micro
  reference on, by more than 5 % and 10 %, the median and worst
  difference and the worst wall; then the walls by verdict and proof, as
  ``xcheck compare`` gives them (:func:`comparison.domain.proof.judge`): unsafe by
  the associative bound, unsafe by a certified state, not refuted, no verdict;
* the cells that gave no value, counted by method and status and listed
  (the first :data:`LISTED` of each status; the table's ``status`` column
  holds them all), never dropped;
* the error map of each macro column over the grid's axes, the
  macro-against-micro scatter with the 1:1 line, the histogram of the
  differences, the worst walls with their parameters, and the micro
  computations' time against their blocks (:mod:`~comparison.sweep.figures`).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from comparison.sweep import figures
from comparison.sweep.figures import layout
from comparison.sweep.table import read_table
from comparison.sweep.wall_comparisons import (
    AGREEMENT,
    AXES,
    MACRO_KINDS,
    MARGINS,
    SYMBOLS,
    VERDICT_LABELS,
    Wall,
    axis_values,
    columns,
    shown,
    success,
    summary,
    varying,
    walls,
    worst,
)
from comparison.utilities.outputs import write_text

#: Walls listed in the worst-walls table of each macro column.
WORST = 12
#: Cells listed of each status without a value (the rest are counted; the table lists them all).
LISTED = 10
#: The statuses a sweep gives a cell it did not compute, and what each means.
WHY = {
    "not_applicable": "the parameters make no wall",
    "not_run": "above the block limit",
    "refused_memory": "its memory estimate exceeds a worker's",
    "error": "the computation raised",
    "worker_died": "its worker process died",
    "failed": "no value",
    "max_iterations": "the iterated LP's cap of LPs reached",
    "cycling": "the iterated LP cycled",
}


@dataclass(frozen=True)
class Page:
    """A rendered page.

    Attributes:
        text: its Markdown.
        figures: the PNG files it links, in order.
        numbers: its numbers, JSON-ready: ``columns`` (each macro column's
            :func:`~comparison.sweep.wall_comparisons.summary`), ``worst`` (each column's worst walls),
            ``statuses`` (cells by method and status).
        path: the Markdown file written (``None``: rendered as a section of another document).
    """

    text: str
    figures: tuple[Path, ...]
    numbers: dict[str, Any] = field(default_factory=dict)
    path: Path | None = None


def write_page(table: Path, out_dir: Path, name: str) -> Page:
    """Draw the page of the sweep table ``table`` into ``out_dir``: ``name.md`` and ``name-*.png``."""
    meta_path = table.with_suffix(".json")
    meta = _meta(meta_path)
    intro = (f"From the sweep table `{table.name}`"
             + (f" (how it ran: `{meta_path.name}`)" if meta else "") + ".")
    page = render(read_table(table), out_dir, title=f"Validation: {name}", intro=intro, prefix=name,
                  functions=_functions(meta), source=table.name)
    path = out_dir / f"{name}.md"
    write_text(path, page.text)
    return Page(page.text, page.figures, page.numbers, path)


def _meta(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _functions(meta: Mapping[str, Any]) -> dict[str, str]:
    """The user models' functions (``module:function``) by name, from the sweep's metadata."""
    methods = meta.get("grid", {}).get("methods", []) if isinstance(meta.get("grid"), dict) else []
    return {m["name"]: m["function"] for m in methods
            if isinstance(m, dict) and m.get("kind") == "user" and "name" in m and "function" in m}


def render(
    rows: Sequence[Mapping[str, str]],
    out_dir: Path,
    *,
    title: str,
    intro: str,
    prefix: str,
    source: str,
    level: int = 1,
    first_figure: int = 1,
    functions: Mapping[str, str] | None = None,
) -> Page:
    """The page of a sweep table's ``rows``, its figures drawn into ``out_dir`` as ``prefix-*.png``.

    Args:
        rows: the table's rows.
        out_dir: where the figures go.
        title: the page's heading.
        intro: its first paragraph (where the table comes from).
        prefix: the figures' file names start with it.
        source: the table's name in the captions (``errormap.csv``).
        level: the heading's level (2 for a section of the report); the page's own sections one below.
        first_figure: the number of its first figure.
        functions: the user models' ``module:function`` by name, to say what they are.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    ws = walls(rows)
    macro_columns = columns(rows)
    moving = varying(ws)
    _, _, panel_col, panel_rows = layout(ws)
    groups = [*panel_rows, *([panel_col] if panel_col else [])]
    sums = {c: summary(ws, c, groups) for c in macro_columns}
    h1, h2 = "#" * level, "#" * (level + 1)
    lines = [f"{h1} {title}", "", intro + " " + _how(macro_columns, functions or {}), ""]
    lines += [f"{h2} Summary", "", *_overview(rows, ws, moving), ""]
    if macro_columns:
        lines += _summary_table(ws, sums, moving)
    else:
        lines.append("The sweep ran no macro model: there is nothing to compare with the micro values.")
    lines += ["", *_without_value(rows)]
    figs: list[Path] = []

    def figure(path: Path | None, caption: str) -> list[str]:
        if path is None:
            return []
        figs.append(path)
        n = first_figure + len(figs) - 1
        return ["", f"![Figure {n}]({path.name})", "", f"**Figure {n}.** {caption}", ""]

    slug = _slugs(macro_columns)
    for c in macro_columns:
        drawn = figure(figures.error_map(ws, c, out_dir / f"{prefix}-map{slug[c]}.png"), _map_caption(ws, c, source))
        if drawn:
            lines += ["", f"{h2} Error map" + ("" if len(macro_columns) == 1 else f": {c}"), *drawn]
            if groups:
                lines += _group_table(sums[c], groups)
    scatter = figure(figures.scatter(ws, macro_columns, out_dir / f"{prefix}-scatter.png"), _scatter_caption(source))
    if scatter:
        lines += ["", f"{h2} Macro against micro", *scatter]
    hist = figure(figures.histogram(ws, macro_columns, out_dir / f"{prefix}-histogram.png"), _hist_caption(source))
    if hist:
        lines += ["", f"{h2} Distribution of the differences", *hist]
    for c in macro_columns:
        bad = worst(ws, c, WORST)
        if bad:
            lines += ["", f"{h2} Worst walls" + ("" if len(macro_columns) == 1 else f": {c}"), "",
                      *_worst_table(bad, c, moving)]
    lines += _local_section(ws, moving, h2)
    timing = figure(figures.time_against_blocks(rows, out_dir / f"{prefix}-time.png"), _time_caption(source))
    if timing:
        lines += ["", f"{h2} Time against blocks", *timing]
    text = re.sub(r"\n{3,}", "\n\n", "\n".join(lines)).strip() + "\n"
    numbers = {
        "columns": sums,
        "worst": {c: [_wall_numbers(w, c) for w in worst(ws, c, WORST)] for c in macro_columns},
        "statuses": statuses(rows),
    }
    return Page(text, tuple(figs), numbers)


def _how(macro_columns: Sequence[str], functions: Mapping[str, str]) -> str:
    named = [f"`{c}`" + (f" (`{functions[c]}`)" if c in functions else "") for c in macro_columns]
    what = ", ".join(named) if named else "no macro column"
    return (
        f"Macro columns: {what}. Each is compared, wall by wall, with the micro reference: the non-associative "
        "method's value to quote where it converged (the table's `load_factor`: its lowest certified collapse "
        "state where the descent found one; the iterated LP's own value is the `iterated_load_factor` column), "
        "else the associative LP (an upper bound of the non-associative load factor: a macro value above it is "
        f"unsafe for certain). Difference: (λ macro − λ micro) / λ micro; a macro value lies above the reference "
        f"where the difference exceeds {AGREEMENT:.0e}, the solvers' accuracy. The verdict is that of "
        "`xcheck compare`: *unsafe* where the macro value lies above the associative LP (a bound of every "
        "non-associative collapse load) or above a certified collapse state (the lowest certified), *not "
        "refuted* where it lies below every state found (no lower bound is computed, so never *safe*), *no "
        "verdict* where there is no converged non-associative value and the bound does not settle it."
    )


def _overview(rows: Sequence[Mapping[str, str]], ws: Sequence[Wall], moving: Sequence[str]) -> list[str]:
    points = {tuple(r[k] for k in ("t", "m", "rows", "f", "p", "storeys")) for r in rows}
    params = [a for a in moving if a not in ("first_course", "head_joints", "ends")]
    sizes = " × ".join(f"{len(axis_values(ws, a))} {SYMBOLS[a]}" for a in params)
    bonds = {(w.first_course, w.head_joints, w.ends) for w in ws if w.first_course}
    micro = [r for r in rows if r["kind"] not in MACRO_KINDS]
    ran = [r for r in micro if r["status"] not in ("not_applicable", "not_run")]
    valued = sum(success(r["kind"], r["status"]) for r in micro)
    by_method = ", ".join(f"{n} {m}" for m, n in _count(r["method"] for r in micro).items())
    out = [f"* **{len(points)} walls**" + (f" ({sizes})" if sizes else "")
           + (f" in {len(bonds)} bonds each: {len(ws)} bonded walls, each compared on its own"
              if len(bonds) > 1 else "") + "."]
    if micro:
        out.append(f"* **{len(micro)} micro computations** ({by_method}): {len(ran)} run, {valued} with a value, "
                   f"{len(micro) - valued} without (below, by status).")
    cut = {(w.t, w.m, w.rows, w.f, w.p, w.storeys) for w in ws if w.cut}
    if cut:
        ends = sorted({w.ends or "closers" for w in ws if w.cut})
        out.append(f"* **{len(cut)} walls of a length that is not a whole number of half blocks**: their courses "
                   f"end in {' or '.join('closers' if e == 'closers' else 'cut pieces' for e in ends)} "
                   "(docs/micro/walls.md); the worst-walls tables give their length in half blocks.")
    else:
        out.append("* No micro method: the sweep has no micro reference.")
    return out


def _count(items: Any) -> dict[str, int]:
    out: dict[str, int] = {}
    for item in items:
        out[item] = out.get(item, 0) + 1
    return out


def _pct(x: float | None, digits: int = 1) -> str:
    return "–" if x is None or not math.isfinite(x) else f"{100 * x:+.{digits}f} %"


def _share(n: int, of: int) -> str:
    return f"{n} ({100 * n / of:.0f} %)" if of else "0"


def _wall_axes(moving: Sequence[str]) -> list[str]:
    return ["t", "m", "rows", "f", "p", "storeys", *[a for a in ("first_course", "head_joints", "ends") if a in moving]]


def _summary_table(ws: Sequence[Wall], sums: Mapping[str, Any], moving: Sequence[str]) -> list[str]:
    margins = " | ".join(f"above by > {round(100 * m)} %" for m in MARGINS)
    lines = [
        f"| macro column | walls compared | above micro | {margins} | agree within {AGREEMENT:.0e} "
        "| median difference | worst difference | worst wall |",
        "|---" * (7 + len(MARGINS)) + "|",
    ]
    for c, s in sums.items():
        a = s["all"]
        top = worst(ws, c, 1)
        where = top[0].parameters(_wall_axes(moving)) if top else "–"
        above = " | ".join(str(a[f"above_{round(100 * m)}pct"]) for m in MARGINS)
        lines.append(f"| {c} | {a['walls']} | {_share(a['unsafe'], a['walls'])} | {above} | {a['agree']} "
                     f"| {_pct(a['median'])} | {_pct(a['max'])} | {where} |")
    lines.append("")
    for c, s in sums.items():
        na, asc = s["nonassoc"], s["assoc"]
        parts = [f"above the converged non-associative value on {na['unsafe']} of {na['walls']} walls"] * bool(
            na["walls"])
        parts += [f"above the associative LP (where there is no non-associative value) on {asc['unsafe']} of "
                  f"{asc['walls']}"] * bool(asc["walls"])
        if s["no_reference"]:
            parts.append(f"{s['no_reference']} walls without a micro reference or a value of the column")
        if parts:
            lines.append(f"* `{c}`: " + "; ".join(parts) + ".")
    return [*lines, "", *_verdict_table(sums)]


def _verdict_table(sums: Mapping[str, Any]) -> list[str]:
    """The walls of each macro column by verdict and proof."""
    labels = list(dict.fromkeys([*VERDICT_LABELS, *(k for s in sums.values() for k in s["verdicts"])]))
    lines = ["Walls by verdict (what the micro values prove about the macro value):", "",
             "| macro column | " + " | ".join(labels) + " |", "|---" * (len(labels) + 1) + "|"]
    for c, s in sums.items():
        lines.append(f"| {c} | " + " | ".join(str(s["verdicts"].get(label, 0)) for label in labels) + " |")
    return lines


def statuses(rows: Sequence[Mapping[str, str]]) -> dict[str, dict[str, int]]:
    """Cells by method and status, in the table's order."""
    out: dict[str, dict[str, int]] = {}
    for r in rows:
        by = out.setdefault(r["method"], {})
        by[r["status"]] = by.get(r["status"], 0) + 1
    return out


def _without_value(rows: Sequence[Mapping[str, str]]) -> list[str]:
    """The cells without a value, counted by method and status, and listed by status."""
    missing = [r for r in rows if not success(r["kind"], r["status"])]
    counts = statuses(rows)
    every = list(dict.fromkeys(s for by in counts.values() for s in by))
    lines = ["Cells by method and status:", "", "| method | " + " | ".join(f"`{s}`" for s in every) + " |",
             "|---" * (len(every) + 1) + "|"]
    lines += [f"| {m} | " + " | ".join(str(by.get(s, 0)) for s in every) + " |" for m, by in counts.items()]
    lines.append("")
    if not missing:
        return [*lines, "Every cell gave a value."]
    lines.append(f"{len(missing)} cell{'s' * (len(missing) != 1)} gave no value:")
    lines.append("")
    for status, n in _count(r["status"] for r in missing).items():
        listed = [r for r in missing if r["status"] == status][:LISTED]
        why = f" ({WHY[status]})" if status in WHY else ""
        shown_ = "; ".join(f"{r['wall']}, {r['method']}" + (f": {_short(r.get('message', ''))}" if r.get("message")
                                                          and status not in ("not_run",) else "") for r in listed)
        more = f"; and {n - len(listed)} more (the table's `status` column lists them all)" if n > len(listed) else ""
        lines.append(f"* `{status}`{why}: {n} — {shown_}{more}.")
    return lines


def _short(message: str, limit: int = 120) -> str:
    text = " ".join(message.split()).replace("|", "/")
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _slugs(names: Sequence[str]) -> dict[str, str]:
    """A file-name suffix per macro column: none for the first, ``-<name>`` for the others."""
    out: dict[str, str] = {}
    for i, name in enumerate(names):
        slug = "" if i == 0 else "-" + (re.sub(r"[^A-Za-z0-9]+", "-", name).strip("-").lower() or f"{i}")
        while slug in out.values():
            slug += f"-{i}"
        out[name] = slug
    return out


def _group_table(s: Mapping[str, Any], groups: Sequence[str]) -> list[str]:
    if not s["by_group"]:
        return []
    head = ", ".join(SYMBOLS[g] for g in groups)
    lines = [f"| {head} | walls | above | > +10 % | agree | median | worst |", "|---|---|---|---|---|---|---|"]
    for label, g in s["by_group"].items():
        lines.append(f"| {label} | {g['walls']} | {g['unsafe']} | {g['above_10pct']} | {g['agree']} "
                     f"| {_pct(g['median'])} | {_pct(g['max'])} |")
    return lines


def _worst_table(bad: Sequence[Wall], column: str, moving: Sequence[str]) -> list[str]:
    """The worst walls of ``column``: the numbers, the verdict, the macro mechanism, and the command that
    draws both mechanisms of the wall (``xcheck compare ... --plot``: the page is drawn from the table, which
    keeps no velocities)."""
    axes = _wall_axes(moving)
    head = " | ".join(SYMBOLS[a] for a in axes)
    lines = [f"| {head} | blocks | λ {column} | λ micro | reference | difference | verdict | macro mechanism "
             "| its plot |", "|---" * (len(axes) + 8) + "|"]
    for k, w in enumerate(bad, 1):
        values = " | ".join(shown(a, w.value(a)) for a in axes)
        blocks = f"{w.blocks or '–'}" + (f" (L = {w.half_blocks:.4g} half blocks, {w.ends or 'closers'})"
                                          if w.cut else "")
        lines.append(f"| {values} | {blocks} | {w.macro[column]:.4f} | {w.reference:.4f} "
                     f"| {w.reference_kind} | {_pct(w.error(column))} | {w.verdict_label(column)} "
                     f"| {w.mechanism.get(column, '–')} | `{plot_command(w, f'worst-{k}.png')}` |")
    return lines


def plot_command(w: Wall, path: str) -> str:
    """The ``xcheck compare`` command that draws wall ``w``'s governing micro mechanism (and gives its
    verdict) into ``path``."""
    parts = ["xcheck compare", f"--t {shown('t', w.t)}", f"--m {shown('m', w.m)}", f"--rows {w.rows}",
             f"--f {w.f:g}"]
    if w.p:
        parts.append(f"--p {w.p:g}")
    if w.storeys != 1:
        parts.append(f"--storeys {w.storeys}")
    if w.first_course and w.first_course != "full":
        parts.append(f"--first-course {w.first_course}")
    if w.head_joints and w.head_joints != "frictional":
        parts.append(f"--head-joints {w.head_joints}")
    if w.ends and w.ends != "closers":
        parts.append(f"--ends {w.ends}")
    # --full: the non-associative state is drawn, the one whose value the table compares, also where the
    # associative bound settles the verdict
    return " ".join([*parts, "--full", f"--plot {path}"])


def _local_section(ws: Sequence[Wall], moving: Sequence[str], h2: str) -> list[str]:
    """The walls as built that a sliver's local mechanism governs (walls of cut ends): what moves, its λ (the
    value compared), and the held wall's λ beside it (no section when there are none)."""
    local = [w for w in ws if w.local]
    if not local:
        return []
    axes = _wall_axes(moving)
    head = " | ".join(SYMBOLS[a] for a in axes)
    lines = ["", f"{h2} Local mechanisms", "",
             "A sliver governs these walls as built (`ends = \"cut\"`: a piece narrower than a closer tips over "
             "alone, or the block above rocks out over it; docs/micro/walls.md). The comparisons above use the "
             "wall as built; the held wall (the slivers held to the blocks that carry them, another structure: "
             "the table's `held_load_factor`) is shown beside it, never compared.",
             "", f"| {head} | method | what moves | λ as built | λ held wall |", "|---" * (len(axes) + 4) + "|"]
    for w in local:
        values = " | ".join(shown(a, w.value(a)) for a in axes)
        for kind, (what, held) in sorted(w.local.items()):
            built = w.nonassoc if kind == "micro-nonassoc" else w.assoc
            lines.append(f"| {values} | {kind} | {what} | {built:.4f} | {held:.4f} |")
    return lines


def _wall_numbers(w: Wall, column: str) -> dict[str, Any]:
    out: dict[str, Any] = {a: w.value(a) for a in AXES}
    verdict, proof = w.verdict(column)
    out.update(blocks=w.blocks, macro=w.macro[column], reference=w.reference, reference_kind=w.reference_kind,
               error=w.error(column), verdict=verdict, proof=proof)
    return out


def _map_caption(ws: Sequence[Wall], column: str, source: str) -> str:
    across, up, panel_col, panel_rows = layout(ws)
    parts = []
    if across:
        parts.append(f"over {SYMBOLS[across]} (across)" + (f" and {SYMBOLS[up]} (up)" if up else ""))
    panels = [SYMBOLS[a] for a in (*panel_rows, *([panel_col] if panel_col else []))]
    if panels:
        parts.append("one panel per " + " and ".join(panels))
    where = figures.fixed(ws)
    return (
        f"(λ {column} − λ micro)/λ micro in per cent" + (" " + ", ".join(parts) if parts else "")
        + (f"; {where}" if where else "") + ". Red: the macro value above the micro reference (unsafe), blue: "
        "below; the black line: where it turns unsafe. The reference is the converged non-associative value, or "
        "(marked *) the associative LP; hatched grey cells: no micro value. The colour scale ends at the outlier "
        f"fences (the quartiles ± {figures.FENCE_IQR:g} interquartile ranges): a wall beyond them is outlined, its "
        f"number its own. Data: `{source}`."
    )


def _scatter_caption(source: str) -> str:
    return ("Each wall's macro value against its micro reference (filled: the non-associative value, hollow: "
            "the associative LP), one colour per macro column; the solid line is λ macro = λ micro (above it the "
            f"macro value is unsafe), the dotted ones ±10 %. Data: `{source}`.")


def _hist_caption(source: str) -> str:
    return ("The differences (λ macro − λ micro)/λ micro of every wall with a micro reference, in per cent, "
            "one histogram per macro column; right of 0 (shaded) the macro value is unsafe. Walls beyond the outlier "
            f"fences (the quartiles ± {figures.FENCE_IQR:g} interquartile ranges) are drawn in the end bins and "
            f"counted in the legend. Data: `{source}`.")


def _time_caption(source: str) -> str:
    return ("Seconds of each micro computation against its wall's blocks, log-log, one colour per method (every "
            "bond): the time of its computation as the table records it (a record read from the cache keeps "
            f"it); crosses: computations that gave no value. Data: `{source}`.")
