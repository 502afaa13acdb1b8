"""A grid's user model cannot end the sweep, move its outputs or write to its standard output, and runs no
code for a grid that is refused; bad input to ``xcheck sweep`` creates no folder.

Each model here lives in a module of its own name (Python imports a module once per process).
"""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.sweep import load_grid, read_table
from comparison.sweep.grid import MAX_NAME_LENGTH, GridError
from comparison.sweep.usermodel import MAX_LOAD_FACTOR, UserModel

#: Two walls (t = 1 and t = 2), the macro model and a user model ``{module}:lam``: no micro cell.
GRID = """name = "{name}"
[axes]
t = [1.0, 2.0]
m = 1
rows = 6
f = 0.75

[[method]]
kind = "macro"

[[method]]
kind = "user"
name = "mine"
function = "{module}:lam"
"""


def _macro_only(name: str) -> str:
    """:data:`GRID` without its user model."""
    return GRID.format(name=name, module="unused").split('[[method]]\nkind = "user"')[0]


def _grid(tmp_path: Path, module: str, body: str, name: str = "u") -> Path:
    (tmp_path / f"{module}.py").write_text(body)
    path = tmp_path / f"{name}.toml"
    path.write_text(GRID.format(name=name, module=module))
    return path


def _sweep(grid: Path, out: Path | str, cache: Path | str, *extra: str) -> int:
    return main(["sweep", str(grid), "--out", str(out), "--cache", str(cache), "-q", *extra])


@pytest.mark.parametrize(("call", "words"), [
    ("sys.exit(0)", "the model called sys.exit(0)"),
    ("sys.exit(3)", "the model called sys.exit(3)"),
    ("raise BaseException('gone')", "BaseException: gone"),
    ("raise GeneratorExit()", "GeneratorExit"),
])
def test_a_user_model_that_exits_is_an_error_cell_and_the_sweep_goes_on(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], call: str, words: str
) -> None:
    """A model that calls ``sys.exit`` or raises a ``BaseException`` gives an ``error`` cell; the other cells
    and the page are written, exit 1."""
    module = f"exits_{abs(hash(call))}"
    body = f"import sys\ndef lam(t, m, rows, f, p, storeys):\n    if t > 1:\n        {call}\n    return 0.3\n"
    grid = _grid(tmp_path, module, body)
    code = _sweep(grid, tmp_path / "out", tmp_path / "cache")
    out = capsys.readouterr().out
    assert code == 1 and out.splitlines()[-1] == f"page: {tmp_path / 'out' / 'u.md'}"
    mine = {r["t"]: r for r in read_table(tmp_path / "out" / "u.csv") if r["method"] == "mine"}
    assert mine["1.0"]["status"] == "optimal" and mine["1.0"]["load_factor"] == "0.3"
    assert mine["2.0"]["status"] == "error" and words in mine["2.0"]["message"]
    assert (tmp_path / "out" / "u.md").is_file()


def test_ctrl_c_in_a_user_model_still_interrupts() -> None:
    def interrupted(t: float, m: float, rows: int, f: float, p: float, storeys: int) -> float:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        UserModel("m", interrupted).evaluate(1, 1, 6, 0.6, 0, 1)


@pytest.mark.parametrize("value", [0, 0.0, -0.5, -5, 1e308, 10**400, -(10**400), math.inf, MAX_LOAD_FACTOR * 2],
                         ids=["0", "0.0", "-0.5", "-5", "1e308", "10**400", "-10**400", "inf", "twice the bound"])
def test_a_number_that_is_not_a_load_factor_is_a_failed_cell(value: object) -> None:
    """Zero, a negative number, NaN, an infinity or a number above ``MAX_LOAD_FACTOR`` (``10**400`` too) is a
    ``failed`` cell, never a value the page compares."""
    lam, status, message, _ = UserModel("m", lambda *a: value).evaluate(1, 1, 6, 0.6, 0, 1, "w")
    assert status == "failed" and math.isnan(lam)
    assert "not a load factor (a positive number at most 1e+06)" in message
    assert len(message) < 150  # 10**400 by its size, not its 401 digits
    if isinstance(value, int) and abs(value) > 10**300:
        assert "an integer of 401 digits" in message


