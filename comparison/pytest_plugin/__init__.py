"""A pytest plugin: run the paper's walls against your own method, with reference values to compare.

Installed with ``xcheck-masonry`` and registered through the ``pytest11`` entry
point, so a downstream project's tests get, without a ``conftest.py``:

* parametrisation helpers: :func:`paper_cases` (the paper's cases of a table,
  with known gaps marked as strict expected failures), :func:`walls_from_file`
  (your own walls in the paper's parameters), and the ``xcheck_case`` fixture
  driven by ``--xcheck-cases`` / ``--xcheck-walls``;
* reference values for every method on every case, each with its tolerance and
  source (:class:`References`, fixture ``xcheck_references``), and the assertion
  helper :meth:`References.check`, whose failure names the case, the method and
  the cell: ``Set 14 / micro-nonassoc / load_factor: 0.2500 outside 0.2658 ± 0.0066 (...)``;
* the Tables 7-9 style percentage table of your values against the references
  (fixture ``xcheck_table``, option ``--xcheck-table PATH``).

Example (a downstream ``tests/test_table7.py``)::

    import pytest
    from comparison.pytest_plugin import paper_cases
    import my_model

    @pytest.mark.parametrize("case", paper_cases("7", known_gaps={"Set 11": "no friction"}))
    def test_table7(case, xcheck_references, xcheck_table):
        lam = my_model.load_factor(t=case.t, m=case.m, rows=case.rows, f=case.f)
        xcheck_table.add(case, lam, "my model")
        xcheck_references.check(case, "orduna-micro", lam, rel=0.05)

Timings: use pytest-benchmark's ``benchmark`` fixture in the same tests, so
that ``--benchmark-autosave`` and ``--benchmark-compare`` flag slowdowns. The
reference values are regenerated with ``xcheck references`` (see
:mod:`comparison.pytest_plugin.generate`).
"""

from comparison.pytest_plugin.comparison_table import DEFAULT_AGAINST, ComparisonTable
from comparison.pytest_plugin.references import (
    BadReferences,
    MissingReference,
    Reference,
    ReferenceMismatch,
    References,
)
from comparison.pytest_plugin.walls import UserWall, paper_cases, select_cases, walls_from_file

__all__ = [
    "DEFAULT_AGAINST",
    "ComparisonTable",
    "BadReferences",
    "MissingReference",
    "Reference",
    "ReferenceMismatch",
    "References",
    "UserWall",
    "paper_cases",
    "select_cases",
    "walls_from_file",
]
