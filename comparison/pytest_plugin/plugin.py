"""The pytest hooks and fixtures (registered through the ``pytest11`` entry point ``xcheck``).

Fixtures:

* ``xcheck_references``: the shipped :class:`~comparison.pytest_plugin.references.References`
  (session scope); ``xcheck_references.check(case, method, value, rel=...)`` asserts;
* ``xcheck_table``: the session's :class:`~comparison.pytest_plugin.comparison_table.ComparisonTable`;
  ``xcheck_table.add(case, value, method)`` records a value. The table is printed
  at the end of the session and written to ``--xcheck-table PATH``;
* ``xcheck_case``: a test that takes it runs once per wall of ``--xcheck-cases``
  and ``--xcheck-walls`` (default: every paper case).

Options: ``--xcheck-compute`` (our methods computed as references for the
walls of ``--xcheck-walls``, default ``macro``; ``micro-assoc``,
``micro-nonassoc`` through the result cache), ``--xcheck-cases`` (``"7"``, ``"5,9"``, ``"Ref,Set 12"``, ``"all"``,
or names of the walls of ``--xcheck-walls``: see :func:`~comparison.pytest_plugin.walls.cases_and_walls`),
``--xcheck-walls FILE.toml`` (see :func:`~comparison.pytest_plugin.walls.walls_from_file`),
``--xcheck-table PATH`` (``.md`` or ``.csv``; its folder is checked before the tests run, and a table
that cannot be written at the end, a full disk, is one line in the summary and fails the run),
``--xcheck-against LIST`` (the reference columns of the table, methods of the references, default
:data:`~comparison.pytest_plugin.comparison_table.DEFAULT_AGAINST`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pytest

from comparison.domain.cases import PaperCase
from comparison.pytest_plugin.comparison_table import DEFAULT_AGAINST, ComparisonTable
from comparison.pytest_plugin.references import COMPUTABLE, BadReferences, References
from comparison.pytest_plugin.walls import UserWall, cases_and_walls

_TABLE = pytest.StashKey[ComparisonTable]()
_TABLE_ERROR = pytest.StashKey[str]()
_REFERENCES = pytest.StashKey[References]()
_WALLS = pytest.StashKey[Sequence[PaperCase]]()


def pytest_addoption(parser: pytest.Parser) -> None:
    """The plugin's options."""
    g = parser.getgroup("xcheck", "xcheck-masonry: the paper's walls and reference values")
    g.addoption(
        "--xcheck-cases",
        default=None,
        metavar="LIST",
        help="walls for xcheck_case: tables (7), paper cases (Ref, Set 12), all, or names of --xcheck-walls walls",
    )
    g.addoption("--xcheck-walls", default=None, metavar="FILE.toml", help="your own walls for xcheck_case")
    g.addoption(
        "--xcheck-compute",
        default="macro",
        metavar="LIST",
        help="our methods computed now as references for --xcheck-walls: macro (default), micro-assoc, "
        "micro-nonassoc (through the result cache, $XCHECK_CACHE or ~/.cache/xcheck)",
    )
    g.addoption("--xcheck-table", default=None, metavar="PATH", help="write the comparison table (.md or .csv)")
    g.addoption(
        "--xcheck-against",
        default=",".join(DEFAULT_AGAINST),
        metavar="LIST",
        help=f"reference columns of the comparison table (default {','.join(DEFAULT_AGAINST)})",
    )


def _references(config: pytest.Config) -> References:
    """The shipped references, with cells computed now for the user's walls (``--xcheck-compute``)."""
    if _REFERENCES not in config.stash:
        refs = References.load()
        own = [w for w in config.stash[_WALLS] if isinstance(w, UserWall)]
        kinds = _listed(config, "xcheck_compute")
        if own and kinds:
            from comparison.pytest_plugin.generate import wall_cells
            from comparison.runner import default_cache_dir

            refs = refs.extended(wall_cells(own, kinds, default_cache_dir()))
        config.stash[_REFERENCES] = refs
    return config.stash[_REFERENCES]


def _table(config: pytest.Config) -> ComparisonTable:
    if _TABLE not in config.stash:
        config.stash[_TABLE] = ComparisonTable(_references(config), _listed(config, "xcheck_against"))
    return config.stash[_TABLE]


