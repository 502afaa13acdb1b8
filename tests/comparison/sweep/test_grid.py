"""Grid files: the documented format parses; a malformed one is one line naming the key (exit 2)."""

from __future__ import annotations

import re
import sys
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.runner import MACRO, MICRO_ASSOC, MICRO_NONASSOC
from comparison.sweep import GridError, cells, load_grid, parse_grid
from comparison.sweep.plan import wall_points

ROOT = Path(__file__).resolve().parents[3]

GOOD = """
name = "g"
[axes]
t = [1.0, 2.0]
m = ["1/3", 1]
rows = { from = 12, to = 24, step = 6 }
f = 0.6
storeys = [1, 4]
[bond]
first_course = ["full", "half"]
[limits]
max_blocks = 100
[[method]]
kind = "macro"
[[method]]
kind = "micro-assoc"
solver = "clarabel"
[[method]]
kind = "micro-nonassoc"
max_blocks = 50
"""


def test_a_grid_expands_to_its_cells() -> None:
    g = parse_grid(GOOD)
    assert g.name == "g" and g.axes["rows"] == (12, 18, 24) and g.axes["m"] == (1 / 3, 1.0)
    assert g.axes["p"] == (0.0,) and g.axes["storeys"] == (1, 4)
    assert [m.method for m in g.methods] == [MACRO, replace(MICRO_ASSOC, solver="clarabel"), MICRO_NONASSOC]
    cs = cells(g)
    walls = 2 * 2 * 3 * 2
    assert len(cs) == walls * (1 + 2 + 2) and [c.index for c in cs] == list(range(len(cs)))
    # 18 rows do not split over 4 storeys: every method's cell says so
    odd = [c for c in cs if c.point.rows == 18 and c.point.storeys == 4]
    assert odd and all(c.skip == "not_applicable" and "storeys" in c.message for c in odd)
    # the nonassoc limit is the smaller of the grid's and its own
    na = [c for c in cs if c.method.kind == "micro-nonassoc" and not c.skip]
    assert na and all(c.blocks <= 50 for c in na)
    assert any(c.skip == "not_run" and c.method.kind == "micro-nonassoc" and c.blocks <= 100 for c in cs)
    # the associative LP runs on the walls above the grid's limit too (its bound can settle their verdict)
    big = [c for c in cs if c.method.kind == "micro-assoc" and c.blocks > 100]
    assert big and all(c.skip == "" for c in big)
    own = cells(parse_grid(GOOD.replace('solver = "clarabel"', 'solver = "clarabel"\nmax_blocks = 60')))
    assert all(c.skip == "not_run" for c in own if c.method.kind == "micro-assoc" and c.blocks > 60)


def test_points_that_make_no_wall_are_skipped_with_the_reason() -> None:
    """t = 3 with m = 1/3 and 6 rows is a wall shorter than one block (o m = 2 < t): outside the physical
    bounds, so every method's cell of it is not_applicable with the wall check's message; the rest run."""
    text = GOOD.replace("t = [1.0, 2.0]", "t = [1.0, 3.0]").replace("{ from = 12, to = 24, step = 6 }", "6")
    g = parse_grid(text.replace("storeys = [1, 4]", "storeys = [1, 2]"))
    cs = cells(g)
    short = [c for c in cs if c.point.t == 3.0 and c.point.m < 1]
    assert short and all(c.skip == "not_applicable" and "one block long" in c.message for c in short)
    assert all(not c.skip for c in cs if not (c.point.t == 3.0 and c.point.m < 1) and c.method.kind == "macro")


def test_the_example_grids_parse() -> None:
    for path in sorted((ROOT / "examples" / "sweeps").glob("*.toml")):
        assert cells(load_grid(path)), path


