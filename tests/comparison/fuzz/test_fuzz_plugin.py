"""Fuzzing the pytest plugin's helpers and fixtures: ``xcheck_references.check``/``get``/``value``,
``xcheck_table.add``, ``paper_cases``, ``select_cases`` and the walls file.

Any draw either gives an answer or raises ``TypeError``/``ValueError`` (a parameter named), a
``ReferenceMismatch`` or a ``MissingReference``; never another exception (``AttributeError``,
``OverflowError``) and never a silent pass: ``check`` passes only a finite value within a finite
interval, and ``paper_cases`` of named tables is never empty.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path
from typing import Any

from fuzz_strategies import FUZZ, mark, mostly, number_text, numbers
from hypothesis import event, given
from hypothesis import strategies as st

from comparison.pytest_plugin import (
    ComparisonTable,
    MissingReference,
    ReferenceMismatch,
    References,
    paper_cases,
    select_cases,
    walls_from_file,
)
from comparison.pytest_plugin.walls import TABLES

pytestmark = mark

REFS = References.load()

#: Anything a careless test might pass where a name, a number or a mapping is expected.
ODD: st.SearchStrategy[Any] = st.one_of(
    st.none(), st.booleans(), st.integers(-(10**400), 10**400), numbers,
    st.text(st.characters(blacklist_categories=("Cc", "Cs")), max_size=8),  # a name, on one line
    st.lists(st.integers(0, 20), max_size=2), st.dictionaries(st.text(max_size=3), st.none(), max_size=2),
    st.sampled_from([b"7", object(), math.nan, "5%", "Set 99", "", " "]),
)  # fmt: skip
WALLS = mostly(st.sampled_from(["Ref", "Set 11", "12", "Set 17", "set 5", "my wall"]), ODD)
METHODS = mostly(st.sampled_from(["paper", "orduna-micro", "micro-nonassoc", "micro-assoc", "macro"]), ODD)
CELLS = mostly(st.sampled_from(["load_factor", "load_factor", "band_min", "alpha_c_deg"]), ODD)
WIDENINGS = mostly(st.sampled_from([0.0, 0.02, 0.05, 1e-3]), st.one_of(numbers, ODD))


@FUZZ
@given(wall=WALLS, method=METHODS, value=mostly(st.floats(0.0, 1.5), ODD), cell=CELLS, rel=WIDENINGS,
       abs_=WIDENINGS)
def test_fuzz_check(wall: Any, method: Any, value: Any, cell: Any, rel: Any, abs_: Any) -> None:
    try:
        ref = REFS.check(wall, method, value, cell, rel=rel, abs=abs_)
    except (TypeError, ValueError, ReferenceMismatch, MissingReference) as exc:
        assert "\n" not in str(exc)
        event(type(exc).__name__)
        return
    # a pass: a real value within a finite interval of a real reference
    widen = [float(w) for w in (rel, abs_)]
    assert all(math.isfinite(w) and w >= 0 for w in widen), (rel, abs_)
    assert ref.value is not None and math.isfinite(float(value))
    assert math.fabs(float(value) - ref.value) <= ref.allowed(*widen)
    event("passed")


@FUZZ
@given(wall=WALLS, method=METHODS, cell=CELLS)
def test_fuzz_lookups(wall: Any, method: Any, cell: Any) -> None:
    for call in (lambda: REFS.get(wall, method, cell), lambda: REFS.value(wall, method, cell),
                 lambda: REFS.methods(wall)):
        try:
            call()
        except (TypeError, ValueError, MissingReference) as exc:
            event(type(exc).__name__)


@FUZZ
@given(wall=WALLS, value=mostly(st.floats(0.0, 1.5), ODD), method=mostly(st.just("mine"), ODD))
def test_fuzz_table_add(wall: Any, value: Any, method: Any) -> None:
    table = ComparisonTable(REFS)
    try:
        table.add(wall, value, method)
    except (TypeError, ValueError) as exc:
        assert table.entries == [] and "\n" not in str(exc)
        event(type(exc).__name__)
        return
    assert isinstance(table.entries[0][2], float)
    table.markdown()
    table.csv()
    event("added")


GAPS = st.one_of(
    st.none(),
    st.dictionaries(st.sampled_from(["Set 11", "11", "Set 15", "Ref", "Set 99"]), mostly(st.just("why"), ODD),
                    max_size=2),
    ODD,
)


@FUZZ
@given(tables=st.lists(mostly(st.sampled_from([*TABLES, "table 7"]), ODD), max_size=3), gaps=GAPS)
def test_fuzz_paper_cases(tables: list[Any], gaps: Any) -> None:
    try:
        params = paper_cases(*tables, known_gaps=gaps)
    except (TypeError, ValueError) as exc:
        assert "\n" not in str(exc)
        event(type(exc).__name__)
        return
    assert params, (tables, gaps)  # never an empty selection whose tests pytest would skip and pass
    for p in params:
        for m in p.marks:
            assert isinstance(m.kwargs["reason"], str) and m.kwargs["reason"].strip()
    event("selected")


@FUZZ
@given(selection=mostly(st.sampled_from(["7", "Ref,Set 12", "all", "table 9", "Set 99", ""]), ODD))
def test_fuzz_select_cases(selection: Any) -> None:
    try:
        select_cases(selection)
    except (TypeError, ValueError) as exc:
        event(type(exc).__name__)


def _toml(value: Any) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return repr(value).replace("True", "true").replace("False", "false")


@FUZZ
@given(
    t=mostly(st.sampled_from([0.5, 1, 2]), st.one_of(numbers, number_text)),
    m=mostly(st.sampled_from(['"1/3"', "0.5", "1"]), st.one_of(numbers.map(_toml), number_text.map(_toml))),
    rows=mostly(st.sampled_from([4, 8, 12]), st.one_of(st.integers(-3, 10**30), numbers)),
    f=mostly(st.sampled_from([0.6, 0.75]), numbers),
    storeys=mostly(st.just(1), st.one_of(st.integers(-1, 5), numbers)),
)
def test_fuzz_walls_file(t: Any, m: str, rows: Any, f: Any, storeys: Any) -> None:
    text = (f'[[wall]]\nname = "w"\nt = {_toml(t)}\nm = {m}\nrows = {_toml(rows)}\nf = {_toml(f)}\n'
            f"storeys = {_toml(storeys)}\n")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "w.toml"
        path.write_text(text)
        try:
            (wall,) = walls_from_file(path)
        except ValueError as exc:
            assert str(exc).startswith(str(path)) and "\n" not in str(exc), exc
            event("refused")
            return
    assert wall.spec().rows == wall.rows
    event("read")


@FUZZ
@given(selection=mostly(st.sampled_from(["7", "Ref,Set 12", "all", "w", "Set 99", "", None]), ODD),
       path=mostly(st.sampled_from(["t.md", "t.csv", "missing/t.md", ".", ""]), st.text(max_size=12)))
def test_fuzz_plugin_options(selection: Any, path: str) -> None:
    """What ``pytest_configure`` reads: ``--xcheck-cases`` (with a walls file) and ``--xcheck-table``'s path;
    a usage error or a selection, never another exception."""
    from comparison.pytest_plugin.plugin import table_path_problem
    from comparison.pytest_plugin.walls import cases_and_walls

    with tempfile.TemporaryDirectory() as tmp:
        walls = Path(tmp) / "walls.toml"
        walls.write_text('[[wall]]\nname = "w"\nt = 1\nm = "1/3"\nrows = 4\nf = 0.6\n')
        try:
            chosen = cases_and_walls(selection, str(walls))
        except (TypeError, ValueError) as exc:
            event(type(exc).__name__)
        else:
            assert chosen
        assert isinstance(table_path_problem(str(Path(tmp) / path) if path else path), str)
