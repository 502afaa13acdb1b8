"""The report's prose: ``REPORT.md`` around the tables, and where the paper and the model differ."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from math import isfinite
from typing import Any

from comparison.domain.cases import CASES, MODELS, SET4_HINGE_LOAD_FACTORS, case, cases_in_table
from comparison.report.computed import Results
from comparison.report.figures import Figure
from comparison.report.plan import NONASSOC_MAX_BLOCKS, NONASSOC_MAX_BLOCKS_CASES, table9_alternative
from comparison.report.reproduce import how_to_reproduce
from comparison.report.tables import Table, published
from comparison.runner import NONASSOC_MAX_LPS, NONASSOC_RETRY_LPS

#: The order of the tables in ``REPORT.md``.
ORDER = (
    "table7",
    "bond_variants",
    "table8",
    "table9",
    "table5",
    "all_cases",
    "robustness",
    "failure_modes",
    "sensitivity",
    "speed_accuracy",
    "histories",
)


#: The symbols of the report.
GLOSSARY = {
    "λ": "the load factor: the horizontal load, as a fraction of the weight, at which the wall collapses",
    "λ_r": "the macro model's rocking-sliding load factor, the minimum of Eq. (10) over the crack angle and "
    "the hinge storey: the number the paper tabulates",
    "λ_s": "the load factor of Eq. (12) at which the macro-block slides along the crack",
    "macro λ": "min(λ_r, f): no mechanism carries more than f, at which the whole wall slides on a bed joint",
    "α_c": "the angle from the vertical of the macro crack through the hinge (Eq. 10's variable)",
    "α_c*": "the angle of the macro model's stepped crack of Eq. (9), tan α_c* = tan α_c − v/(n b)",
    "α_b": "the angle of the bond's stair, tan α_b = v/b (v the overlap, b the block height)",
    "lowest certified": "the micro value the report quotes: the lowest exact non-associative collapse state the "
    "descent from the iterated LP's fixed point reaches (every state verified: equilibrium, Coulomb with its own "
    "normal forces, no dilatancy); the collapse load is not unique, and the iterated LP's own value (beside it) "
    "can lie higher in its mechanism's band",
    "band": "mechanism band: the range of λ over which the iterated LP's final mechanism admits an exact "
    "non-associative collapse state (one value: the solution is unique); cycling band: the range of the last "
    "λ values of a sequence that did not converge",
    "t, m, o, p, f": "the paper's Table 4 parameters: H/L, b/l, rows, floor load q/(γHb), friction coefficient",
    "Δ %": "the first value named against the second, in percent of the second",
}

#: What every status a table can show means (the report lists those that appear).
STATUS_LEGEND = {
    "optimal": "the LP was solved to optimality and its answer passed the independent re-check "
    "(equilibrium, n ≥ 0, Coulomb to 1e-6 block weights)",
    "converged": "the iterated LP reached an exact non-associative collapse state (equilibrium, Coulomb with "
    "its own normal forces, no dilatancy): its λ is a collapse load",
    "cycling": "the iterated LP's λ repeats or oscillates without an exact state; the cell shows the range of "
    "its last values, and no λ",
    "max_iterations": "the iterated LP stopped without settling, at its cap of LPs "
    f"({NONASSOC_MAX_LPS} per load direction in this report, {NONASSOC_RETRY_LPS} for the proximal sequence run after "
    "a vertex sequence that cycled) or of simplex iterations; the cell shows the range of its last values, "
    "and no λ",
    "solver_failure": "an LP of the iterated sequence failed; no λ",
    "inaccurate": "the back end called its answer optimal but it failed the independent re-check; no λ",
    "time_limit": "the LP back end hit its time limit; no λ",
    "not run": f"the report does not run this method on this wall (the iterated LP on the paper's walls above "
    f"{NONASSOC_MAX_BLOCKS_CASES:,} blocks and on the other walls above {NONASSOC_MAX_BLOCKS:,}: too slow for the "
    "report; for Sets 15-17 see \"Table 9's walls with coarser bonds\" below)",
    "n/a": "no number: the method does not apply to this wall or gave none (the status column or the "
    "table's note says which)",
    "not_applicable": "the micro wall cannot be built (shown as n/a where a λ would be)",
    "–": "no value in this column for this row",
}


def glossary() -> str:
    """The glossary as a markdown list."""
    return "\n".join(f"* **{k}**: {v}." for k, v in GLOSSARY.items())


def status_legend(tables: Mapping[str, Table]) -> str:
    """The statuses that appear in ``tables``, explained (markdown list)."""
    every = [c for t in tables.values() for r in t.rows for c in r]
    cells = {c for c in every if isinstance(c, str)}
    cells |= {"–" for c in every if c is None} | {"n/a" for c in every if isinstance(c, float) and not isfinite(c)}
    said = {c.replace("_", " ") for c in cells}  # a status column says not_run where a λ cell says not run
    shown = [k for k in STATUS_LEGEND if any(c == (w := k.replace("_", " ")) or c.endswith(f"({w})") for c in said)]
    return "\n".join(f"* `{k}`: {STATUS_LEGEND[k]}." for k in shown)


def figure_list(figures: Sequence[Figure], start: int = 1) -> str:
    """Every figure, numbered from ``start``, with its caption."""
    return "\n\n".join(
        f"![Figure {i}]({f.name})\n\n**Figure {i}.** {f.caption}" for i, f in enumerate(figures, start)
    )


def _pct(ours: float, ref: float) -> str:
    return f"{100.0 * (ours - ref) / ref:+.1f}"


def discrepancies(res: Results) -> str:
    """Where the paper and the faithful model differ, with the numbers of this run."""
    macro = {c.case: res.macro[c.spec()] for c in CASES}
    pub = {c.case: published(c, "proposed") for c in CASES if c.value("proposed") is not None}
    c1, c3, c4, c5, c6, c7, c8 = (case(n) for n in ("1", "3", "4", "5", "6", "7", "8"))
    s1, s4, ref = macro["1"], macro["4"], macro["Ref"].rocking_load_factor
    storey = [res.macro[c.spec("storey")].rocking_load_factor / macro[c.case].rocking_load_factor - 1 for c in (c3, c4)]
    hinges = [h.rocking_load_factor for h in s4.hinges]
    base = "the base" if s4.hinge_storey == s4.wall.storeys else f"storey {s4.hinge_storey}"
    t9 = cases_in_table("9")
    alt = [res.macro[table9_alternative(c)].load_factor for c in t9]
    return f"""\