def test_the_nonassociative_selection_of_a_sweep() -> None:
    """A sweep's iterated LP runs the library's method unless the grid names a scheme or a selection,
    which become the method's tuning (only where they differ from the library's)."""
    assert MICRO_NONASSOC.tuning == () and MICRO_NONASSOC.nonassoc_tuning().resolved_selection == "vertex+proximal"
    g = parse_grid(GOOD.replace("max_blocks = 50", 'selection = "vertex"'))
    assert g.methods[-1].method == replace(MICRO_NONASSOC, tuning=(("selection", "vertex"),))
    g = parse_grid(GOOD.replace("max_blocks = 50", 'selection = "vertex+proximal"'))
    assert g.methods[-1].method == MICRO_NONASSOC  # the library's own: the report's cache entries
    g = parse_grid(GOOD.replace("max_blocks = 50", 'scheme = "b"'))
    scheme_b = replace(MICRO_NONASSOC, tuning=(("scheme", "b"),))
    assert g.methods[-1].method == scheme_b and scheme_b.nonassoc_tuning().resolved_selection == "vertex"
    assert "tuning" not in MICRO_ASSOC.key() and MICRO_NONASSOC.key()["tuning"] == []
    assert MICRO_NONASSOC.label == "micro-nonassoc (scheme a)" and scheme_b.label == "micro-nonassoc (scheme b)"
    proximal = replace(MICRO_NONASSOC, tuning=(("selection", "proximal"),))
    assert proximal.label == "micro-nonassoc (scheme a, proximal selection)"


