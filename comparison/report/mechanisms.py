"""The mechanism figures: each case's micro mechanism with the macro crack drawn over it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import macro
from comparison.domain.wall import WallSpec
from comparison.report.computed import Results
from comparison.report.figures import Figure, pyplot, save_figure
from comparison.report.tables import mechanism_record


def mechanism_figures(res: Results, out: Path) -> list[Figure]:
    """One figure per case with a micro mechanism: the blocks displaced by their velocities, the load arrow,
    and the macro model's cracks (α_c and α_c*)."""
    from micro.plot import draw_mechanism

    plt = pyplot()
    figures = []
    for c in res.plan.cases:
        spec = c.spec()
        rec = mechanism_record(res, c)
        mech = res.mechanisms.get((spec, rec.method))
        if mech is None:
            continue
        wall = spec.to_micro()
        r = res.macro[spec]
        aspect = min(1.4, max(0.45, wall.height / wall.length))
        fig, ax = plt.subplots(figsize=(7.5, 5.2 * aspect + 1.4), dpi=100, layout="constrained")
        amplification = draw_mechanism(ax, wall, mech.velocities, fig=fig, direction=mech.direction,
                                       **storey_marks(spec, r))  # fmt: skip
        _draw_macro_crack(ax, r, mech.direction)
        fig.suptitle(f"{c.label}: {rec.method.column} λ = {rec.load_factor:.3f}, macro λ = {r.load_factor:.3f}",
                     fontsize=9)  # fmt: skip
        ax.legend(fontsize=7, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, frameon=False)
        name = f"mechanism_{c.case.lower()}.png"
        save_figure(fig, out / name)
        which = "" if rec.method == res.plan.reference else _why_not(res, c)
        na = rec.nonassoc
        lowest = na is not None and na.quoted == "lowest certified"
        what = f"{'lowest certified collapse state' if lowest else 'collapse mechanism'} of the {rec.method.label}"
        figures.append(
            Figure(
                name,
                f"{c.label} (t = {c.t:g}, m = {c.m:.3g}, o = {c.rows}, p = {c.p:g}, f = {c.f:g}, {c.storeys} "
                f"storey{'s' if c.storeys > 1 else ''}): the {what}{which} "
                f"for the live load in {mech.direction} (arrow), λ = {rec.load_factor:.4f}. Blocks are drawn "
                f"displaced by their virtual velocities × {amplification:.3g} and coloured by their speed relative to "
                f"the fastest block, the wall "
                f"undeformed in grey; axes in block heights{_floors_said(spec)}. Red: the macro model's crack "
                f"through the hinge (α_c = {r.alpha_c_deg:.1f}°, dashed) and its stepped crack "
                f"(α_c* = {r.alpha_c_star_deg:.1f}°), the hinge (circle) at the base of storey {r.hinge_storey}, "
                f"macro λ = {r.load_factor:.4f}.",
            )
        )
    return figures


def storey_marks(spec: WallSpec, r: macro.MacroResult | None = None) -> dict[str, Any]:
    """What a mechanism plot of ``spec`` marks, as keyword arguments of :func:`micro.plot.draw_mechanism`:
    the floors between its storeys and the macro model's hinge (``r``'s, else solved here; no hinge when the
    macro model gives none)."""
    marks: dict[str, Any] = {"floors": [spec.storey_base(k) for k in range(1, len(spec.storeys))]}
    if r is None:
        try:
            r = macro.solve(spec.to_macro())
        except ValueError:  # a wall the macro model refuses (TooLarge is one): no hinge to mark
            return marks
    if r.status == "optimal":
        marks |= {"hinge": spec.storey_base(r.hinge_storey),
                  "hinge_label": f"macro hinge: base of storey {r.hinge_storey}"}  # fmt: skip
    return marks


def _floors_said(spec: WallSpec) -> str:
    """The caption's words for the floor lines (none on a one-storey wall)."""
    return "; dashed: the floors, the storeys numbered from the top at the right" if len(spec.storeys) > 1 else ""


def _why_not(res: Results, case: Any) -> str:
    """Why the caption shows another method's mechanism than the reference's: not run, or no state."""
    ref = res.record(case.spec(), res.plan.reference)
    kind = res.plan.reference.column
    if ref.status == "not_run":
        return f" (the {kind}: not run on this wall, see the status legend)"
    return f" (the {kind} ended `{ref.status}`: no collapse state)"


def _draw_macro_crack(ax: Any, r: macro.MacroResult, direction: str) -> None:
    """The macro crack through the hinge (α_c) and the stepped crack (α_c*), in the micro wall's frame,
    in block heights."""
    w = r.wall
    b = w.block_height
    base = sum(w.rows[r.hinge_storey :])
    height = sum(w.rows[: r.hinge_storey])
    L, v = w.length / b, w.overlap / b
    lines = {
        "macro crack through the hinge (α_c)": [0.0, r.tan_alpha_c * height],
        "macro stepped crack (α_c*)": [v, v + r.tan_alpha_c_star * height],
    }
    for (label, xs), style in zip(lines.items(), ("--", "-"), strict=True):
        xs_c = [min(x, L) for x in xs]
        top = height * (xs_c[1] - xs[0]) / (xs[1] - xs[0]) if xs[1] != xs[0] else height
        if direction == "+x":
            xs_c = [L - x for x in xs_c]
        ax.plot(xs_c, [base, base + top], style, color="red", lw=1.5, label=label)
