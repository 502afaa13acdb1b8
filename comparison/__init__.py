"""Macro against micro: shared wall specs, the paper's cases, reports and the ``xcheck`` CLI.

:func:`compare` sets both models against each other on one wall and gives the verdict on the macro model
(:mod:`comparison.compare`).
"""

from comparison.compare import CompareOptions, Comparison, compare

__all__ = ["CompareOptions", "Comparison", "compare"]
