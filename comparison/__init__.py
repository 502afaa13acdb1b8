"""Macro against micro: shared wall specs, the paper's cases, reports and the ``xcheck`` CLI.

:func:`compare` sets both models against each other on one wall and gives the verdict on the macro model
(:mod:`comparison.domain.verdict`). It is imported when first used, so that ``import comparison`` (and the
``xcheck`` command's start, whose Ctrl-C handling is installed by :mod:`comparison.cli`) loads no numerical
library.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover - typing only
    from comparison.domain.verdict import CompareOptions, Comparison, compare

__all__ = ["CompareOptions", "Comparison", "compare"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from comparison.domain import verdict

        return getattr(verdict, name)
    raise AttributeError(f"module 'comparison' has no attribute {name!r}")