def test_the_largest_load_factor_is_accepted() -> None:
    assert UserModel("m", lambda *a: MAX_LOAD_FACTOR).evaluate(1, 1, 6, 0.6, 0, 1)[:2] == (MAX_LOAD_FACTOR, "optimal")


def test_what_a_user_model_prints_goes_to_standard_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """What a model prints goes to standard error; standard output holds the paths written, under ``-q`` too."""
    body = "print('LOADING')\ndef lam(t, m, rows, f, p, storeys):\n    print('CALLED', t)\n    return 0.3\n"
    grid = _grid(tmp_path, "prints_u", body)
    assert _sweep(grid, tmp_path / "out", tmp_path / "cache") == 0
    out, err = capsys.readouterr()
    assert out.splitlines() == [f"{k}: {tmp_path / 'out' / f'u.{ext}'}" for k, ext in
                                (("table", "csv"), ("meta", "json"), ("page", "md"))]
    assert "LOADING" in err and "CALLED 1.0" in err and "CALLED 2.0" in err


def test_a_user_model_that_changes_directory_moves_no_output(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A model calling ``os.chdir("/")`` moves no output, even with a relative ``--out``: the folders are
    absolute before any user code runs, and the working directory is restored."""
    body = "import os\nos.chdir('/')\ndef lam(t, m, rows, f, p, storeys):\n    os.chdir('/')\n    return 0.3\n"
    grid = _grid(tmp_path, "chdir_u", body, name="chdir-u-i50")
    monkeypatch.chdir(tmp_path)
    assert _sweep(grid, "out", "cache") == 0
    assert Path.cwd() == tmp_path
    assert (tmp_path / "out" / "chdir-u-i50.csv").is_file() and not Path("/chdir-u-i50.csv").exists()


#: A model whose import leaves a file beside it.
MARKER = ("import pathlib\npathlib.Path(__file__).with_name('imported').write_text('yes')\n"
          "def lam(*a):\n    return 0.3\n")


#: Grids refused for what follows their user model: a later method, the cell count, a name taken twice.
AFTER_THE_MODEL = {
    "a later method": ("", '\n[[method]]\nkind = "nosuch"\n'),
    "too many cells": ("t = [1.0, 2.0]\nm = 1\nrows = 6", "t = { from = 1, to = 2, num = 10000 }\nm = 1\n"
                                                           "rows = { from = 6, to = 600, step = 6 }"),
    "a name twice": ("", '\n[[method]]\nkind = "user"\nname = "mine"\nfunction = "marker_u:lam"\n'),
}


@pytest.mark.parametrize("bad", list(AFTER_THE_MODEL))
def test_a_refused_grid_imports_no_user_model(tmp_path: Path, capsys: pytest.CaptureFixture[str], bad: str) -> None:
    """A grid refused for any reason imports no user model (its module's top-level code does not run)."""
    grid = _grid(tmp_path, "marker_u", MARKER)
    old, new = AFTER_THE_MODEL[bad]
    text = grid.read_text()
    grid.write_text(text.replace(old, new) if old else text + new)
    assert _sweep(grid, tmp_path / "out", tmp_path / "cache") == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "imported").exists() and "marker_u" not in sys.modules
    assert not (tmp_path / "out").exists() and not (tmp_path / "cache").exists()


def test_a_function_that_is_not_a_python_name_is_refused_unimported(tmp_path: Path) -> None:
    grid = _grid(tmp_path, "marker_v", MARKER)
    grid.write_text(grid.read_text().replace("marker_v:lam", "marker_v:lam()"))
    rule = r"line 14\): method.function must be 'module:function', got 'marker_v:lam\(\)'"
    with pytest.raises(GridError, match=rule):
        load_grid(grid)
    assert not (tmp_path / "imported").exists()


@pytest.mark.parametrize("name", ["x" * 300, "x" * (MAX_NAME_LENGTH + 1), ".", "..", ".hidden", "-q", "a/b", ""])
def test_a_grid_name_that_is_not_a_safe_file_stem_is_refused_when_read(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str
) -> None:
    """A grid name that is not a safe file stem (300 characters, ``"."``) is refused when the grid is read,
    before any computation."""
    grid = tmp_path / "g.toml"
    grid.write_text(_macro_only(name))
    assert _sweep(grid, tmp_path / "out", tmp_path / "cache") == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"grid {grid} (line 1): name must be letters" in err, err
    assert not (tmp_path / "out").exists()


def test_the_longest_name_is_accepted(tmp_path: Path) -> None:
    grid = tmp_path / "g.toml"
    grid.write_text(_macro_only("x" * MAX_NAME_LENGTH))
    assert load_grid(grid).name == "x" * MAX_NAME_LENGTH


@pytest.mark.parametrize("command", ["sweep", "report"])
def test_a_scheduler_that_is_not_one_creates_no_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    """A ``--scheduler`` that is not one: exit 2, and no ``--out`` or cache folder made."""
    grid = _grid(tmp_path, "unused_w", "def lam(*a):\n    return 0.3\n")
    out, cache = tmp_path / "o" / "deeper", tmp_path / "c"
    first = [str(grid)] if command == "sweep" else ["--quick"]
    code = main([command, *first, "--out", str(out), "--cache", str(cache), "--scheduler", "http://x:1"])
    assert code == 2 and "--scheduler must be an address" in capsys.readouterr().err
    assert not (tmp_path / "o").exists() and not cache.exists()


@pytest.mark.parametrize(("call", "status", "words"), [
    ("os._exit(0)", "error", "the model ended its process (exit code 0)"),
    ("os.kill(os.getpid(), 9)", "error", "the model ended its process (killed by signal 9)"),
    ("os.fork()", "optimal", ""),
    ("sys.stdout.close()", "optimal", ""),
    ("os.close(1)", "optimal", ""),
])
def test_a_user_model_cannot_end_fork_or_silence_the_sweep(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], call: str, status: str, words: str
) -> None:
    """A model that calls ``os._exit``, is killed, forks or closes standard output runs in a process of its own:
    its cell says what happened, every cell and the page are written once, the paths printed once."""
    module = f"ends_{abs(hash(call))}"
    body = f"import os, sys\ndef lam(t, m, rows, f, p, storeys):\n    if t > 1:\n        {call}\n    return 0.3\n"
    grid = _grid(tmp_path, module, body)
    code = _sweep(grid, tmp_path / "out", tmp_path / "cache")
    out = capsys.readouterr().out
    assert code == (1 if status == "error" else 0)
    written = [f"{what}: {tmp_path / 'out' / f'u.{kind}'}" for what, kind in (("table", "csv"), ("meta", "json"),
                                                                              ("page", "md"))]
    assert out.splitlines() == written, out
    mine = {r["t"]: r for r in read_table(tmp_path / "out" / "u.csv") if r["method"] == "mine"}
    assert mine["1.0"]["status"] == "optimal" and mine["1.0"]["load_factor"] == "0.3"
    assert mine["2.0"]["status"] == status and words in mine["2.0"]["message"], mine["2.0"]
    assert (tmp_path / "out" / "u.md").is_file()