def test_a_range_by_count() -> None:
    g = parse_grid(GOOD.replace("{ from = 12, to = 24, step = 6 }", "{ from = 12, to = 24, num = 3 }"))
    assert g.axes["rows"] == (12, 18, 24)


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (("t = [1.0, 2.0]", "t = [1.0, -2.0]"), ["line 4", "axes.t", "t must be a positive number, got -2.0"]),
        (("m = [", "mm = ["), ["line 5", "unknown key axes.mm"]),
        (('m = ["1/3", 1]', 'm = ["1/x", 1]'), ["axes.m", "fraction"]),
        (("m = [", "q = 1\nm = ["), ["unknown key axes.q"]),
        (("f = 0.6\n", ""), ["missing key axes.f"]),
        (("step = 6", "stride = 6"), ["axes.rows", "range"]),
        # issue 41: OverflowError (cannot convert float infinity to integer) in the count of the range
        (("step = 6", "step = 5e-324"), ["axes.rows", "the range gives more than 10000 values (step = 4.94066e-324)"]),
        (("from = 12, to = 24, step = 6", "from = 24, to = 12, step = 5e-324"),
         ["axes.rows", "from must not exceed to, got from = 24, to = 12"]),
        (('solver = "clarabel"', 'solver = "gurobi"'), ["line 17", "method.solver", "gurobi"]),
        (('kind = "micro-nonassoc"', 'kind = "micro-magic"'), ["line 19", "method.kind"]),
        (("max_blocks = 50", "max_blocks = 0"), ["line 20", "max_blocks must be a positive integer"]),
        (("max_blocks = 50", 'selection = "closest"'), ["line 20", "method.selection", "closest"]),
        (("max_blocks = 50", 'scheme = "b"\nselection = "proximal"'),
         ["line 21", "method.selection 'proximal' needs scheme 'a'"]),
        (('first_course = ["full", "half"]', 'first_course = "middle"'), ["bond.first_course", "middle"]),
        (('[[method]]\nkind = "macro"', '[[method]]\nkind = "macro"\nsolver = "x"'), ["unknown key method.solver"]),
        (("name = \"g\"", "name = \"g\"\nspeed = 1"), ["unknown key 'speed'"]),
        (("name = \"g\"", "name = \"a b\""), ["line 2", "name must be letters"]),
        (("rows = {", "rows = [{"), ["malformed TOML"]),
    ],
)
def test_a_malformed_grid_is_one_line_naming_the_key_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], edit: tuple[str, str], words: list[str]
) -> None:
    text = GOOD.replace(*edit)
    assert text != GOOD
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(GridError):
        load_grid(path)
    assert main(["sweep", str(path), "--out", str(tmp_path / "out"), "--cache", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("xcheck: error: grid ") and str(path) in err, err
    for w in words:
        assert w in err, (w, err)
    assert not (tmp_path / "out").exists()


USER = GOOD + """[[method]]
kind = "user"
name = "mine"
function = "mine:lam"
"""


def test_a_user_model_is_found_beside_the_grid_and_runs_once_per_wall(tmp_path: Path) -> None:
    (tmp_path / "mine.py").write_text("def lam(t, m, rows, f, p, storeys):\n    return min(f, 1 / t) / 2\n")
    (tmp_path / "g.toml").write_text(USER)
    g = load_grid(tmp_path / "g.toml")
    user = g.methods[-1].method
    assert user.kind == "user" and user.label == "mine" and user.key() == {"kind": "user", "name": "mine",
                                                                          "function": "mine:lam"}
    cs = cells(g)
    mine = [c for c in cs if c.method.label == "mine"]
    assert len(mine) == 2 * 2 * 3 * 2 and all(c.spec is None and not c.micro and c.item is None for c in mine)
    assert user.evaluate(2.0, 1 / 3, 12, 0.6, 0.0, 1)[:3] == (0.25, "optimal", "")  # type: ignore[union-attr]
    assert str(tmp_path) not in sys.path  # the grid's folder is on the path only to import the model


def test_what_a_user_model_gives_becomes_its_cells_status() -> None:
    """The plugin's convention: a real number is the value; NaN or infinite is ``failed``; a string, None or
    an exception is ``error`` with a message naming the wall and the model, never a number."""
    from comparison.sweep.usermodel import UserModel

    def model(value: object) -> UserModel:
        def fn(t: float, m: float, rows: int, f: float, p: float, storeys: int) -> object:
            if value == "raise":
                raise ZeroDivisionError("no")
            return value
        return UserModel("m", fn)

    assert model(0.5).evaluate(1, 1, 6, 0.6, 0, 1, "w")[:3] == (0.5, "optimal", "")
    lam, status, message, _ = model(float("nan")).evaluate(1, 1, 6, 0.6, 0, 1, "w")
    assert status == "failed" and "nan" in message
    assert model("0.5").evaluate(1, 1, 6, 0.6, 0, 1, "wall 7")[1:3] == (
        "error", "wall 7 / m needs a number, got '0.5' (str)")
    lam, status, message, _ = model("raise").evaluate(1, 1, 6, 0.6, 0, 1, "w")
    assert status == "error" and message.startswith("ZeroDivisionError: no") and lam != lam


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (('function = "mine2:lam"\n', ""), ["line 21", "method.function is missing"]),
        (("mine2:lam", "nosuchmodule_i43:lam"), ["line 24", "cannot import 'nosuchmodule_i43'", "ModuleNotFound"]),
        (("mine2:lam", "mine2:nothing"), ["line 24", "mine2 has no 'nothing'"]),
        (("mine2:lam", "mine2:VALUE"), ["line 24", "is not callable (float)"]),
        (("mine2:lam", "mine2"), ["line 24", "function must be 'module:function', got 'mine2'"]),
        (("mine2:lam", "broken:lam"), ["line 24", "cannot import 'broken'", "SyntaxError"]),
        (('name = "mine"', 'name = "macro"'), ["line 23", "the name 'macro' is another method's"]),
        (('name = "mine"', 'name = "a|b"'), ["line 23", "name must be a non-empty text"]),
    ],
)
def test_a_bad_user_model_is_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], edit: tuple[str, str], words: list[str]
) -> None:
    # modules of names of their own: Python keeps a module imported once (another test's mine.py)
    (tmp_path / "mine2.py").write_text("VALUE = 0.5\ndef lam(t, m, rows, f, p, storeys):\n    return 0.5\n")
    (tmp_path / "broken.py").write_text("def lam(:\n")
    path = tmp_path / "bad.toml"
    base = USER.replace("mine:", "mine2:")
    text = base.replace(*edit)
    assert text != base
    path.write_text(text)
    assert main(["sweep", str(path), "--out", str(tmp_path / "out"), "--cache", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"xcheck: error: grid {path}"), err
    for w in words:
        assert w in err, (w, err)
    assert not (tmp_path / "out").exists()


def test_missing_grid_file_and_bad_options(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["sweep", str(tmp_path / "none.toml"), "--out", str(tmp_path)]) == 2
    assert "cannot read" in capsys.readouterr().err
    good = tmp_path / "g.toml"
    good.write_text(GOOD)
    for extra, word in (
        (["--workers", "0"], "--workers must be a positive integer"),
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "exclude each other"),
        (["--scheduler", "127.0.0.1:8786"], "--scheduler must be an address"),
        (["--worker-memory", "-1"], "--worker-memory must be a positive number"),
    ):
        assert main(["sweep", str(good), "--out", str(tmp_path / "o"), *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and word in err, err
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    assert main(["sweep", str(good), "--out", str(blocker / "out")]) == 2
    assert "--out: cannot write to" in capsys.readouterr().err


def test_a_grid_above_the_cell_limit_is_refused_before_it_is_built(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Issue 31, item 2: 10,000 x 10,000 walls were planned in memory (5 GB, then a MemoryError traceback);
    the grid is now counted, not built, and refused in one line with exit 2."""
    from comparison.sweep.grid import MAX_CELLS, cell_count

    path = tmp_path / "huge.toml"
    path.write_text(
        "[axes]\nt = { from = 1, to = 2, num = 10000 }\nm = { from = 0.1, to = 1, num = 10000 }\nrows = 12\n"
        'f = 0.6\n[[method]]\nkind = "macro"\n'
    )
    with pytest.raises(GridError, match=r"100,000,000 cells \(10,000 t x 10,000 m walls, 1 per wall\), more than "
                       r"the 100,000 a sweep may have"):
        load_grid(path)
    assert main(["sweep", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("xcheck: error: grid ") and "split it" in err, err
    assert not (tmp_path / "out").exists()
    # the count is every wall times one per macro method and one per bond of each micro method; at the
    # limit a grid is still read
    small = parse_grid(GOOD)
    assert cell_count(small) == len(cells(small)) == 2 * 2 * 3 * 2 * (1 + 2 + 2)
    per_t = 2 * 3 * 2 * 5  # cells per value of t
    most = GOOD.replace("t = [1.0, 2.0]", f"t = {{ from = 1, to = 2, num = {MAX_CELLS // per_t} }}")
    assert cell_count(parse_grid(most)) == MAX_CELLS // per_t * per_t <= MAX_CELLS
    with pytest.raises(GridError, match="more than the 100,000"):
        parse_grid(GOOD.replace("t = [1.0, 2.0]", f"t = {{ from = 1, to = 2, num = {MAX_CELLS // per_t + 1} }}"))


@pytest.mark.parametrize(
    "address",
    ["tcp://127.0.0.1:abc", "http://127.0.0.1:8786", "tcp://:8786", "tcp://127.0.0.1:99999", "tcp://127.0.0.1"],
)
def test_a_bad_scheduler_address_is_refused_before_connecting(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], address: str
) -> None:
    """Issue 31, item 3: these waited for the connection's time-out (about 40 s), then a traceback and exit 1."""
    from comparison.cli.options import scheduler_address

    good = tmp_path / "g.toml"
    good.write_text(GOOD)
    assert main(["sweep", str(good), "--out", str(tmp_path / "o"), "--scheduler", address]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--scheduler must be an address SCHEME://HOST:PORT" in err and address in err
    assert scheduler_address(" tcp://127.0.0.1:8786 ") == "tcp://127.0.0.1:8786"
    assert scheduler_address("tls://scheduler.example:8786") == "tls://scheduler.example:8786"


def test_more_workers_than_cpus_are_capped_with_a_warning(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Issue 31, item 6: ``--workers 100000`` split the memory 100,000 ways and every micro cell was refused
    (``exceeds a worker's 0 GB``); it is capped at the CPU count, with a warning."""
    monkeypatch.setattr("os.cpu_count", lambda: 2)
    seen: list[int | None] = []

    def fake_make_executor(workers: int | None, scheduler: str | None, memory: int | None) -> object:
        seen.append(workers)
        raise KeyboardInterrupt  # stop before any work

    monkeypatch.setattr("comparison.runner.executor.make_executor", fake_make_executor)
    grid = ROOT / "examples" / "sweeps" / "tiny.toml"
    for workers in ("100000", "2", "1"):
        argv = ["sweep", str(grid), "--out", str(tmp_path / "o"), "--cache", str(tmp_path / "c"), "--workers", workers]
        assert main(argv) == 130
        err = capsys.readouterr().err
        assert ("xcheck: warning: --workers 100000: this machine has 2 CPUs; using 2 workers" in err) is (
            workers == "100000"
        ), err
    assert seen == [2, 2, 1]


def test_the_tiny_grid_is_what_its_comment_says() -> None:
    """Issue 31, item 12: the comment described walls (one of 12 rows) that the grid does not build."""
    path = ROOT / "examples" / "sweeps" / "tiny.toml"
    comment = " ".join(line.lstrip("# ") for line in path.read_text().splitlines() if line.startswith("#"))
    grid = load_grid(path)
    walls = wall_points(grid)
    match = re.search(r"(\d+) walls of (\d+) rows in one storey \(t = ([\d., ]+) times m = ([\d/, ]+)\)", comment)
    assert match, comment
    assert int(match[1]) == len(walls) and {int(match[2])} == {w.rows for w in walls} == set(grid.axes["rows"])
    assert {w.storeys for w in walls} == {1}
    assert [float(x) for x in match[3].split(", ")] == list(grid.axes["t"])
    assert [float(Fraction(x)) for x in match[4].split(", ")] == list(grid.axes["m"])
    assert f"{len(cells(grid))} cells" in comment