* **Set 1 (f = {c1.f:g}).** Eq. (10)'s minimum is {s1.rocking_load_factor:.3f}, as published, but it exceeds
  f = {c1.f:g}: the whole wall slides on a bed joint first (the paper itself calls f an
  upper bound of the load factor). `load_factor` reports min(λ_r, f) = {s1.load_factor:.3f} and the
  mechanism `{s1.mechanism}`; `rocking_load_factor` keeps the paper's {pub["1"]:.3f}.
* **Sets 3-4 (p = {c3.p:g}, {c4.p:g}).** Ours is {_pct(macro["3"].rocking_load_factor, pub["3"])[1:]} % and \
{_pct(macro["4"].rocking_load_factor, pub["4"])[1:]} % below the paper; reading H in
  p = q/(γHb) as the storey height instead of the wall height moves the values by
  {100 * storey[0]:.2f} % and {100 * storey[1]:.2f} %, so the reading of p does not explain the gap; a different
  treatment of the floor terms in the paper's spreadsheet may. For Set 4 the paper
  finds the hinge at the top storey (λ = {", ".join(f"{x:.3f}" for x in SET4_HINGE_LOAD_FACTORS)} from the top); \
ours gives
  {", ".join(f"{x:.4f}" for x in hinges)}: all three hinges lie within {max(hinges) - min(hinges):.1e} of each other, \
and the
  global minimum is at {base}.
* **Set 5 (o = {c5.rows}).** The paper prints {pub["5"]:.3f} ({_pct(pub["5"], ref)} %), yet concludes that the
  number of rows is "substantially irrelevant"; the faithful model gives {macro["5"].rocking_load_factor:.3f}
  ({_pct(macro["5"].rocking_load_factor, ref)} % on the reference wall), in line with o = {c6.rows} \
({macro["6"].rocking_load_factor:.3f}, paper {pub["6"]:.3f}). No single
  parameter change we tried reproduces both {pub["5"]:.3f} and {published(c5, "proposed", "alpha_c_deg"):.2f}°: \
most likely a
  transcription error in the table.
* **Sets 7-8 (t = {c7.t:g}, {c8.t:g}).** Ours is {_pct(macro["7"].rocking_load_factor, pub["7"])[1:]} % and \
{_pct(macro["8"].rocking_load_factor, pub["8"])[1:]} % above. Here the crack leaves
  through the side of the wall: Eq. (2) finds the exit with the conventional line
  tan α_c while Table 2 draws parts C and D with tan α_c* (Eq. 9), so the triangle D
  overhangs the wall end by v(1 - e/n). Any treatment of that overhang moves these
  two sets and no other.
* **Sets {t9[0].case}-{t9[-1].case} (Table 9).** The faithful model gives {macro[t9[0].case].load_factor:.2f} for \
the five-storey wall
  of Table 6 (m = 1/3), not {pub[t9[0].case]:.2f}. With m = 1/2 it gives {", ".join(f"{x:.3f}" for x in alt)}, \
