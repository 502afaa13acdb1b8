"""The plugin's helpers and fixtures refuse bad input at once, naming the parameter; no silent pass,
no silently empty selection, no INTERNALERROR, no traceback when the table cannot be written."""

from __future__ import annotations

import errno
import json
import math
import os
import re
from pathlib import Path

import pytest
from downstream import Run, in_a_process, in_this_process

from comparison.pytest_plugin import (
    BadReferences,
    ComparisonTable,
    References,
    paper_cases,
    select_cases,
    walls_from_file,
)
from comparison.pytest_plugin import references as references_module

REFS = References.load()


@pytest.mark.parametrize("widen", ["rel", "abs"])
@pytest.mark.parametrize("bad", [math.nan, math.inf, -0.01, 10**400])
def test_a_nan_or_negative_widening_is_refused_not_passed(widen: str, bad: float) -> None:
    """A NaN, infinite or negative ``rel`` or ``abs`` is refused, never a check every value passes."""
    with pytest.raises(ValueError, match=rf"^{widen} must be a finite number >= 0"):
        REFS.check("Set 11", "orduna-micro", 99.0, **{widen: bad})  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=rf"^{widen} must be a finite number >= 0"):
        REFS.get("Set 11", "orduna-micro").allowed(**{widen: bad})


@pytest.mark.parametrize("bad", ["5%", None, True, [0.05]])
def test_a_widening_that_is_not_a_number_is_a_type_error_naming_it(bad: object) -> None:
    with pytest.raises(TypeError, match=r"^rel must be a number >= 0 \(0.05 for 5 %\), got "):
        REFS.check("Set 11", "orduna-micro", 0.69, rel=bad)  # type: ignore[arg-type]


def test_the_widening_still_widens() -> None:
    REFS.check("Set 11", "orduna-micro", 0.72, rel=0.05)
    REFS.check("Set 11", "orduna-micro", 0.72, abs=0.03)
    REFS.check("Set 11", "orduna-micro", 0.69, rel=0, abs=0)


@pytest.mark.parametrize("wall", [None, 11, 11.0, ["Set 11"]])
def test_a_wall_that_is_not_a_case_or_a_name_is_a_type_error(wall: object) -> None:
    """``check(None, ...)`` raised ``AttributeError: 'NoneType' object has no attribute 'removeprefix'``."""
    msg = r"^wall must be a case \(PaperCase\) or a name such as 'Set 12', got "
    for call in (
        lambda: REFS.check(wall, "orduna-micro", 0.69),  # type: ignore[arg-type]
        lambda: REFS.get(wall, "paper"),  # type: ignore[arg-type]
        lambda: REFS.value(wall, "paper"),  # type: ignore[arg-type]
        lambda: REFS.methods(wall),  # type: ignore[arg-type]
        lambda: ComparisonTable(REFS).add(wall, 0.5),  # type: ignore[arg-type]
    ):
        with pytest.raises(TypeError, match=msg):
            call()


def test_a_method_or_cell_that_is_not_a_string_is_named() -> None:
    with pytest.raises(TypeError, match=r"^method must be a string"):
        REFS.check("Set 11", None, 0.69)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"^cell must be a string"):
        REFS.check("Set 11", "paper", 0.69, cell=None)  # type: ignore[arg-type]
    table = ComparisonTable(REFS)
    with pytest.raises(TypeError, match=r"^method must be a string"):
        table.add("Set 11", 0.5, None)  # type: ignore[arg-type]
    assert table.entries == []


@pytest.mark.parametrize(("tables", "error", "match"), [
    (("99",), ValueError, r"^paper_cases: no table '99' \(tables 5, 6, 7, 8, 9\)$"),
    (("7", "4"), ValueError, r"^paper_cases: no table '4'"),
    (("",), ValueError, r"^paper_cases: no table ''"),
    ((7,), TypeError, r"^paper_cases: tables must be strings such as '7', got 7 \(int\)$"),
    ((None,), TypeError, r"^paper_cases: tables must be strings"),
    ((["7"],), TypeError, r"^paper_cases: tables must be strings"),
])
def test_paper_cases_of_no_table_is_an_error_not_an_empty_list(tables: tuple, error: type, match: str) -> None:
    """``paper_cases("99")`` and ``paper_cases(7)`` raise, naming the table; never an empty list (a test
    skipped, pytest exit 0)."""
    with pytest.raises(error, match=match):
        paper_cases(*tables)


def test_paper_cases_of_real_tables() -> None:
    assert [p.id for p in paper_cases("7")] == ["Set 11", "Set 12", "Set 13", "Set 14"]
    assert [p.id for p in paper_cases("table 9")] == ["Set 15", "Set 16", "Set 17"]
    assert [p.id for p in paper_cases("9", "7")] == ["Set 11", "Set 12", "Set 13", "Set 14", "Set 15", "Set 16",
                                                     "Set 17"]
    assert len(paper_cases()) == 18


