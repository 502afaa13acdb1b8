"""The report's headline findings, worded from its results."""

from __future__ import annotations

import math

from comparison.domain.cases import cases_in_table
from comparison.report.computed import Results
from comparison.report.robustness import robustness_table
from comparison.report.tables import delta, published

#: A mechanism band "comes within" a published value when its lower end is at most this much above it.
BAND_CLOSE = 0.02


def _finite(x: float) -> bool:
    return math.isfinite(x)


def rows_finding(res: Results) -> str | None:
    """How λ changes with the number of rows of the same wall, macro against micro."""
    plan = res.plan
    values = plan.sweeps.get("rows", ())
    if len(values) < 2:
        return None
    lo, hi = plan.sweep_spec("rows", values[0]), plan.sweep_spec("rows", values[-1])
    both = [
        m for m in plan.methods if _finite(res.record(lo, m).load_factor) and _finite(res.record(hi, m).load_factor)
    ]
    if not both:
        return None
    m = both[-1]
    return (
        f"* **Number of rows.** From o = {values[0]:.4g} to o = {values[-1]:.4g} rows (the same wall of smaller "
        f"blocks) the macro λ goes from {res.macro[lo].load_factor:.3f} to {res.macro[hi].load_factor:.3f}, the "
        f"{m.column} λ from {res.record(lo, m).load_factor:.3f} to {res.record(hi, m).load_factor:.3f}: the "
        "rigid-block wall loses strength as its blocks get smaller, the macro model hardly does. The paper "
        "validated it on 12-row walls only (Table 7)."
    )


def beyond_table7_finding(res: Results) -> str | None:
    """The macro λ against the micro one on the walls the paper has no micro value for."""
    validation = set(cases_in_table("7"))
    big = []
    for c in res.plan.cases:
        d = delta(res.macro[c.spec()].load_factor, res.best_micro(c.spec()).load_factor)
        if d is not None and c not in validation:
            big.append((c, d))
    if not big:
        return None
    above = [d for _, d in big if d > 0]
    if not above:
        return (
            f"* **Macro against micro beyond Table 7.** The macro λ lies below the micro one on all {len(big)} walls: "
            "not refuted (no lower bound of the collapse load is computed, so not shown safe either)."
        )
    n_na = sum(1 for c, _ in big if _finite(res.record(c.spec(), res.plan.reference).load_factor))
    ref_note = (
        ""
        if n_na == len(big)
        else f" (against the non-associative λ on {n_na} of them, elsewhere against the associative LP, "
        "itself an upper bound of the non-associative λ)"
    )
    rows = [c.rows for c, _ in big]
    return (
        f"* **Macro against micro beyond Table 7.** On the {len(big)} other walls the micro model can build "
        f"({min(rows)}-{max(rows)} rows), the macro λ lies above the micro one (the lowest certified state) on "
        f"{len(above)}, by "
        f"{min(above):+.1f} % to {max(above):+.1f} %"
        + ref_note
        + "; below it, not refuted (no lower bound of the collapse load is computed, so not shown safe either), "
        "only "
        + ", ".join(f"{c.label} ({d:+.1f} %)" for c, d in big if d <= 0)
        + "."
    )


def table7_finding(res: Results) -> str:
    """The micro LPs against Orduña's values on Table 7's walls: the lowest certified state, the
    iterated LP's own value and the bands of its mechanisms."""
    cases = cases_in_table("7")
    devs, iterated, close = [], [], []
    for c in cases:
        pub = published(c, "orduna_micro")
        rec = res.record(c.spec(), res.plan.reference)
        if _finite(rec.load_factor):
            devs.append(100.0 * (rec.load_factor - pub) / pub)
        if _finite(rec.iterated_load_factor):
            iterated.append(100.0 * (rec.iterated_load_factor - pub) / pub)
        band = res.mechanism_band(c.spec())
        if band is not None and band[0] <= pub * (1.0 + BAND_CLOSE):
            close.append(c.label)
    na = (
        f"the lowest certified non-associative state lies {min(devs):+.1f} % to {max(devs):+.1f} % from them on "
        f"the {len(devs)} sets where the iterated LP converged (the iterated LP's own fixed point "
        f"{min(iterated):+.1f} % to {max(iterated):+.1f} %)"
        if devs and iterated
        else "the iterated non-associative LP did not converge"
    )
    return (
        "* **Table 7.** The associative LP lies above Orduña's non-associative values, as friction with "
        f"dilatancy must; {na} (default bond, frictional head joints; `bond_variants` below for the others). "
        "The non-associative solution is not unique: the iterated LP's final mechanism can form at any load "
        f"factor of its band (last column), whose lower end comes within {BAND_CLOSE * 100:g} % of Orduña's "
        f"value on {len(close)} of {len(cases)} sets ({', '.join(close) or 'none'})."
    )


def robustness_finding(res: Results) -> str | None:
    """Which conclusions hold in every bond the suite builds (the robustness table's note)."""
    t = robustness_table(res)
    if t is None:
        return None
    return ("* **Under every bond?** " + t.note.split(" Bonds:")[0]
            + " (`robustness` below: the bottom course starting with a full or a half block, head joints with "
            "or without friction).")


def findings(res: Results) -> str:
    """The headline findings, one bullet each."""
    lines = [rows_finding(res), beyond_table7_finding(res), table7_finding(res), robustness_finding(res)]
    return "\n".join(line for line in lines if line is not None)