i.e. the
  published {pub[t9[0].case]:.2f} for all three sets: Table 9 was most likely computed with m = 1/2.
  We keep m = 1/3 as Table 6 states.
"""


def slender_walls(res: Results) -> str:
    """What the paper's model does for a wall one block long, with this run's numbers (``macro.bounds``)."""
    spec = res.plan.slender_spec()
    r = res.macro[spec]
    shortest = min(c.spec().length / c.spec().block_length for c in CASES)
    closest = max(res.macro[c.spec()].rocking_load_factor / res.macro[c.spec()].overturning_load_factor for c in CASES)
    n_c = r.storeys[-1].n_c
    if r.mechanism == "overturning":
        verdict = (
            f"Eq. (10) gives {r.rocking_load_factor:.5f}, above {r.overturning_load_factor:.5f}, the load factor at "
            "which the whole wall overturns as one rigid body about its far corner (L/H without floor loads)"
        )
    else:
        verdict = (
            f"Eq. (10) gives {r.rocking_load_factor:.5f}, just below {r.overturning_load_factor:.5f}, the load factor "
            "at which the whole wall overturns as one rigid body about its far corner (L/H without floor loads); "
            "the wedge left behind can tip it above"
        )
    return f"""Eq. (10) minimises over one family of mechanisms: a crack from the hinge through the wall. In a wall
one block long (the base wall with t = o m = {spec.paper_parameters()["t"]:g}: L = l = {spec.length:g},
H = {spec.height:g}) the crack of Eq. (2) leaves the far side {n_c:g} rows above the hinge, the moving part
is the wall less a small wedge at its base, and part D of the stepped crack (Eq. 9) reaches past the end
of the wall. {verdict}. Overturning is a mechanism the paper's family leaves out: it assumes a crack
inside the wall. The suite keeps Eq. (10)'s minimum as `rocking_load_factor` and reports as the load
factor the least of Eq. (10), sliding (f) and the rigid overturning bound, here
{r.load_factor:.5f} (`{r.mechanism}`). Walls shorter than one block are refused: running bond needs a
whole block in every course, and below half a block the column over the hinge (part A) is wider than
the wall and part B's weight turns negative. The paper's walls are at least {shortest:.1f} blocks long;
on them Eq. (10) is at most {100 * closest:.0f} % of the overturning bound.
"""


def document(
    res: Results,
    tables: Mapping[str, Table],
    findings: str,
    figures: Sequence[Figure],
    meta: Mapping[str, Any],
    first_figure: int = 1,
) -> str:
    """The text of ``REPORT.md`` but for the sections of the committed tables.

    Args:
        res: the results (for the discrepancies with the paper).
        tables: the tables by name.
        findings: the headline findings (markdown bullets).
        figures: every figure with its caption, in the order they are numbered.
        meta: what was run (``quick``, ``methods``); run times, the machine and
            the cache are in ``timings.md`` (:mod:`~comparison.report.timings`).
        first_figure: the number of the first of ``figures`` (:func:`comparison.report.sections.render`).
    """
    body = "\n\n".join(tables[k].markdown() for k in ORDER if k in tables)
    return f"""# Macro-block against rigid-block limit analysis: validation report

Argiento, Maione & Casapulla (2018), *Formulating the in-plane frictional resistances and
collapse mechanisms for multi-storey masonry block walls*, Frattura ed Integrità Strutturale
46, 226-239, recomputed. Methods: {", ".join(meta["methods"])}.
{"**Quick run: the micro model on the small walls only.**" if meta["quick"] else ""}
Δ % is the first value against the second named. Every number shown is in `report.json`
and in one CSV per table. The glossary, the status legend and how to reproduce this report
are at the end.

## Findings

{findings}

## Tables

{body}

## Figures

{figure_list(figures, first_figure)}

The iterated LP over 120 small walls, seven settings: [stability.md](stability.md); Table 7 per
scheme, bond phase and head-joint friction: [table7_nonassoc.md](table7_nonassoc.md)
(both by `xcheck stability`).

## Where the paper and the model differ

{discrepancies(res)}
## Slender walls

{slender_walls(res)}
## Models

{chr(10).join(f"* `{k}`: {v}" for k, v in MODELS.items())}

## Status legend

{status_legend(tables)}

## Glossary

{glossary()}

## How to reproduce

{how_to_reproduce(meta)}
## Run times

Seconds, the machine and what came from the result cache are in [timings.md](timings.md)
(and `timings.csv`, `timings.json`, the speed-accuracy figure): they change from run to run;
nothing else in this report does. Numbers are printed to the digits their method guarantees (seven
significant digits in the CSV tables and `report.json`) and contacts are counted opening or sliding
above the solvers' noise (1e-3 of the largest rate), so that another machine's last-digit differences
(1e-8 relative in the associative λ) do not show, unless a value falls that close to a rounding boundary.
"""
