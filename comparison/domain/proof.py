"""What a macro λ set against the micro model's proves: the verdict and its proof (:func:`judge`).

* The associative λ bounds every non-associative collapse load from above (Drucker 1954: joints "cemented"
  with a normality-obeying material carry at least as much). So a macro λ above the associative λ is
  **unsafe**, proof ``"associative bound"``: one LP settles it (:func:`comparison.compare` then skips the
  non-associative solve).
* Every certified collapse state is a load at which the wall can collapse. So a macro λ above a certified
  state's λ is **unsafe**, proof ``"certified state"``. Where both prove it, the verdict cites the one the
  macro λ exceeds by more (the certified state's, which lies at or below the bound).
* No lower bound on the non-associative collapse load of dry joints is known short of a closed global search
  (Drucker's frictionless bound is 0 under horizontal load; the reduced friction ``tan φ* = sin φ`` is no
  bound for joints of fixed orientation). So a macro λ below every state found is **not refuted**, never
  safe, unless a global search that closed (status ``optimal``) proves a lower bound above it: **safe**,
  proof ``"global bound"``.

A method that fails gives a verdict only from what was proven (a macro λ above the associative bound is
unsafe whatever the non-associative solve did); where nothing proves either way there is no verdict
(``None``), and the comparison's ``diagnostics`` say what is missing. No number is made up for a method that failed.

"Above" means above by more than :data:`ACCURACY`, the relative accuracy of the solvers: a macro λ that
agrees with a micro one within it is neither above nor below it.
"""

from __future__ import annotations

import math

#: Relative accuracy of the solvers' load factors: the LPs are solved to about 1e-6 relative, a certified
#: state's residuals are at rounding level, the macro minimum is exact to about 1e-9. One value is *above*
#: another only when it exceeds it by more than this fraction (walls where both models slide at λ = f agree
#: to 1e-9 and are not told apart). The same margin as the sweeps'
#: (:data:`comparison.sweep.wall_comparisons.AGREEMENT`).
ACCURACY = 1e-4

#: Values of :attr:`comparison.domain.verdict.Comparison.verdict` (``None``: no verdict, nothing proves either way).
UNSAFE, NOT_REFUTED, SAFE = "unsafe", "not refuted", "safe"
VERDICTS = (UNSAFE, NOT_REFUTED, SAFE)
#: Values of :attr:`comparison.domain.verdict.Comparison.proof` (``None`` with "not refuted" or no verdict).
ASSOCIATIVE_BOUND, CERTIFIED_STATE, GLOBAL_BOUND = "associative bound", "certified state", "global bound"
PROOFS = (ASSOCIATIVE_BOUND, CERTIFIED_STATE, GLOBAL_BOUND)
#: The global search's status when it closed (its lower bound is proven to its gap).
GLOBAL_CLOSED = "optimal"


def above(value: float, reference: float) -> bool:
    """Whether ``value`` exceeds ``reference`` by more than :data:`ACCURACY` (relative); ``False`` unless both
    are finite."""
    return math.isfinite(value) and math.isfinite(reference) and value > reference * (1.0 + ACCURACY)


def refuting_below(macro_load_factor: float) -> float:
    """The λ below which a certified collapse state proves ``macro_load_factor`` unsafe (:func:`above` it);
    :func:`comparison.compare` stops the non-associative search at the first such state."""
    return macro_load_factor / (1.0 + ACCURACY)


def judge(macro_load_factor: float, associative_load_factor: float = math.nan,
          certified_load_factor: float = math.nan, *, found_load_factor: float = math.nan,
          global_lower_bound: float = math.nan) -> tuple[str | None, str | None]:
    """The verdict on a macro λ and its proof (module docstring), from what the micro model proved.

    Args:
        macro_load_factor: the macro model's λ (NaN: it gave none, no verdict).
        associative_load_factor: the associative LP's λ (NaN: not run or failed).
        certified_load_factor: the lowest λ of a certified collapse state found (NaN: none).
        found_load_factor: the lowest λ of the non-associative states found, certified or not (the value to
            quote of a converged solve; NaN: the solve did not run or failed). A macro λ not above it is "not
            refuted"; without it, or above an uncertified one, and no proof, there is no verdict.
        global_lower_bound: the lower bound of a global search that closed (NaN: none; pass only a bound of
            status :data:`GLOBAL_CLOSED`).

    Returns:
        ``(verdict, proof)``: one of :data:`VERDICTS` or ``None``, one of :data:`PROOFS` or ``None``.

    Examples:
        >>> from comparison.domain.proof import judge
        >>> judge(0.61, 0.505)
        ('unsafe', 'associative bound')
        >>> judge(0.4914, 0.5564, 0.4895, found_load_factor=0.4895)
        ('unsafe', 'certified state')
        >>> judge(0.5010, 0.5005, 0.4752, found_load_factor=0.4752)  # both prove it: the larger margin is cited
        ('unsafe', 'certified state')
        >>> judge(0.6481, 0.7303, 0.6911, found_load_factor=0.6911)
        ('not refuted', None)
        >>> judge(0.6481, 0.7303)  # the non-associative solve failed: nothing proves either way
        (None, None)
    """
    if not math.isfinite(macro_load_factor):
        return None, None
    # the strongest proof: the one the macro value exceeds by the largest margin (a certified state lies at or
    # below the associative bound, so it wins wherever both prove it)
    margins = [(macro_load_factor / ref, proof) for ref, proof in ((associative_load_factor, ASSOCIATIVE_BOUND),
                                                                  (certified_load_factor, CERTIFIED_STATE))
               if above(macro_load_factor, ref)]
    if margins:
        return UNSAFE, max(margins)[1]
    if above(global_lower_bound, macro_load_factor):
        return SAFE, GLOBAL_BOUND
    if math.isfinite(found_load_factor) and not above(macro_load_factor, found_load_factor):
        return NOT_REFUTED, None
    return None, None
