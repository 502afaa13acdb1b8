"""``xcheck micro``: rigid-block limit analysis of the wall (micro model).

Example::

    xcheck micro --t 1 --m 1/3 --rows 12 --f 0.75 --friction associative --solver clarabel --json
    xcheck micro --t 1 --m 1/3 --rows 12 --f 0.75 --friction nonassociative --json
    xcheck micro --t 1 --m 1/3 --rows 12 --f 0.75 --friction nonassociative --tuning scheme=b --tuning relaxation=0.5
    xcheck micro --t 2 --m 1/3 --rows 6 --f 0.6 --friction nonassociative --global --time-limit 60 --json
    xcheck micro --t 1 --m 1/2 --rows 12 --f 0.75 --friction nonassociative --state set13.json
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover - typing only
    from comparison.domain.wall import WallSpec
    from comparison.domain.wall_mechanism import WallMechanism
    from micro import BlockWall
    from micro.nonassociative import LPProgress

from comparison.cli.micro_words import print_associative, print_cut, print_local, print_nonassociative
from comparison.cli.options import (
    PLOT_SUFFIXES,
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
from comparison.cli.state import add_state_option, check_state_path, write_state_file
from comparison.cli.tuning import parse_tuning

#: Friction laws accepted by ``--friction``.
FRICTION_LAWS = ("associative", "nonassociative")
#: ``--lowest``: the value of ``micro.NonAssociativeOptions.lowest`` for each choice.
LOWEST_CHOICES: dict[str, bool] = {"on": True, "off": False}


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``micro`` subcommand."""
    from micro import SOLVERS

    p = add_command(
        subparsers,
        "micro",
        help="rigid-block limit analysis (LP) of the wall built block by block",
        description="Collapse load factor of the wall built block by block in running bond, "
        "by rigid-block limit analysis solved as a linear program.",
    )
    add_wall_options(p)
    g = p.add_argument_group("micro model")
    g.add_argument(
        "--friction",
        default="associative",
        metavar="LAW",
        help="friction law: associative (default) or nonassociative (the iterated LP; -v streams its LPs)",
    )
    g.add_argument(
        "--solver",
        default=None,
        metavar="NAME",
        help=f"LP back end of --friction associative: {', '.join(SOLVERS)} (default: micro.solve_associative's)",
    )
    g.add_argument(
        "--first-course",
        default="full",
        metavar="full|half",
        help="the bottom course starts with a full (default) or a half block",
    )
    g.add_argument(
        "--head-joints",
        default="frictional",
        metavar="frictional|frictionless",
        help="friction on the head joints (default frictional)",
    )
    g.add_argument("--time-limit", default=None, metavar="SECONDS",
                   help="time limit per LP solve (with --global also of each direction's branch and bound: a "
                   "wall-clock limit, reported as such; default none)")
    g.add_argument("--json", action="store_true", help="print one JSON object")
    g.add_argument("--plot", default=None, metavar="FILE.png", help="draw the wall and its collapse mechanism")
    add_state_option(g)
    # ---- non-associative friction: the report's method; research knobs only through --tuning
    na = p.add_argument_group("non-associative friction (--friction nonassociative; the report's method)")
    na.add_argument("--max-iterations", default=None, metavar="N",
                    help="cap on the LPs of a direction's first sequence, 2..2,147,483,647 (default: the library's, "
                    "100)")
    na.add_argument(
        "--lowest",
        default=None,
        metavar="on|off|N",
        help="the descent to the lowest certified collapse state, the value printed first (lowest_load_factor): "
        "on (default, at most 100 LPs per direction), N (on, at most N LPs per direction; one that spends them "
        "prints the lowest state found so far and says so; N in 1..2,147,483,647) or off (the iterated LP's "
        "state only)",
    )
    na.add_argument("--no-lowest", dest="lowest", action="store_const", const="off", help=argparse.SUPPRESS)
    na.add_argument(
        "--global",
        dest="global_",
        action="store_true",
        help="then search for the global minimum by branch and bound (HiGHS MIP), started from the lowest "
        "state: a proven lower bound and the gap (global_load_factor, global_lower_bound, global_gap, "
        "global_status); a reference tool for walls of a few blocks",
    )
    na.add_argument(
        "--node-limit",
        default=None,
        metavar="N",
        help="with --global: branch-and-bound nodes per direction, 1..2,147,483,647 (default: 1,600,000 over the "
        "model's binaries, 20 to 100,000: 20,000 on ten blocks); the budget that decides where the search stops, "
        "the same answer on every machine, unlike --time-limit",
    )
    na.add_argument(
        "--tuning",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="change a research knob of the method (repeatable; e.g. scheme=b, selection=vertex, relaxation=0.5, "
        "certify=false, fuse=true; the knobs: micro.Tuning, docs/micro/tuning.md)",
    )
    p.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck micro``."""
    import micro
    from micro import SOLVERS

    choice("--friction", args.friction, FRICTION_LAWS)
    if args.solver is not None:
        choice("--solver", args.solver, SOLVERS)
    choice("--first-course", args.first_course, ("full", "half"))
    choice("--head-joints", args.head_joints, ("frictional", "frictionless"))
    time_limit = in_range("--time-limit", args.time_limit, "a positive number of seconds", math.inf)
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)  # before the solves, not after
    check_state_path(args)
    spec = wall_from_args(args)
    try:
        wall = spec.to_micro(first_course=args.first_course, head_joints=args.head_joints)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    _options_apply(args)
    if args.friction == "nonassociative":
        return _run_nonassociative(args, spec, wall, time_limit)
    solver = {} if args.solver is None else {"solver": args.solver}  # else the library's default back end
    if args.solver is not None and (missing := micro.backends.missing_extra(args.solver)):  # an optional extra
        raise UsageError(missing)
    result = micro.solve_associative(wall, time_limit=time_limit, **solver)
    own = _wall_mechanism(wall, result, lambda w: micro.solve_associative(w, time_limit=time_limit, **solver))
    plot_error = None
    if args.plot is not None and result.ok:
        from comparison.report.mechanisms import storey_marks
        from micro.plot import plot_mechanism

        plot_error = _write_plot(lambda: plot_mechanism(wall, result, args.plot, **storey_marks(spec)), args.plot)
    state_written, state_error = write_state_file(args, result, wall, spec)
    if args.json:
        print(_json({**result.summary(), **own.to_dict()}, args, spec, wall,
                    plotted=result.ok and plot_error is None, state=state_written))
    else:
        print_associative(result, args.verbosity)
        print_local(own, args.verbosity)
        print_cut(wall, args.verbosity)
    return exit_after_outputs(result.ok, plot_error, state_error)


def _options_apply(args: argparse.Namespace) -> None:
    """Refuse the options that do not apply to the friction law and mode chosen (they were ignored silently).

    Raises:
        UsageError: naming the options.
    """
    if args.friction != "nonassociative":
        given = [o for o, on in (("--max-iterations", args.max_iterations is not None),
                                 ("--lowest", args.lowest is not None), ("--global", args.global_),
                                 ("--node-limit", args.node_limit is not None), ("--tuning", bool(args.tuning))) if on]
        if given:
            raise UsageError(f"{', '.join(given)} appl{'ies' if len(given) == 1 else 'y'} to --friction "
                             "nonassociative only")
    elif args.node_limit is not None and not args.global_:
        raise UsageError("--node-limit applies to --global only (the branch and bound's nodes)")


def _wall_mechanism(wall: BlockWall, result: Any, solve: Callable[[BlockWall], Any]) -> WallMechanism:
    """The wall as built's result with a sliver's local mechanism told apart, and the held wall's beside it
    (:func:`comparison.domain.wall_mechanism.solve_wall_mechanism`; the held wall is solved only where a local
    one governs)."""
    from comparison.domain.wall_mechanism import solve_wall_mechanism

    return solve_wall_mechanism(wall, solve, first=result)


def _write_plot(draw: Callable[[], object], path: str) -> str | None:
    """Draw a plot (whole or not at all: :func:`micro.plot.save_figure`); why it could not be written
    (``None``: written). Not bad input (the folder was checked before solving; a full disk is not the
    user's input): the result is printed all the same, then :func:`~comparison.cli.options.exit_after_outputs`."""
    try:
        draw()
    except OSError as exc:
        return f"--plot: cannot write {path!r} ({exc.strerror or exc})"
    return None


def _json(summary: dict[str, Any], args: argparse.Namespace, spec: WallSpec, wall: BlockWall, *, plotted: bool,
          state: str | None) -> str:
    """One JSON line: the result's summary with the wall (its name, ``None`` without one; its paper parameters;
    whether its end blocks are cut), the options and the files written (``plot``, ``state``; ``None`` where
    none)."""
    summary.update(
        wall=spec.name or None,
        paper_parameters=spec.paper_parameters(),
        end_blocks_cut=wall.end_blocks_cut,
        ends=wall.ends,
        friction=args.friction,
        first_course=args.first_course,
        head_joints=args.head_joints,
        plot=args.plot if plotted else None,
        state=state,
    )
    return json.dumps(summary)


def _progress_line(event: LPProgress) -> None:
    """One line on stderr per LP (``-v``), written as it happens."""
    lam = f"{event.load_factor:.6f}" if math.isfinite(event.load_factor) else "-"
    step = f"{event.step:.2e}" if math.isfinite(event.step) else "-"
    print(f"  {event.direction} {event.stage} LP {event.lp}: lambda {lam}, step {step}, {event.algorithm}, "
          f"{event.seconds:.2f} s", file=sys.stderr, flush=True)


def _run_nonassociative(args: argparse.Namespace, spec: WallSpec, wall: BlockWall, time_limit: float | None) -> int:
    """``--friction nonassociative``: :func:`micro.solve_nonassociative`, the report's method."""
    import micro

    if args.solver is not None:
        raise UsageError("--solver applies to --friction associative only (the iterated LP runs HiGHS' simplex "
                         "and Clarabel's interior point)")
    tuning = parse_tuning(args.tuning)
    # the options given; the others are the library's defaults
    given: dict[str, Any] = {} if time_limit is None else {"time_limit": time_limit}
    if args.max_iterations is not None:
        given["max_iterations"] = int_option("--max-iterations", args.max_iterations, 2, SOLVER_COUNT_MAX)
    lowest = args.lowest or "on"
    if lowest not in LOWEST_CHOICES:
        try:
            given["lowest_budget"] = int_option("--lowest", lowest, 1, SOLVER_COUNT_MAX)
        except UsageError:
            raise UsageError(f"--lowest must be on, off or a number of LPs in 1..{SOLVER_COUNT_MAX:,}, "
                             f"got {lowest!r}") from None
        lowest = "on"
    nodes = None if args.node_limit is None else int_option("--node-limit", args.node_limit, 1, SOLVER_COUNT_MAX)
    progress = _progress_line if args.verbosity >= VERBOSE else None
    result = micro.solve_nonassociative(wall, tuning=tuning, progress=progress, lowest=LOWEST_CHOICES[lowest],
                                        **given)
    own = _wall_mechanism(wall, result, lambda w: micro.solve_nonassociative(
        w, tuning=tuning, progress=progress, lowest=LOWEST_CHOICES[lowest], **given))
    search = None
    if args.global_:  # composed after the run, from its states; its limits: --node-limit, and --time-limit
        from micro.global_search import GlobalOptions, solve_global

        limits = {"node_limit": nodes} if time_limit is None else {"node_limit": nodes,
                                                                    "direction_time_limit": time_limit}
        search = solve_global(wall, start=result, options=GlobalOptions(**limits))
    mechanism = result.governing.mechanism if result.ok and result.governing is not None else None
    plot_error = None
    if args.plot is not None and mechanism is not None:
        from comparison.report.mechanisms import storey_marks
        from micro.plot import plot_velocities

        title = (
            f"non-associative micro λ = {result.load_factor:.4f} (lowest certified; iterated LP "
            f"{result.iterated_load_factor:.4f}), {result.direction}, {result.blocks} blocks"
            if result.quoted == "lowest certified" else
            f"non-associative micro λ = {result.iterated_load_factor:.4f} (iterated LP; the lowest not searched or not "
            f"found), {result.direction}, {result.blocks} blocks"
        )
        plot_error = _write_plot(
            lambda: plot_velocities(wall, mechanism.velocities, args.plot, title=title, direction=result.direction,
                                    **storey_marks(spec)),
            args.plot,
        )
    state_written, state_error = write_state_file(args, result, wall, spec)
    if args.json:
        summary = result.summary(search)
        print(_json({**summary, **own.to_dict()}, args, spec, wall,
                    plotted=mechanism is not None and plot_error is None, state=state_written))
    else:
        print_nonassociative(result, args.verbosity, search)
        print_local(own, args.verbosity)
        print_cut(wall, args.verbosity)
        if args.plot is not None and mechanism is None:
            print(f"  no plot written to {args.plot}: no converged mechanism")
    return exit_after_outputs(result.ok, plot_error, state_error)


