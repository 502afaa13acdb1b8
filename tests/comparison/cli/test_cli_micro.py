"""``xcheck micro``: JSON output, plot, one-line errors with exit code 2."""

from __future__ import annotations

import argparse
import json

import pytest

from comparison.cli import app as cli
from comparison.cli import micro as cmd_micro


@pytest.fixture(autouse=True)
def _micro_only_parser(monkeypatch: pytest.MonkeyPatch) -> None:
    """Register only ``micro`` so the test does not depend on the other commands."""

    def build() -> argparse.ArgumentParser:
        parser = cli.Parser(prog="xcheck")
        sub = parser.add_subparsers(dest="command", required=True, parser_class=cli.Parser)
        cmd_micro.register(sub)
        return parser

    monkeypatch.setattr(cli, "build_parser", build)


WALL = ["--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75"]


def test_json(capsys: pytest.CaptureFixture[str]) -> None:
    rc = cli.main(["micro", *WALL, "--friction", "associative", "--solver", "clarabel", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0
    for key in ("load_factor", "status", "solver", "direction", "blocks", "contacts", "solve_seconds", "build_seconds"):
        assert key in out
    assert out["status"] == "optimal" and out["blocks"] == 54 and out["solver"] == "clarabel"
    assert out["load_factor"] == pytest.approx(0.712047, abs=1e-5)


def test_no_solver_named_runs_the_library_default(capsys: pytest.CaptureFixture[str]) -> None:
    import micro

    rc = cli.main(["micro", *WALL, "--friction", "associative", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["solver"] == micro.DEFAULT_SOLVER
    assert out["load_factor"] == pytest.approx(0.712047, abs=1e-5)


def test_text_and_plot(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:  # type: ignore[no-untyped-def]
    png = tmp_path / "m.png"
    rc = cli.main(["micro", *WALL, "--first-course", "half", "--head-joints", "frictionless", "--plot", str(png)])
    assert rc == 0
    assert "lambda = " in capsys.readouterr().out
    assert png.stat().st_size > 1000


@pytest.mark.parametrize(
    ("extra", "word"),
    [
        (["--friction", "non-associative"], "--friction"),
        (["--solver", "gurobi"], "--solver"),
        (["--first-course", "middle"], "--first-course"),
        (["--head-joints", "sticky"], "--head-joints"),
        (["--plot", "m.txt"], "--plot"),
        (["--time-limit", "soon"], "--time-limit"),
    ],
)
def test_bad_input_one_line_exit_2(extra: list[str], word: str, capsys: pytest.CaptureFixture[str]) -> None:
    rc = cli.main(["micro", *WALL, *extra])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.startswith("xcheck: error:") and word in err and err.count("\n") == 1


@pytest.mark.parametrize("friction", ["associative", "nonassociative"])
def test_a_plot_into_a_missing_folder_is_refused_before_solving(
    friction: str, tmp_path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]  # type: ignore[no-untyped-def]
) -> None:
    """The README's example once ran its minutes of LPs, then failed on ``--plot out/x.png`` without ``out/``."""
    import micro

    def never(*args: object, **kwargs: object) -> None:
        raise AssertionError("solved before the bad --plot was refused")

    monkeypatch.setattr(micro, "solve_associative", never)
    monkeypatch.setattr(micro, "solve_nonassociative", never)
    plot = str(tmp_path / "missing" / "mechanism.png")
    rc = cli.main(["micro", *WALL, "--friction", friction, "--plot", plot])
    err = capsys.readouterr().err
    assert rc == 2 and "--plot" in err and "does not exist" in err and err.count("\n") == 1


def test_bad_wall_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    rc = cli.main(["micro", "--t", "30", "--m", "1", "--rows", "12", "--f", "0.75"])  # L = 0.4 < l = 1
    err = capsys.readouterr().err
    assert rc == 2 and "t must be in" in err and "one block long" in err and err.count("\n") == 1


@pytest.mark.processes  # a fresh process's standard output, descriptor 1
def test_json_stdout_of_a_real_process_is_one_json_line() -> None:
    """In a fresh process (where HiGHS builds its first instance) stdout is
    the JSON line alone: highspy 1.16 prints a banner on descriptor 1 when its
    first instance is built, which ``capsys`` does not see."""
    import subprocess
    import sys

    code = "import sys; from comparison.cli import main; sys.exit(main(sys.argv[1:]))"
    args = ["micro", *WALL, "--friction", "nonassociative", "--no-lowest", "--json"]
    p = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) == 1, p.stdout[:300]
    assert json.loads(lines[0])["status"] == "converged"


@pytest.mark.parametrize(("friction", "law"), [("associative", "associative friction"),
                                               ("nonassociative", "non-associative")])
def test_the_plot_title_names_the_friction_law(
    tmp_path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], friction: str, law: str
) -> None:  # type: ignore[no-untyped-def]
    """A ``--plot``'s title says which friction law drew it, associative as well as non-associative."""
    import micro.plot

    titles: list[str] = []
    monkeypatch.setattr(micro.plot, "plot_velocities", lambda *a, title, **k: titles.append(title))
    assert cli.main(["micro", *WALL, "--friction", friction, "--no-lowest" if friction == "nonassociative"
                     else "--solver=highs-ipm", "--plot", str(tmp_path / "m.png")]) == 0
    capsys.readouterr()
    assert len(titles) == 1 and law in titles[0], titles


def test_a_failed_run_prints_the_line_the_readme_documents(capsys: pytest.CaptureFixture[str]) -> None:
    """A failed run prints the line the README documents, with and without ``-q``; under ``-q`` that line
    alone."""
    import re
    from pathlib import Path

    readme = (Path(__file__).parents[3] / "README.md").read_text()
    documented = re.findall(r"^\s*\* `(status [^`]+)`", readme, flags=re.MULTILINE)
    assert len(documented) == 2, documented
    patterns = []
    for template in documented:
        rx = re.escape(template)
        for token, sub in (("[, lambda in [LO, HI]]", r"(, lambda in \[[0-9.]+, [0-9.]+\])?"), ("STATUS", "[a-z_]+"),
                           ("MESSAGE", ".+"), (" N ", r" \d+ ")):
            rx = rx.replace(re.escape(token), sub)
        patterns.append(rx)
    runs = [(["--time-limit", "1e-9"], patterns[0]),
            (["--friction", "nonassociative", "--max-iterations", "2", "--tuning", "selection=vertex", "--no-lowest"],
             patterns[1]),
            (["--m", "1", "--friction", "nonassociative", "--tuning", "relaxation=1", "--tuning", "certify=false",
              "--tuning", "selection=vertex", "--no-lowest"], patterns[1])]  # Set 14's naive sequence cycles
    for extra, pattern in runs:
        argv = ["micro", *WALL, *extra]
        assert cli.main([*argv, "-q"]) == 1
        quiet = capsys.readouterr().out
        assert quiet.count("\n") == 1 and re.fullmatch(pattern, quiet.rstrip("\n")), (pattern, quiet)
        assert cli.main(argv) == 1
        assert capsys.readouterr().out.startswith(quiet)  # the same line, then the details


@pytest.mark.parametrize("friction", ["associative", "nonassociative"])
def test_the_plot_marks_the_floors_and_the_macro_hinge(friction: str, tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """``xcheck micro --plot`` marks the floors between storeys and the macro model's hinge storey, so the two
    mechanisms can be compared on one picture (the comparison solves the macro model for it; micro only
    draws the numbers it is given)."""
    import matplotlib.figure

    import macro
    from comparison.domain.wall import WallSpec

    kept = []
    save = matplotlib.figure.Figure.savefig
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig",
                        lambda fig, *a, **k: (kept.append(fig), save(fig, *a, **k)))  # fmt: skip
    wall = ["--storeys", "2", "--rows", "12", "--t", "1", "--m", "1/2", "--f", "0.6"]
    png = tmp_path / "m.png"
    assert cli.main(["micro", *wall, "--friction", friction, "--plot", str(png), "-q"]) == 0
    (fig,) = kept
    ax = fig.axes[0]
    floors = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    assert [float(ln.get_ydata()[0]) for ln in floors] == [6.0]  # two storeys of 6 rows
    hinge = macro.solve(WallSpec.from_paper(t=1, m=1 / 2, rows=12, f=0.6, storeys=2).to_macro()).hinge_storey
    (marker,) = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    assert marker.get_label() == f"macro hinge: base of storey {hinge}"
    assert float(marker.get_ydata()[0]) == 6.0 * (2 - hinge)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["floor", marker.get_label()]
    assert png.stat().st_size > 1000


@pytest.mark.parametrize("friction", ["associative", "nonassociative"])
def test_cut_end_blocks_are_said(capsys: pytest.CaptureFixture[str], friction: str) -> None:
    """t = 0.7 on 6 rows of m = 1/3 gives L = 5.714 half blocks: how the courses end is said in one line (closers
    by default, cut with ``--ends cut``) and in the JSON (``end_blocks_cut``, ``ends``); a wall of whole half
    blocks says nothing."""
    cut = ["--t", "0.7", "--m", "1/3", "--rows", "6", "--f", "0.6", "--friction", friction]
    assert cli.main(["micro", *cut]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if "half blocks" in line]
    assert lines == ["  L = 5.714 half blocks, not a whole number: the courses end in closers at least 0.6 wide, a "
                     "remainder narrower than that taken up by a long last unit (--ends closers) (docs/micro/walls.md)"]
    assert cli.main(["micro", *cut, "--ends", "cut"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if "half blocks" in line]
    assert lines == ["  L = 5.714 half blocks, not a whole number: the last block of every course is cut, down to "
                     "slivers (--ends cut) (docs/micro/walls.md)"]
    assert cli.main(["micro", *cut, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["end_blocks_cut"] is True and out["ends"] == "closers"
    assert cli.main(["micro", *cut, "-q"]) == 0
    assert "half blocks" not in capsys.readouterr().out  # quiet: the value alone
    whole = ["--t", "1", "--m", "1/3", "--rows", "6", "--f", "0.6", "--friction", friction]
    assert cli.main(["micro", *whole]) == 0
    assert "half blocks" not in capsys.readouterr().out
    assert cli.main(["micro", *whole, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["end_blocks_cut"] is False
