"""``xcheck macro``: the macro-block model of one wall."""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence

import macro
from comparison.cli.options import (
    COMPILING,
    QUIET,
    VERBOSE,
    UsageError,
    add_command,
    add_wall_options,
    wall_from_args,
)
from macro import kernel
from macro.checks import TooLarge


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``macro`` subcommand."""
    p = add_command(
        sub,
        "macro",
        help="load factor of the macro-block model (Argiento, Maione & Casapulla 2018)",
        description="Minimise Eq. (10) of the paper over the crack angle and the hinge storey.",
    )
    add_wall_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object on one line")
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Solve and print."""
    spec = wall_from_args(args)
    compiled = kernel.compilations()
    try:
        result = macro.solve(spec.to_macro())
    except TooLarge as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        d = result.to_dict()
        d["paper_parameters"] = spec.paper_parameters()
        print(json.dumps(d))  # one line, as micro --json
        return 0
    if args.verbosity == QUIET:
        print(f"{result.load_factor:.6f}")
        return 0
    print(format_result(result, spec.paper_parameters()["p_storeys"]))
    if args.verbosity >= VERBOSE:
        paper = ", ".join(f"{k} = {v:.6g}" for k, v in spec.paper_parameters().items()
                          if k != "p_storeys" and v is not None)
        why = f" ({COMPILING})" if kernel.compilations() > compiled else ""
        print(f"  paper parameters: {paper}\n  solved in {1e3 * result.solve_seconds:.2f} ms{why}")
    return 0


def format_result(r: macro.MacroResult, p_storeys: Sequence[float]) -> str:
    """A human-readable account of a macro result, Eq. (10) term by term; ``p_storeys``: each storey's
    p = q/(gamma H b) (:meth:`comparison.domain.wall.WallSpec.paper_parameters`)."""
    w = r.wall
    lines = [
        f"macro-block model: {w.storeys} storey(s), rows {list(w.rows)}, L = {w.length:g}, "
        f"block {w.block_length:g} x {w.block_height:g}, f = {w.friction:g}",
        f"  floor loads (storey 1, the top, first): q = {', '.join(f'{q:g}' for q in w.overload)}; "
        f"p = q/(gamma H b) = {', '.join(f'{p:.4g}' for p in p_storeys)}",
        f"  load factor         lambda   = {r.load_factor:.4f}  ({r.mechanism}, status {r.status})",
        f"  Eq. (10) minimum    lambda_r = {r.rocking_load_factor:.4f}",
        f"  Eq. (12) at optimum lambda_s = {r.sliding_load_factor:.4f}",
        f"  rigid bounds        sliding f = {w.friction:.4f}, overturning = {r.overturning_load_factor:.4f}",
        f"  crack angle alpha_c = {r.alpha_c_deg:.2f} deg (tan {r.tan_alpha_c:.4f}), "
        f"alpha_b = {r.alpha_b_deg:.2f} deg, alpha_c/alpha_b = {r.alpha_ratio:.3f}",
        f"  hinge at the base of storey {r.hinge_storey} (1 = top); "
        + ", ".join(f"k={h.hinge_storey}: {h.rocking_load_factor:.4f}" for h in r.hinges),
        "  storey   H_c      n_c      W_A+W_B+W_C+W_D   Q         F_g        F_q",
    ]
    for s in r.storeys:
        weight = s.W_A + s.W_B + s.W_C + s.W_D
        lines.append(
            f"  {s.storey:>6} {s.H_c:8.3f} {s.n_c:8.3f} {weight:14.4g} {s.Q:10.4g} {s.F_g:10.4g} {s.F_q:10.4g}"
        )
    lines.append(
        f"  Eq. (10): ({r.stabilising_moment:.6g} + {r.friction_reduction:.4f} x {r.friction_moment:.6g})"
        f" / {r.overturning_moment:.6g}"
    )
    return "\n".join(lines)
