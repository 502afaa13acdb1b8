"""The verdict of a :class:`~comparison.domain.verdict.Comparison` in words: :func:`verdict_sentence`.

One sentence with the numbers the verdict rests on (the first line of ``xcheck compare``), and a second one
where a sliver's local mechanism governs the wall as built (:mod:`comparison.domain.wall_mechanism`).
"""

from __future__ import annotations

import math
from typing import Any

from comparison.domain.proof import ASSOCIATIVE_BOUND, GLOBAL_CLOSED, NOT_REFUTED, SAFE, UNSAFE, above

#: A :class:`comparison.domain.verdict.Comparison` (named, not imported: that module imports this one).
Comparison = Any


def verdict_sentence(c: Comparison) -> str:
    """The verdict and its proof in one sentence, with the numbers it rests on (and, where a sliver's local
    mechanism governs the wall as built, a second sentence that says so)."""
    return _verdict_only(c) + _local_sentence(c)


def _local_sentence(c: Comparison) -> str:
    loc = c.local_mechanism
    if loc is None:
        return ""
    held = loc.get("held_load_factor")
    beside = (f"; with the slivers held to the blocks that carry them (another wall), λ would be {held:.4f}"
              if held is not None else "")
    return (f" The wall as built collapses there by a local mechanism: {loc['description']} at λ "
            f"{loc['load_factor']:.4f}, which the verdict rests on{beside}.")


def _verdict_only(c: Comparison) -> str:
    macro_lam = c.macro_load_factor
    lam = f"{macro_lam:.4f}"
    if c.verdict == UNSAFE and c.proof == ASSOCIATIVE_BOUND:
        return (f"The macro model is unsafe for this wall: its λ {lam} is above the associative bound "
                f"{c.associative_load_factor:.4f} ({_percent(macro_lam, c.associative_load_factor)}), which no "
                "non-associative collapse load exceeds.")
    if c.verdict == UNSAFE:
        return (f"The macro model is unsafe for this wall: its λ {lam} is above the certified collapse state's "
                f"{c.certified_load_factor:.4f} ({_percent(macro_lam, c.certified_load_factor)}).")
    if c.verdict == SAFE:
        return (f"The macro model is safe for this wall: its λ {lam} lies below the global search's proven lower "
                f"bound {c.global_lower_bound:.4f} on every collapse load "
                f"({_percent(macro_lam, c.global_lower_bound)}).")
    if c.verdict == NOT_REFUTED:
        what = "lowest certified" if c.micro_quoted == "lowest certified" else "the iterated LP's"
        where = ("lies below every collapse state found" if above(c.micro_load_factor, macro_lam)
                 else "agrees with the lowest collapse state found within the solvers' accuracy")
        closed = c.global_status == GLOBAL_CLOSED
        bound = ("no lower bound was computed" if not c.global_status else
                 f"the global search's proven lower bound {c.global_lower_bound:.4f} agrees with it within the "
                 "solvers' accuracy: the macro λ is the wall's collapse load to that accuracy"
                 if closed and not above(macro_lam, c.global_lower_bound) else
                 f"the global search's lower bound {c.global_lower_bound:.4f} does not lie above it"
                 if closed else
                 f"the global search did not close ({c.global_status}; lower bound {c.global_lower_bound:.4f})")
        return (f"The macro model is not refuted for this wall: its λ {lam} {where} ({what} "
                f"{c.micro_load_factor:.4f}, {_percent(macro_lam, c.micro_load_factor)}); {bound}.")
    if not math.isfinite(macro_lam):
        return "No verdict for this wall: the macro model gave no load factor."
    bound = f" {c.associative_load_factor:.4f}" if math.isfinite(c.associative_load_factor) else ""
    if math.isfinite(c.micro_load_factor):  # above a state that is not certified
        return (f"No verdict for this wall: the macro λ {lam} is not above the associative bound{bound}, and the "
                f"state it lies above ({c.micro_load_factor:.4f}, "
                f"{_percent(macro_lam, c.micro_load_factor)}) is not certified (" + "; ".join(c.diagnostics) + ").")
    return (f"No verdict for this wall: the macro λ {lam} is not above the associative bound{bound}, and no "
            "collapse state was found to compare it with (" + "; ".join(c.diagnostics) + ").")


def _percent(value: float, reference: float) -> str:
    """``+0.4 %`` / ``−6.2 %``: ``value`` relative to ``reference``."""
    d = 100.0 * (value - reference) / reference
    size = f"{abs(d):.1f}" if abs(d) >= 0.1 or d == 0 else f"{abs(d):.2g}"  # +0.03 %, never an unsafe +0.0 %
    return f"{'+' if d >= 0 else '−'}{size} %"
