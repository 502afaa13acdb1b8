"""Strategies and checks shared by the fuzz tests (hypothesis).

The fast suite draws :data:`EXAMPLES` examples per test (a few seconds in all);
the long run sets ``XCHECK_FUZZ_EXAMPLES``::

    XCHECK_FUZZ_EXAMPLES=2000 pytest -m fuzz -p no:randomly
"""

from __future__ import annotations

import math
import os
from typing import Any

import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

#: Examples per fuzz test (``XCHECK_FUZZ_EXAMPLES``, default 40).
EXAMPLES = int(os.environ.get("XCHECK_FUZZ_EXAMPLES", "40"))

#: The settings of every fuzz test.
FUZZ = settings(
    max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)

#: The marker of every fuzz test (``pytest -m fuzz``).
mark = pytest.mark.fuzz

#: Numbers at the edges of double precision and of the physical bounds.
EDGES = (
    0.0, -0.0, 5e-324, 1e-300, 1e-30, 1e-17, 1e-9, 1e-6, 1e-3, 1e3, 1e6, 1e7, 1e16, 1e30, 1e31, 1e300,
    1.7976931348623157e308, math.inf, -math.inf, math.nan, -1.0, -1e-300,
)  # fmt: skip

#: Any double, the edges, and ordinary values.
numbers = st.one_of(st.floats(), st.sampled_from(EDGES), st.floats(0.05, 20.0))


def mostly(ordinary: st.SearchStrategy[Any], odd: st.SearchStrategy[Any] = numbers) -> st.SearchStrategy[Any]:
    """``ordinary`` values, and one draw in eight from ``odd`` (extreme numbers by default)."""
    return st.sampled_from([False] * 7 + [True]).flatmap(lambda extreme: odd if extreme else ordinary)


#: A command-line number: a float's text, a fraction, or garbage.
number_text = st.one_of(
    numbers.map(repr),
    st.sampled_from(["1/3", "1/0", "0/0", "-1/2", "", " ", "x", "1e400", "-1e400", "nan", "inf", "0x10", "1_000"]),
    st.integers(-(10**20), 10**20).map(str),
    st.text(max_size=6),
)


def finite_success(status: str, load_factor: Any) -> bool:
    """A success status comes with a finite load factor (the invariant under test)."""
    if status not in ("optimal", "converged"):
        return True
    return isinstance(load_factor, (int, float)) and math.isfinite(load_factor) and load_factor >= 0


def one_line_error(err: str) -> bool:
    """``xcheck: error: ...`` on one line."""
    return err.startswith("xcheck: error: ") and err.count("\n") == 1
