"""``xcheck micro``'s result in words: the value to quote first, then how it was reached (quiet: λ alone;
verbose: every LP). The command itself, its options and its JSON: :mod:`comparison.cli.micro`."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from comparison.cli.options import QUIET, VERBOSE

if TYPE_CHECKING:  # pragma: no cover - typing only
    from comparison.domain.wall_mechanism import WallMechanism
    from micro import BlockWall, LimitResult, NonAssociativeResult
    from micro.global_search import GlobalResult


def print_associative(result: LimitResult, verbosity: int) -> None:
    """The associative result in words: λ alone when quiet, sizes and contact states when verbose."""
    if not result.ok:
        print(f"status {result.status}: {result.message}")
        return
    if verbosity == QUIET:
        print(f"{result.load_factor:.6f}")
        return
    print(
        f"lambda = {result.load_factor:.6f} ({result.direction}) by {result.solver}: "
        f"{result.blocks} blocks, {result.contacts} contacts, "
        f"build {result.build_seconds:.3f} s, solve {result.solve_seconds:.3f} s"
    )
    for d in result.directions:
        print(f"  {d.direction}: lambda = {d.load_factor:.6f}, {d.iterations} iterations, {d.seconds:.3f} s")
    if result.mirror_symmetric:
        print("  the wall is mirror-symmetric: -x gives the same load factor")
    if verbosity >= VERBOSE:
        rec = result.to_record()
        print(f"  LP: {rec.variables} variables, {rec.rows} rows, {rec.nnz} nonzeros; contact points {rec.points}")
        print("  contacts of the mechanism: " + ", ".join(f"{n} {k}" for k, n in rec.contact_states.items()))


def print_local(own: WallMechanism, verbosity: int) -> None:
    """Where a sliver's local mechanism governs the wall as built, what moves and the held wall's load factor
    beside it: two lines after the result, none when quiet."""
    if own.local is None or verbosity == QUIET:
        return
    loc = own.local
    print(f"  local mechanism: {loc.description} (lambda = {loc.load_factor:.6f}, {loc.direction}, "
          f"{100 * loc.weight_share:.2g} % of the weight): the wall as built collapses there, at a sliver")
    n = len(own.held)
    if math.isfinite(own.held_load_factor) and own.held_result is not None:
        print(f"  held wall ({n} sliver{'s' if n != 1 else ''} held to the block{'s' if n != 1 else ''} that carry "
              f"{'them' if n != 1 else 'it'}, another wall): lambda = {own.held_load_factor:.6f} "
              f"({own.held_result.direction})")
    else:
        print(f"  held wall: no value ({own.message})")


def print_cut(wall: BlockWall, verbosity: int) -> None:
    """One line when ``L`` is not a whole number of half blocks (how the courses end), but when quiet."""
    if not wall.end_blocks_cut or verbosity == QUIET:
        return
    from micro import closer_width

    if wall.ends == "cut":
        how = "the last block of every course is cut, down to slivers (--ends cut)"
    else:
        width = closer_width(wall.block_length, wall.block_height, wall.friction)
        how = (f"the courses end in closers at least {width:.4g} wide, a remainder narrower than that taken up by "
               "a long last unit (--ends closers)")
    print(f"  L = {wall.half_blocks:.4g} half blocks, not a whole number: {how} (docs/micro/walls.md)")


def print_nonassociative(result: NonAssociativeResult, verbosity: int, search: GlobalResult | None = None) -> None:
    """The result in words, the value to quote first (the lowest certified collapse state, else the
    iterated LP's, saying why): λ alone when quiet, every LP when verbose."""
    if result.ok and verbosity == QUIET:
        print(f"{result.load_factor:.6f}")
        return
    if result.ok:
        _print_answer(result)
        band = result.mechanism_band
        states = "" if band is None else f"; its mechanism's collapse states: lambda in [{band[0]:.6f}, {band[1]:.6f}]"
        print(f"  iterated LP (Gilbert et al., scheme {result.scheme}, relaxation {result.relaxation:g}): "
              f"lambda = {result.iterated_load_factor:.6f}, converged in {result.iterations} LPs "
              f"({result.sequence.stop_reason})"
              f"{states}")
        print(f"  associative lambda = {result.associative_load_factor:.6f}")
        _print_retry(result)
        _print_global(search)
    else:
        window = (
            ""
            if result.sequence.lambda_band is None
            else f", lambda in [{result.sequence.lambda_band[0]:.6f}, {result.sequence.lambda_band[1]:.6f}]"
        )
        print(f"status {result.status} after {result.iterations} LPs{window}: {result.message}")
        if verbosity == QUIET:  # the failure line alone (docs/cli.md, "Exit codes")
            return
        _print_retry(result)
    _print_fusion(result)
    if verbosity == QUIET:
        return
    cold = ("" if not math.isfinite(result.sequence.warm_cold_rel_diff)
            else f"final LP re-solved cold: rel. difference {result.sequence.warm_cold_rel_diff:.2e}, ")
    print(
        f"  {cold}Coulomb residual {result.sequence.coulomb_residual:.2e}, dilatancy residual "
        f"{result.sequence.dilatancy_residual:.2e}, {result.blocks} blocks, {result.solve_seconds:.3f} s"
    )
    if verbosity >= VERBOSE:
        print("  LP   lambda      max dn     simplex it.  seconds  algorithm  certificate")
        for r in result.sequence.history:
            dn = "" if r.max_dn is None or not math.isfinite(r.max_dn) else f"{r.max_dn:.2e}"
            print(
                f"  {r.iteration:>3}  {r.load_factor:.6f}  {dn:>9}  {r.simplex_iterations:>11}  "
                f"{r.seconds:7.3f}  {r.algorithm}  {r.certificate}".rstrip()
            )


def _lowest_note(result: NonAssociativeResult) -> str:
    """Why the value printed first is not a finished descent's (``""`` when every direction's finished)."""
    if not result.lowest:
        return "the lowest certified state was not searched (--lowest off)"
    if result.lowest_state is None:
        why = "; ".join(x.message for x in result.lowest if x.message) or "none found"
        return f"the descent found no exact state ({why})"
    spent = [x for x in result.lowest if x.stop == "budget"]
    if spent:
        return (f"the descent spent its budget of {spent[0].budget} LPs: the lowest state found so far, not "
                "finished; --lowest N raises it")
    return ""


def _print_answer(result: NonAssociativeResult) -> None:
    """The first line: the value to quote, what it is, and where the descent did not finish, why."""
    low = result.lowest_state
    note = _lowest_note(result)
    if low is not None:
        n = len(low.moves)
        how = f"{low.lps} LPs" + (f", {n} move{'s' if n > 1 else ''}" if n else "")
        done = note or f"descent finished: {how}, {low.seconds:.3f} s"
        print(f"lambda = {low.load_factor:.6f} ({low.direction}): the lowest certified collapse state, "
              f"non-associative friction ({done})")
    else:
        print(f"lambda = {result.iterated_load_factor:.6f} ({result.direction}): the iterated LP's collapse state, "
              f"non-associative friction; {note}")


def _print_retry(result: NonAssociativeResult) -> None:
    """Where the vertex sequence failed and the proximal one ran: the line saying so, and how
    the vertex one ended."""
    first = result.sequence.vertex_attempt
    if first is None:
        return
    band = "" if first.lambda_band is None else f", lambda in [{first.lambda_band[0]:.6f}, {first.lambda_band[1]:.6f}]"
    print(f"  {result.sequence.selection} sequence ({len(result.sequence.history) - 1} LPs) after the vertex sequence "
          f"ended {first.stop_reason} "
          f"({len(first.history) - 1} LPs{band})")


def _print_fusion(result: NonAssociativeResult) -> None:
    """On a fused wall (walls of more than 2,000 blocks, ``--tuning fuse=true``, or after the wall's own
    sequences failed): the size of the fused wall, and whether the wall's certificate took its state."""
    f = result.sequence.fusion
    if f is None:
        return
    before = result.sequence.unfused_attempt
    if before is not None:
        print(f"  the wall's own sequences ended {before.stop_reason} ({len(before.history) - 1} LPs); "
              "then the fused wall with the continuation:")
    took = {"certified": "; the wall's certificate extends its state to every block",
            "rejected": "; the wall's certificate rejects its state"}.get(f.wall_certificate, "")
    print(f"  fused wall: {f.bodies:,} moving bodies ({f.single_bodies:,} of one block), {f.blocks_at_rest:,} "
          f"blocks at rest, {f.points:,} of {f.wall_points:,} contact points{took}")


def _print_global(g: GlobalResult | None) -> None:
    """The global search, when it ran."""
    if g is not None:
        print(f"  global search ({g.status}): best lambda = {g.load_factor:.6f}, proven lower bound "
              f"{g.lower_bound:.6f}, gap {100 * g.gap:.2f} %, {g.seconds:.1f} s")
        if g.message:  # where it stopped: its node budget (the same on every machine) or a time limit given
            print(f"    {g.message}")
