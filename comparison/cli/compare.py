"""``xcheck compare``: the macro model against the micro model on one wall, the verdict and its proof.

Example::

    xcheck compare --rows 12 --t 1 --m 1/2 --f 0.75
    xcheck compare --storeys 5 --rows 150 --t 1 --m 1/3 --f 0.75 --json

The first line states the verdict and its proof (:func:`comparison.domain.verdict_words.verdict_sentence`), the next
ones the numbers. Exit 0 whatever the verdict, 1 when a method failed (the verdict is then only what was
proven, and the lines say what is missing), 2 on bad input.
"""

from __future__ import annotations

import argparse
import json
import math
from typing import TYPE_CHECKING

from comparison.cli.options import (
    COMPILING,
    PLOT_SUFFIXES,
    QUIET,
    SOLVER_COUNT_MAX,
    VERBOSE,
    UsageError,
    add_command,
    add_wall_options,
    check_output_path,
    choice,
    exit_after_outputs,
    in_range,
    int_option,
    wall_from_args,
)
from comparison.cli.state import check_state_path, write_state_file

if TYPE_CHECKING:  # pragma: no cover - typing only
    from comparison.domain.verdict import CompareOptions, Comparison
    from comparison.domain.wall import WallSpec


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``compare`` subcommand."""
    p = add_command(
        sub,
        "compare",
        help="is the macro model safe for this wall? macro against micro, the verdict and its proof",
        description="The macro-block model against rigid-block limit analysis on one wall: the macro load "
        "factor, the associative bound, the non-associative value to quote, and the verdict on the macro "
        "model with its proof ('unsafe' by the associative bound or a certified collapse state, 'not "
        "refuted', or 'safe' only by a closed global search's lower bound).",
    )
    add_wall_options(p)
    g = p.add_argument_group("micro model")
    g.add_argument("--first-course", default="full", metavar="full|half",
                   help="the bottom course starts with a full (default) or a half block")
    g.add_argument("--head-joints", default="frictional", metavar="frictional|frictionless",
                   help="friction on the head joints (default frictional)")
    g.add_argument("--full", action="store_true",
                   help="compute every number: the non-associative solve also when the associative bound "
                   "settles the verdict, and its whole search for the lowest certified state when a certified "
                   "state below the macro lambda already settles it")
    g.add_argument("--lowest", default="on", metavar="on|off",
                   help="the descent to the lowest certified collapse state, the value compared (default on)")
    g.add_argument("--global", dest="global_", action="store_true",
                   help="then the global search by branch and bound: a proven lower bound, the only way to a "
                   "'safe' verdict (a reference tool for walls of a few blocks)")
    g.add_argument("--node-limit", default=None, metavar="N",
                   help="with --global: branch-and-bound nodes per direction, 1..2,147,483,647 (default: 1,600,000 "
                   "over the model's binaries, 20 to 100,000); the budget that decides where the search stops, the "
                   "same answer on every machine")
    g.add_argument("--time-limit", default=None, metavar="SECONDS",
                   help="time limit per LP solve (with --global also of each direction's branch and bound: a "
                   "wall-clock limit, reported as such; default none)")
    g.add_argument("--json", action="store_true", help="print one JSON object (docs/schemas/compare.schema.json)")
    g.add_argument("--plot", default=None, metavar="FILE.png", help="draw the wall and its governing micro mechanism")
    g.add_argument("--state", default=None, metavar="FILE.json",
                   help="write the collapse state compared (the non-associative one; the associative LP's when "
                   "the bound settled the verdict), of the wall as built; `xcheck verify FILE.json` checks it")
    p.set_defaults(handler=run)


def options_from_args(args: argparse.Namespace) -> CompareOptions:
    """The :class:`~comparison.domain.verdict.CompareOptions` the options ask for.

    Raises:
        UsageError: a malformed option, naming it.
    """
    from comparison.domain.verdict import FIRST_COURSES, HEAD_JOINTS, CompareOptions

    first = choice("--first-course", args.first_course, FIRST_COURSES)
    head = choice("--head-joints", args.head_joints, HEAD_JOINTS)
    lowest = choice("--lowest", args.lowest, ("on", "off")) == "on"
    if args.node_limit is not None and not args.global_:
        raise UsageError("--node-limit applies to --global only (the branch and bound's nodes)")
    nodes = None if args.node_limit is None else int_option("--node-limit", args.node_limit, 1, SOLVER_COUNT_MAX)
    time_limit = in_range("--time-limit", args.time_limit, "a positive number of seconds", math.inf)
    return CompareOptions(first_course=first, head_joints=head, full=args.full,  # type: ignore[arg-type]
                          global_=args.global_, lowest=lowest, time_limit=time_limit, node_limit=nodes)


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck compare``."""
    from comparison.domain.verdict import compare
    from macro import kernel

    options = options_from_args(args)
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)  # before the solves, not after
    check_state_path(args)
    spec = wall_from_args(args)
    compiled = kernel.compilations()
    progress = None
    if args.verbosity != QUIET:
        from comparison.cli.solve_progress import SolveProgress
        from comparison.runner.pool import approximate_blocks

        progress = SolveProgress(approximate_blocks(spec))
    try:
        result = compare(spec, options, progress=progress)
    except ValueError as exc:  # a wall a model refuses (too large for the memory, a bond it cannot build)
        raise UsageError(str(exc)) from None
    plot_error, drawn = _plot(result, args.plot) if args.plot is not None else (None, False)
    plotted = drawn and plot_error is None
    state_written, state_error = _state(args, result, spec)
    if args.json:
        doc = result.to_dict()
        doc.update(wall=spec.name or None, paper_parameters=spec.paper_parameters(),
                   plot=args.plot if plotted else None, state=state_written)
        print(json.dumps(doc))
    elif args.verbosity == QUIET:
        print(result.verdict + (f" ({result.proof})" if result.proof else "") if result.verdict else "no verdict")
    else:
        print(format_comparison(result, verbose=args.verbosity >= VERBOSE,
                                compiled=kernel.compilations() > compiled))
        if args.plot is not None and not drawn:
            print(f"  no plot written to {args.plot}: no micro mechanism")
    return exit_after_outputs(result.status == "ok", plot_error, state_error)


