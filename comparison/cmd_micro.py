"""``xcheck micro``: rigid-block limit analysis of the wall (micro model).

Example::

    xcheck micro --t 1 --m 1/3 --rows 12 --f 0.75 --friction associative --solver highs --json
"""

from __future__ import annotations

import argparse
import json
import math

from comparison.cli import UsageError, add_wall_options, wall_from_args

#: Friction laws accepted by ``--friction`` (the non-associative scheme comes next).
FRICTION_LAWS = ("associative",)


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add the ``micro`` subcommand."""
    from micro.solvers import SOLVERS

    p = subparsers.add_parser(
        "micro",
        help="rigid-block limit analysis (LP) of the wall built block by block",
        description="Collapse load factor of the wall built block by block in running bond, "
        "by rigid-block limit analysis solved as a linear program.",
    )
    add_wall_options(p)
    g = p.add_argument_group("micro model")
    g.add_argument("--friction", default="associative", metavar="LAW",
                   help="friction law: associative (default; the only one so far)")
    g.add_argument("--solver", default="highs", metavar="NAME",
                   help=f"LP back end: {', '.join(SOLVERS)} (default highs = HiGHS interior point, no crossover)")
    g.add_argument("--first-course", default="full", metavar="full|half",
                   help="the bottom course starts with a full (default) or a half block")
    g.add_argument("--head-joints", default="frictional", metavar="frictional|frictionless",
                   help="friction on the head joints (default frictional)")
    g.add_argument("--time-limit", default=None, metavar="SECONDS", help="time limit per LP solve")
    g.add_argument("--json", action="store_true", help="print one JSON object")
    g.add_argument("--plot", default=None, metavar="FILE.png", help="draw the wall and its collapse mechanism")
    p.set_defaults(handler=run)


def _choice(name: str, value: str, allowed: tuple[str, ...]) -> str:
    if value not in allowed:
        raise UsageError(f"{name} must be one of {', '.join(allowed)}, got {value!r}")
    return value


def run(args: argparse.Namespace) -> int:
    """Handler of ``xcheck micro``."""
    import micro
    from micro.solvers import SOLVERS

    _choice("--friction", args.friction, FRICTION_LAWS)
    _choice("--solver", args.solver, SOLVERS)
    _choice("--first-course", args.first_course, ("full", "half"))
    _choice("--head-joints", args.head_joints, ("frictional", "frictionless"))
    time_limit = None
    if args.time_limit is not None:
        try:
            time_limit = float(args.time_limit)
        except ValueError:
            raise UsageError(f"--time-limit must be a number of seconds, got {args.time_limit!r}") from None
        if not math.isfinite(time_limit) or time_limit <= 0:
            raise UsageError(f"--time-limit must be a positive number of seconds, got {args.time_limit!r}")
    if args.plot is not None and not args.plot.lower().endswith((".png", ".pdf", ".svg")):
        raise UsageError(f"--plot must name a .png, .pdf or .svg file, got {args.plot!r}")
    spec = wall_from_args(args)
    try:
        wall = spec.to_micro(first_course=args.first_course, head_joints=args.head_joints)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    result = micro.solve_associative(wall, solver=args.solver, time_limit=time_limit)
    if args.plot is not None and result.ok:
        from micro.plot import plot_mechanism

        try:
            plot_mechanism(wall, result, args.plot)
        except OSError as exc:
            raise UsageError(f"--plot: cannot write {args.plot!r} ({exc.strerror})") from None
    if args.json:
        out = result.summary()
        out.update(
            wall=spec.name or "", friction=args.friction, first_course=args.first_course,
            head_joints=args.head_joints, plot=args.plot if result.ok else None,
        )
        print(json.dumps(out))
    else:
        if result.ok:
            print(
                f"lambda = {result.load_factor:.6f} ({result.direction}) by {result.solver}: "
                f"{result.blocks} blocks, {result.contacts} contacts, "
                f"build {result.build_seconds:.3f} s, solve {result.solve_seconds:.3f} s"
            )
            for d in result.directions:
                print(f"  {d.direction}: lambda = {d.load_factor:.6f}, {d.iterations} iterations, {d.solve_seconds:.3f} s")
            if result.mirror_symmetric:
                print("  the wall is mirror-symmetric: -x gives the same load factor")
        else:
            print(f"status {result.status}: {result.message}")
    return 0 if result.ok else 1
