"""The Examples sections of the API's docstrings run as written (doctest)."""

from __future__ import annotations

import doctest
from typing import Any

import pytest

import micro
from comparison.domain.proof import judge
from comparison.domain.verdict import compare
from micro.global_search import solve_global

#: The documented entry points whose docstrings carry an Examples section.
DOCUMENTED: list[Any] = [micro.build_wall, micro.solve_associative, micro.solve_nonassociative, solve_global,
                         judge, compare]


@pytest.mark.parametrize("obj", DOCUMENTED, ids=lambda o: o.__qualname__)
def test_docstring_examples_run(obj: Any) -> None:
    tests = doctest.DocTestFinder(recurse=False).find(obj, obj.__name__, globs={})
    assert tests and tests[0].examples, f"{obj.__qualname__} has no Examples section"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for test in tests:
        runner.run(test)
    assert runner.failures == 0, f"{runner.failures} failing example(s) in {obj.__qualname__}"