@pytest.fixture(scope="session")
def xcheck_references(pytestconfig: pytest.Config) -> References:
    """The reference values shipped with xcheck-masonry (and computed for ``--xcheck-walls``)."""
    return _references(pytestconfig)


@pytest.fixture(scope="session")
def xcheck_table(pytestconfig: pytest.Config) -> ComparisonTable:
    """The session's comparison table (printed at the end, written to ``--xcheck-table``)."""
    return _table(pytestconfig)


def pytest_configure(config: pytest.Config) -> None:
    """Read ``--xcheck-cases`` and ``--xcheck-walls`` once; a bad one stops the run as a usage error."""
    try:
        config.stash[_WALLS] = cases_and_walls(config.getoption("xcheck_cases"), config.getoption("xcheck_walls"))
    except (TypeError, ValueError) as exc:
        raise pytest.UsageError(str(exc)) from None
    unknown = [k for k in _listed(config, "xcheck_compute") if k not in COMPUTABLE]
    if unknown:
        raise pytest.UsageError(f"--xcheck-compute: {', '.join(unknown)} not among {', '.join(COMPUTABLE)}")
    against = _listed(config, "xcheck_against")
    try:
        methods = References.load().all_methods()
    except BadReferences as exc:
        raise pytest.UsageError(f"the plugin's references: {exc}") from None
    unknown = [k for k in against if k not in methods]
    if unknown or not against:
        given = f"{', '.join(unknown)} not among" if unknown else "no method given; the methods are"
        raise pytest.UsageError(f"--xcheck-against: {given} {', '.join(methods)}")
    path = config.getoption("xcheck_table")
    if path is not None:
        problem = table_path_problem(str(path))
        if problem:
            raise pytest.UsageError(f"--xcheck-table: {problem}")


def table_path_problem(path: str) -> str:
    """Why the comparison table cannot be written to ``path`` (``""``: it can be tried), checked before the
    tests run: an empty path, a directory, a folder that does not exist or cannot be written."""
    if not path.strip():
        return f"must name a file (.md or .csv), got {path!r}"
    p = Path(path)
    if p.is_dir():
        return f"{path!r} is a directory; name a file (.md or .csv)"
    folder = p.parent
    if not folder.is_dir():
        return f"the folder of {path!r} does not exist"
    if not os.access(folder, os.W_OK | os.X_OK) and not (p.exists() and os.access(p, os.W_OK)):
        return f"cannot write to {path!r} (permission denied)"
    return ""


def _listed(config: pytest.Config, option: str) -> list[str]:
    """The items of a comma-separated option."""
    return [k.strip() for k in str(config.getoption(option)).split(",") if k.strip()]


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """Parametrise ``xcheck_case`` over the selected walls."""
    if "xcheck_case" in metafunc.fixturenames:
        walls = metafunc.config.stash[_WALLS]
        metafunc.parametrize("xcheck_case", walls, ids=[w.label for w in walls])


@pytest.hookimpl(tryfirst=True)
def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """Write the comparison table to ``--xcheck-table``."""
    path = session.config.getoption("xcheck_table")
    if path and _TABLE in session.config.stash and session.config.stash[_TABLE].entries:
        try:
            session.config.stash[_TABLE].write(path)
        except OSError as exc:  # a full or read-only disk: one line in the summary, the run fails
            session.config.stash[_TABLE_ERROR] = f"cannot write the table to {path} ({exc.strerror or exc})"
            if session.exitstatus == pytest.ExitCode.OK:
                session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter: Any, exitstatus: int, config: pytest.Config) -> None:
    """Print the comparison table when a test filled it."""
    if _TABLE in config.stash and config.stash[_TABLE].entries:
        terminalreporter.write_sep("=", "xcheck: your values against the references")
        terminalreporter.write_line(config.stash[_TABLE].markdown())
        path = config.getoption("xcheck_table")
        if _TABLE_ERROR in config.stash:
            terminalreporter.write_line(f"xcheck: error: {config.stash[_TABLE_ERROR]}", red=True)
        elif path:
            terminalreporter.write_line(f"written to {path}")