@pytest.mark.processes  # the console script in a process of its own: its descriptor 1 is a real pipe
@pytest.mark.parametrize("call", ["os.close(1)", "os.fork()", "os._exit(0)"])
def test_the_console_sweep_survives_a_model_that_closes_forks_or_exits(tmp_path: Path, call: str) -> None:
    """In a process of its own, the console's sweep prints its paths once and writes its page whatever a
    model does to its process (``os.close(1)``, ``os.fork()``, ``os._exit(0)``)."""
    import subprocess

    module = f"console_{abs(hash(call))}"
    body = f"import os, sys\ndef lam(t, m, rows, f, p, storeys):\n    if t > 1:\n        {call}\n    return 0.3\n"
    grid = _grid(tmp_path, module, body)
    root = Path(__file__).resolve().parents[3]  # this checkout's packages, whatever is installed
    run = subprocess.run([sys.executable, "-m", "comparison.cli", "sweep", str(grid), "--out", str(tmp_path / "out"),
                          "--cache", str(tmp_path / "cache"), "-q"], capture_output=True, text=True, timeout=300,
                         env={**os.environ, "PYTHONPATH": str(root)})
    written = [f"{what}: {tmp_path / 'out' / f'u.{kind}'}" for what, kind in (("table", "csv"), ("meta", "json"),
                                                                              ("page", "md"))]
    assert run.stdout.splitlines() == written, run.stdout + run.stderr
    assert run.returncode == (1 if call == "os._exit(0)" else 0) and "Traceback" not in run.stderr, run.stderr