@pytest.mark.parametrize(("gaps", "error", "match"), [
    ({"Set 11": None}, TypeError, r"^known_gaps\['Set 11'\] must be the reason, a string, got None"),
    ({"Set 11": ""}, ValueError, r"^known_gaps\['Set 11'\]: the reason is empty"),
    (["Set 11"], TypeError, r"^known_gaps must map case names to reasons"),
    ("Set 11", TypeError, r"^known_gaps must map case names to reasons"),
    ({11: "why"}, TypeError, r"^known_gaps: case must be a name such as 'Ref', '7' or 'Set 7', got 11 \(int\)"),
    ({"Set 99": "why"}, ValueError, r"^known_gaps: case must be Ref or 1..17, got 'Set 99'"),
])
def test_malformed_known_gaps_are_named(gaps: object, error: type, match: str) -> None:
    """Malformed ``known_gaps`` (a reason that is not a string, not a mapping, an unknown case) raise at once,
    naming the entry."""
    with pytest.raises(error, match=match):
        paper_cases("7", known_gaps=gaps)  # type: ignore[arg-type]


def test_select_cases_of_a_non_string_is_named() -> None:
    with pytest.raises(TypeError, match=r"^--xcheck-cases must be a comma-separated string"):
        select_cases(None)  # type: ignore[arg-type]


@pytest.mark.parametrize("m", ['"1/0"', '"x"', '"1/"', '"1e999999/1"'])
def test_a_walls_file_fraction_that_is_no_number_is_named(tmp_path: Path, m: str) -> None:
    """A walls file with ``m = "1/0"`` (or another fraction that is no number) is refused naming the wall and
    the key."""
    path = tmp_path / "w.toml"
    path.write_text(f'[[wall]]\nname = "a"\nt = 1\nm = {m}\nrows = 12\nf = 0.75\n')
    with pytest.raises(ValueError, match=r"w.toml: wall\[0\] \(a\): m must (be a number or a fraction such as "
                                         r"\"1/3\", got|be in \(0, 1\])"):
        walls_from_file(path)


def test_a_walls_file_with_arrays_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "w.toml"
    path.write_text('[[wall]]\nname = "a"\nt = [1, 2]\nm = 0.5\nrows = 12\nf = 0.75\n')
    with pytest.raises(ValueError, match=r"w.toml: wall\[0\] \(a\): t must be one number"):
        walls_from_file(path)


def test_a_table_that_cannot_be_written_leaves_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    table = ComparisonTable(REFS)
    table.add("Set 11", 0.7, "mine")
    path = tmp_path / "t.md"
    path.write_text("old\n")

    def read_only(self: Path, *args: object, **kwargs: object) -> int:
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(Path, "write_text", read_only)
    with pytest.raises(OSError, match="Read-only file system"):
        table.write(path)
    monkeypatch.undo()
    assert path.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["t.md"]
    table.write(path)
    assert path.read_text().startswith("| wall | method | λ |")


TEST_FILE = """
import pytest
from comparison.pytest_plugin import paper_cases

def test_one(xcheck_table):
    xcheck_table.add("Set 11", 0.7, "mine")
"""

READ_ONLY = """
import errno, os
from pathlib import Path

def _refuse(self, *args, **kwargs):
    raise OSError(errno.EROFS, os.strerror(errno.EROFS))

Path.write_text = _refuse
"""


def _pytest(pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch, *args: str, conftest: str = "") -> Run:
    """A downstream run of :data:`TEST_FILE` in ``pytester.path``: in this process, or with a ``conftest`` (one
    that patches the interpreter for good) in a process of its own (``downstream.py``)."""
    (pytester.path / "test_down.py").write_text(TEST_FILE)
    if conftest:
        (pytester.path / "conftest.py").write_text(conftest)
        return in_a_process(pytester.path, *args)
    return in_this_process(pytester, monkeypatch, *args)


@pytest.mark.parametrize(("args", "line"), [
    (("--xcheck-table", "missing/t.md"), "ERROR: --xcheck-table: the folder of 'missing/t.md' does not exist"),
    (("--xcheck-table", "."), "ERROR: --xcheck-table: '.' is a directory; name a file (.md or .csv)"),
    (("--xcheck-table", ""), "ERROR: --xcheck-table: must name a file (.md or .csv), got ''"),
    (("--xcheck-against", "bogus"), "ERROR: --xcheck-against: bogus not among paper, macro, orduna-micro"),
    (("--xcheck-against", ","), "ERROR: --xcheck-against: no method given; the methods are paper, macro"),
])
def test_plugin_options_are_checked_before_the_tests(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch, args: tuple[str, ...], line: str
) -> None:
    """The plugin's options are checked before any test runs, each refused in one usage-error line: an
    unknown ``--xcheck-against`` method, a table into a missing folder, a directory or an empty name."""
    run = _pytest(pytester, monkeypatch, *args)
    assert run.returncode == 4 and run.stderr.startswith(line) and "Traceback" not in run.stderr, run.stderr