def _state(args: argparse.Namespace, c: Comparison, spec: WallSpec) -> tuple[str | None, str | None]:
    """Write ``--state``: the state compared (the non-associative result when it ran, else the associative
    LP's), of the wall as built."""
    if c.nonassociative_result is not None and c.nonassociative_wall is not None:
        return write_state_file(args, c.nonassociative_result, c.nonassociative_wall, spec)
    if c.associative_result is not None and c.associative_wall is not None:
        return write_state_file(args, c.associative_result, c.associative_wall, spec)
    return (None, None) if args.state is None else (None, "--state: no micro state to write")


def format_comparison(c: Comparison, *, verbose: bool = False, compiled: bool = False) -> str:
    """The verdict's sentence, then the numbers, one per line (NaN ones left out, what is missing said);
    ``compiled``: the macro model's compiled kernel was compiled during the run (its first use after an
    install), which its time says."""
    lines = [c.sentence()]
    lines.append(f"  macro model:         lambda = {c.macro_load_factor:.6f} ({c.macro_mechanism or 'failed'})"
                 if math.isfinite(c.macro_load_factor) else "  macro model:         no load factor")
    if math.isfinite(c.associative_load_factor):
        lines.append(f"  associative micro:   lambda = {c.associative_load_factor:.6f} (an upper bound of every "
                     "non-associative collapse load)")
    if math.isfinite(c.micro_load_factor):
        what = ("a certified collapse state below the macro λ, where the search stopped" if c.search_stopped
                else "the lowest certified collapse state" if c.micro_quoted == "lowest certified"
                else "the iterated LP's")
        lines.append(f"  non-associative:     lambda = {c.micro_load_factor:.6f} ({what}; the value compared)")
        band = c.mechanism_band
        states = "" if band is None else f"; its mechanism's collapse states: lambda in [{band[0]:.6f}, {band[1]:.6f}]"
        lines.append(f"  iterated LP:         lambda = {c.iterated_load_factor:.6f}{states}")
        lines.append(f"  difference:          (macro - micro) / micro = {c.difference_percent:+.2f} %")
    loc = c.local_mechanism
    if loc is not None:
        held = loc["held_load_factor"]
        lines.append(f"  local mechanism:     {loc['description']} at lambda = {loc['load_factor']:.6f} "
                     f"({loc['method']} micro): the wall as built's, the value compared")
        lines.append(f"  held wall:           lambda = {held:.6f} with the slivers held to the blocks that carry "
                     "them (another wall, not compared)" if held is not None else
                     f"  held wall:           no value ({loc['message'] or loc['status']})")
    if c.global_status:
        lines.append(f"  global search:       {c.global_status}, proven lower bound {c.global_lower_bound:.6f}")
    lines.extend(f"  note: {d}" for d in c.diagnostics)
    s = c.seconds
    stages = [f"{name} {v:.2f} s" for name, v in (("macro", s.macro), ("associative", s.associative),
                                                    ("non-associative", s.nonassociative)) if math.isfinite(v)]
    if compiled and stages and stages[0].startswith("macro"):
        stages[0] += f" ({COMPILING})"
    lines.append(f"  {c.blocks} blocks; " + ", ".join(stages) + f"; total {s.total:.2f} s")
    if verbose:
        paper = ", ".join(f"{k} = {v:.6g}" for k, v in c.wall.paper_parameters().items()
                          if k != "p_storeys" and v is not None)
        lines.append(f"  paper parameters: {paper}")
    return "\n".join(lines)


def _plot(c: Comparison, path: str) -> tuple[str | None, bool]:
    """Draw the governing micro mechanism (the state compared; the associative one when the non-associative
    solve did not run): ``(why it could not be written, whether it was)``."""
    from comparison.cli.micro import _write_plot
    from comparison.report.mechanisms import storey_marks
    from micro.plot import plot_mechanism, plot_velocities

    marks = storey_marks(c.wall, c.macro_result)
    na = c.nonassociative_result
    title = f"macro λ = {c.macro_load_factor:.4f}: {c.verdict or 'no verdict'}" + (f" ({c.proof})" if c.proof else "")
    if na is not None and na.ok and c.nonassociative_wall is not None:
        nwall = c.nonassociative_wall
        low = na.lowest_state
        state = low.state if low is not None and low.state is not None else na.governing
        direction = low.direction if low is not None else na.direction
        if state.mechanism is None:
            return None, False
        velocities = state.mechanism.velocities
        title += f"\nnon-associative micro λ = {c.micro_load_factor:.4f} ({c.micro_quoted}), {direction}"
        return _write_plot(lambda: plot_velocities(nwall, velocities, path, title=title, direction=direction,
                                                   **marks), path), True
    assoc = c.associative_result
    if assoc is not None and assoc.ok and c.associative_wall is not None:
        awall = c.associative_wall
        title += f"\nassociative micro λ = {c.associative_load_factor:.4f}"
        return _write_plot(lambda: plot_mechanism(awall, assoc, path, title=title, **marks), path), True
    return None, False
