"""The report's prose: ``REPORT.md`` around the tables, and where the paper and the model differ."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from comparison.cases import MODELS
from comparison.report.tables import Table

#: The order of the tables in ``REPORT.md``.
ORDER = (
    "table7",
    "bond_variants",
    "table8",
    "table9",
    "table5",
    "all_cases",
    "failure_modes",
    "sensitivity",
    "speed_accuracy",
    "histories",
)

DISCREPANCIES = """\
* **Set 1 (f = 0.4).** Eq. (10)'s minimum is 0.519, as published, but it exceeds
  f = 0.4: the whole wall slides on a bed joint first (the paper itself calls f an
  upper bound of the load factor). `load_factor` reports min(λ_r, f) = 0.400 and the
  mechanism `sliding`; `rocking_load_factor` keeps the paper's 0.519.
* **Sets 3-4 (p = 2, 8).** Ours is 0.4 % and 0.2 % below the paper; reading H in
  p = q/(γHb) as the storey height instead of the wall height moves the values by
  less than 0.25 %, so the reading of p does not explain the gap; a different
  treatment of the floor terms in the paper's spreadsheet may. For Set 4 the paper
  finds the hinge at the top storey (λ = 0.576, 0.578, 0.582 from the top); ours gives
  0.5752, 0.5751, 0.5751: all three hinges lie within 2e-4 of each other, and the
  global minimum is at the base.
* **Set 5 (o = 36).** The paper prints 0.513 (-11.9 %), yet concludes that the
  number of rows is "substantially irrelevant"; the faithful model gives 0.588
  (+0.9 % on the reference wall), in line with o = 45 (0.585 both). No single
  parameter change we tried reproduces both 0.513 and 37.42°: most likely a
  transcription error in the table.
* **Sets 7-8 (t = 2, 3).** Ours is 0.7 % and 1.0 % above. Here the crack leaves
  through the side of the wall: Eq. (2) finds the exit with the conventional line
  tan α_c while Table 2 draws parts C and D with tan α_c* (Eq. 9), so the triangle D
  overhangs the wall end by v(1 - e/n). Any treatment of that overhang moves these
  two sets and no other.
* **Sets 15-17 (Table 9).** The faithful model gives 0.61 for the five-storey wall
  of Table 6 (m = 1/3), not 0.47. With m = 1/2 it gives 0.467, 0.465, 0.465, i.e. the
  published 0.47 for all three sets: Table 9 was most likely computed with m = 1/2.
  We keep m = 1/3 as Table 6 states.
"""


def document(
    tables: Mapping[str, Table],
    findings: str,
    figures: Sequence[str],
    mechanisms: Sequence[str],
    meta: Mapping[str, Any],
) -> str:
    """The text of ``REPORT.md``.

    Args:
        tables: the tables by name.
        findings: the headline findings (markdown bullets).
        figures: the file names of the summary figures.
        mechanisms: the file names of the mechanism figures.
        meta: the run's metadata (``quick``, ``methods``, ``python``, ``machine``,
            ``cpus``, ``seconds``, ``computed``, ``cached``).
    """
    body = "\n\n".join(tables[k].markdown() for k in ORDER if k in tables)
    figs = "\n".join(f"![{n}]({n})" for n in figures)
    mech = " ".join(f"[{n}]({n})" for n in mechanisms)
    return f"""# Macro-block against rigid-block limit analysis: validation report

Argiento, Maione & Casapulla (2018), *Formulating the in-plane frictional resistances and
collapse mechanisms for multi-storey masonry block walls*, Frattura ed Integrità Strutturale
46, 226-239, recomputed. Methods: {", ".join(meta["methods"])}.
{"**Quick run: the micro model on the small walls only.**" if meta["quick"] else ""}
Δ % is the first value against the second named. Every number shown is in `report.json`
and in one CSV per table; `n/a` marks a wall the method cannot build or a failed solve.

## Findings

{findings}

## Tables

{body}

## Figures

{figs}

Micro mechanisms with the macro crack drawn over them: {mech}

The iterated LP over 104 small walls, seven settings: [stability.md](stability.md); Table 7 per
scheme, bond phase and head-joint friction: [table7_nonassoc.md](table7_nonassoc.md)
(both by `xcheck stability`).

## Where the paper and the model differ

{DISCREPANCIES}
## Models

{chr(10).join(f"* `{k}`: {v}" for k, v in MODELS.items())}

## Machine and timings

Python {meta["python"]} on {meta["machine"]}, {meta["cpus"]} CPUs. This run: {meta["seconds"]:.1f} s,
{meta["computed"]} computations, {meta["cached"]} read from the result cache (keyed by the
wall, the method and the source of the packages it runs).
"""