@pytest.mark.parametrize("where", ["full", "read-only"])
def test_a_table_on_a_full_or_read_only_disk_is_one_line_and_a_failed_run(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch, where: str
) -> None:
    """``--xcheck-table`` on ``/dev/full`` or a read-only disk: a traceback (``OSError``) after the tests, exit 0."""
    if where == "full" and not Path("/dev/full").exists():
        pytest.skip("no /dev/full")
    path = "/dev/full" if where == "full" else "t.md"
    tmp_path = pytester.path
    run = _pytest(pytester, monkeypatch, "--xcheck-table", path, conftest=READ_ONLY if where == "read-only" else "")
    reason = "No space left on device" if where == "full" else "Read-only file system"
    assert run.returncode == 1, run.stdout + run.stderr
    assert f"xcheck: error: cannot write the table to {path} ({reason})" in run.stdout, run.stdout
    assert "Traceback" not in run.stdout + run.stderr and "INTERNALERROR" not in run.stdout + run.stderr
    assert "1 passed" in run.stdout and not (tmp_path / "t.md").exists()


def test_a_known_gap_without_a_reason_is_a_collection_error_not_an_internal_error(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch
) -> None:
    (pytester.path / "test_gap.py").write_text(
        "import pytest\nfrom comparison.pytest_plugin import paper_cases\n\n"
        "@pytest.mark.parametrize('case', paper_cases('7', known_gaps={'Set 11': None}))\n"
        "def test_k(case):\n    pass\n"
    )
    run = _pytest(pytester, monkeypatch, "test_gap.py")
    assert run.returncode == 2 and "INTERNALERROR" not in run.stdout + run.stderr, run.stdout
    assert "known_gaps['Set 11'] must be the reason, a string, got None" in run.stdout


def _damaged(how: str) -> str:
    """The shipped references.json damaged as ``how`` says."""
    text = (Path(references_module.__file__).parent / "references.json").read_text()
    data = json.loads(text)
    cell = next(c for c in data["cells"] if c["case"] == "Set 12" and c["method"] == "orduna-micro")
    if how in ("NaN", "Infinity", "1e308"):
        cell["tolerance"] = float(how) if how != "1e308" else 1e308
        return json.dumps(data)
    if how == "truncated":
        return text[: len(text) // 2]
    if how == "empty":
        return ""
    if how == "no value":
        del cell["value"]
        return json.dumps(data)
    assert how == "no cells"
    return json.dumps({"meta": data["meta"]})


@pytest.mark.parametrize("how", ["NaN", "Infinity", "1e308", "truncated", "empty", "no value", "no cells"])
def test_damaged_references_are_refused_in_one_line(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch, how: str
) -> None:
    """A references file with a tolerance that would pass any value near it (NaN, infinite, 1e308 for a value
    of 0.68), or one that is truncated, empty, has a cell without ``value`` or no cells, is refused: by
    ``References.load`` naming the file and the cell, and by the plugin as a usage error of one line (exit
    4) before any test runs."""
    path = pytester.path / "references.json"
    path.write_text(_damaged(how))
    with pytest.raises(BadReferences, match=rf"^{re.escape(str(path))}: "):
        References.load(path)
    if how not in ("NaN", "truncated"):  # the plugin reads the file through References.load: two runs show it
        return
    monkeypatch.setattr(references_module, "shipped", lambda: path)
    run = _pytest(pytester, monkeypatch)
    assert run.returncode == 4, run.stdout + run.stderr
    assert run.stderr.startswith(f"ERROR: the plugin's references: {path}: "), run.stderr
    assert "INTERNALERROR" not in run.stdout + run.stderr and "Traceback" not in run.stdout + run.stderr


def test_a_walls_file_nested_too_deep_is_a_usage_error(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``a = [[[...]]]`` 1,500 deep in a ``--xcheck-walls`` file: one usage-error line, exit 4."""
    (pytester.path / "w.toml").write_text("a = " + "[" * 1500 + "1" + "]" * 1500 + "\n")
    run = _pytest(pytester, monkeypatch, "--xcheck-walls", "w.toml")
    assert run.returncode == 4 and "INTERNALERROR" not in run.stdout + run.stderr, run.stdout + run.stderr
    assert run.stderr.startswith("ERROR: ") and "w.toml: malformed TOML: arrays or tables nested too deep" in run.stderr


@pytest.mark.parametrize("selection", [",", " , ,"])
def test_a_selection_of_no_wall_is_a_usage_error(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch, selection: str
) -> None:
    """``--xcheck-cases ","`` selects no wall: a usage error, exit 4."""
    run = _pytest(pytester, monkeypatch, "--xcheck-cases", selection)
    assert run.returncode == 4, run.stdout + run.stderr
    assert run.stderr.startswith(f"ERROR: --xcheck-cases: no wall selected by {selection!r}"), run.stderr
