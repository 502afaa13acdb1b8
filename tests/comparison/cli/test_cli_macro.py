"""``xcheck macro`` and ``xcheck report`` from the command line, and scene files."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from quick_report import QuickReport

from comparison.cli import main
from comparison.domain.scene import SceneError, parse_scene

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "examples" / "three-storey.toml"


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_macro_json_reference_wall(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(
        capsys, "macro", "--storeys", "3", "--rows", "60", "--t", "1", "--m", "1/3", "--f", "0.6", "--json"
    )
    assert code == 0
    d = json.loads(out)
    for key in ("load_factor", "alpha_c_deg", "alpha_ratio", "hinge_storey", "sliding_load_factor"):
        assert key in d
    assert d["load_factor"] == pytest.approx(0.5825, abs=5e-5)
    assert d["alpha_c_deg"] == pytest.approx(40.15, abs=5e-3)
    assert d["hinge_storey"] == 3
    assert d["paper_parameters"]["m"] == pytest.approx(1 / 3)


def test_macro_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "macro", "--rows", "12", "--t", "1", "--m", "1", "--f", "0.75")
    assert code == 0
    assert "0.2617" in out and "rocking" in out


def test_macro_scene_file(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "macro", "--scene", str(EXAMPLE), "--json")
    assert code == 0
    d = json.loads(out)
    # p = 0.2 on the two lower floors pulls lambda just below the reference wall's 0.5825
    assert 0.57 < d["load_factor"] < 0.5825


def test_a_scene_shows_its_loads_storey_by_storey(capsys: pytest.CaptureFixture[str]) -> None:
    """The example scene's comment gives p = 0.2 on the two lower floors: both outputs show p storey by
    storey, as the comment does, and the JSON's one ``p`` is null (no one value describes those floors)."""
    import re

    comment = [float(p) for p in re.findall(r"p = [^#\n]*= ([\d.]+)\s*$", EXAMPLE.read_text(), re.M)]
    assert comment == [0.2]  # the comment's derivation, for storey 2
    d = json.loads(run(capsys, "macro", "--scene", str(EXAMPLE), "--json")[1])
    assert d["paper_parameters"]["p_storeys"] == pytest.approx([0.0, 0.2, 0.2])
    # no one p describes floors of 0, 0.2 and 0.2 (it said 0.0, the top storey's); m of 0.10/0.30 blocks is
    # 1/3 as written (it said 0.33333333333333337)
    assert d["paper_parameters"]["p"] is None
    assert d["paper_parameters"]["p_storeys"] == [0.0, 0.2, 0.2]
    assert d["paper_parameters"]["m"] == 1 / 3 and d["paper_parameters"]["t"] == 1.0
    assert "0.33333333333333337" not in run(capsys, "micro", "--scene", str(EXAMPLE), "--json")[1]
    assert d["wall"]["overload"] == [0.0, 2.16, 2.16]
    code, out, _ = run(capsys, "macro", "--scene", str(EXAMPLE))
    assert code == 0
    assert "floor loads (storey 1, the top, first): q = 0, 2.16, 2.16; p = q/(gamma H b) = 0, 0.2, 0.2" in out
    uniform = run(capsys, "macro", "--storeys", "3", "--rows", "60", "--t", "1", "--m", "1/3", "--f", "0.6", "--p", "2")
    assert "; p = q/(gamma H b) = 2, 2, 2\n" in uniform[1]  # the paper's walls: the same p on every floor


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--rows", "60", "--t", "1", "--m", "1/3", "--f", "0"], "f must be a positive number"),
        (["--rows", "60", "--t", "1", "--m", "1/3", "--f", "-0.2"], "f must be a positive number"),
        (["--rows", "60", "--t", "0", "--m", "1/3", "--f", "0.6"], "t must be a positive number"),
        (["--rows", "60", "--t", "1", "--m", "3/2", "--f", "0.6"], "m must be in (0, 1]"),
        (["--rows", "60", "--t", "1", "--m", "0", "--f", "0.6"], "m must be a positive number"),
        (["--rows", "12.5", "--t", "1", "--m", "1/3", "--f", "0.6"], "rows must be a positive integer"),
        (["--rows", "-3", "--t", "1", "--m", "1/3", "--f", "0.6"], "rows must be a positive integer"),
        (["--rows", "60", "--t", "1", "--m", "x", "--f", "0.6"], "m must be a number or a fraction"),
        (
            ["--storeys", "0", "--rows", "60", "--t", "1", "--m", "1/3", "--f", "0.6"],
            "storeys must be a positive integer",
        ),
        (
            ["--storeys", "7", "--rows", "60", "--t", "1", "--m", "1/3", "--f", "0.6"],
            "cannot be split equally over 7 storeys",
        ),
        (["--rows", "60", "--t", "1", "--m", "1/3"], "missing --f"),
        (["--rows", "60", "--t", "1", "--m", "1/3", "--f", "0.6", "--p", "-1"], "p must be zero or a positive number"),
        (["--rows", "60", "--t", "1", "--m", "1/3", "--f", "0.6", "--bogus"], "unrecognized arguments: --bogus"),
    ],
)
def test_macro_bad_input_one_line_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str], message: str) -> None:
    code, out, err = run(capsys, "macro", *argv)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("xcheck: error: ")
    assert message in err


GOOD = """\
name = "wall"
[wall]
length = 6.0
unit_weight = 18.0
friction = 0.6
[block]
length = 0.3
height = 0.1
[[storey]]
rows = 20
thickness = 0.1
[[storey]]
rows = 20
overload = 2.0
"""


def test_scene_parses_storey_by_storey() -> None:
    spec = parse_scene(GOOD)
    assert spec.rows == 40 and spec.storeys[1].overload == 2.0 and spec.storeys[1].thickness == 0.1
    assert spec.paper_parameters()["t"] == pytest.approx(4.0 / 6.0)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (GOOD.replace("friction = 0.6", "friction = 0.6\ncolour = 1"), "(line 6): unknown key 'colour' in [wall]"),
        (
            GOOD.replace("rows = 20\noverload", "rows = 20\nroof = 1\noverload"),
            "(line 14): unknown key 'roof' in [storey]",
        ),
        (GOOD.replace("height = 0.1", "height = -0.1"), "(line 8): block.height must be a positive number, got -0.1"),
        (
            GOOD.replace("overload = 2.0", "overload = -2.0"),
            "(line 14): storey 2: overload must be zero or a positive number",
        ),
        (
            GOOD.replace("rows = 20\nthickness", "rows = 2.5\nthickness"),
            "(line 10): storey 1: rows must be a positive integer",
        ),
        (
            GOOD.replace("friction = 0.6", "friction = 'high'"),
            "(line 5): wall.friction must be a positive number, got 'high'",
        ),
        (GOOD.replace("length = 6.0", "length = "), "malformed TOML"),
        (GOOD.replace("friction = 0.6\n", ""), "missing key 'friction' in [wall]"),
        (GOOD.split("[[storey]]")[0], "no [[storey]] given"),
        (GOOD + "[extra]\n", "unknown table [extra]"),
    ],
)
def test_scene_errors_name_key_and_line(text: str, message: str) -> None:
    with pytest.raises(SceneError) as exc:
        parse_scene(text, source="w.toml")
    assert message in str(exc.value)
    assert "\n" not in str(exc.value)


def test_scene_error_via_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(GOOD.replace("friction = 0.6", "friction = 0.6\ncolour = 1"))
    code, _, err = run(capsys, "macro", "--scene", str(bad))
    assert code == 2 and "line 6" in err and "colour" in err and err.count("\n") == 1
    code, _, err = run(capsys, "macro", "--scene", str(tmp_path / "missing.toml"))
    assert code == 2 and "cannot read" in err


@pytest.mark.skipif(
    shutil.which("xcheck") is None and not (Path(sys.executable).parent / "xcheck").exists(),
    reason="console script not installed",
)
@pytest.mark.processes  # the installed console script, a process of its own
def test_console_script_no_traceback() -> None:
    exe = shutil.which("xcheck") or str(Path(sys.executable).parent / "xcheck")
    p = subprocess.run(
        [exe, "macro", "--rows", "0", "--t", "1", "--m", "1/3", "--f", "0.6"], capture_output=True, text=True
    )
    assert p.returncode == 2
    assert "Traceback" not in p.stderr and p.stderr.count("\n") == 1 and "rows" in p.stderr


def test_report_quick_writes_tables_and_figures(
    quick_report: QuickReport, quick_report_cache: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A first run from an empty cache prints its plan, then one line per computation; its timings count every
    computation as computed; the report has every table and figure. A second run into a folder without the
    committed tables warns for each, says so in REPORT.md, and reads every computation from the cache (its
    figures, the first run's drawn from the same results, are written as placeholders: encoding 27 PNGs again
    would be most of its CPU)."""
    # the first run: the shared quick report (tests/conftest.py), from an empty cache, --verbose
    first = quick_report.out
    assert "REPORT.md" in quick_report.stdout
    err = quick_report.stderr
    assert err.startswith("plan: ") and "0 cached" in err.splitlines()[0]  # the plan first
    assert "micro-assoc" in err  # then one line per computation (not a terminal: no bar)
    # timings.md must not count the records computed in the workers, which come back through the cache,
    # as read from the cache
    computed = _timings(first)
    assert computed["cached"] == 0 and computed["yes"] == 0 and computed["rows"] > 0
    assert "0 read from the result cache" in (first / "timings.md").read_text()
    text = (first / "REPORT.md").read_text()
    for heading in (
        "Table 5",
        "Table 7",
        "Table 8",
        "Table 9",
        "Failure modes",
        "Where the paper and the model differ",
    ):
        assert heading in text
    for name in ("table7.csv", "report.json", "sensitivity.png", "speed_accuracy.png", "mechanism_12.png"):
        assert (first / name).stat().st_size > 0, name
    assert "is missing" not in text  # the committed tables read from --tables
    # a second run, into a folder without the committed tables (read from --tables, by default --out): it
    # warns once per table and its sections say so; not on a terminal and not --verbose, it prints the plan,
    # the warnings and what it wrote on stderr, and no status line (everything is read from the cache)
    import matplotlib.figure

    from comparison.report.committed import BOND, ERRORMAP, LOWEST

    def placeholder(fig: matplotlib.figure.Figure, fname: object, **kwargs: object) -> None:
        assert hasattr(fname, "write"), fname  # micro.plot.save_figure renders into memory, then writes whole
        fname.write(b"a figure")  # type: ignore[attr-defined]

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", placeholder)
    cache = ["--cache", str(quick_report_cache)]
    code, out, err = run(capsys, "report", "--out", str(tmp_path), "--quick", *cache)
    assert code == 0 and "REPORT.md" in out
    lines = err.splitlines()
    missing = [line for line in lines if line.startswith("xcheck: warning: the report's table ")]
    assert [line.split()[5] for line in missing] == [str(tmp_path / n) for n in (ERRORMAP, BOND, LOWEST)], err
    assert f"The table `{tmp_path / ERRORMAP}` is missing: make it with `" in (tmp_path / "REPORT.md").read_text()
    assert lines[0].startswith("plan: ") and ", 0 to compute" in lines[0], err
    assert lines[-1].startswith(f"wrote {len(list(tmp_path.glob('*.*')))} files into {tmp_path}: REPORT.md, "
                                "report.json, timings.md, "), err
    assert lines[1:-1] == missing and "micro-assoc" not in err  # nothing to compute: no status line
    again = _timings(tmp_path)
    assert again["cached"] == again["yes"] == again["rows"] == computed["rows"]


@pytest.mark.parametrize(("flag", "said"), [("--verbose", ["plan: ", "wrote "]), ("-q", [])])
def test_a_report_read_from_the_cache_prints_by_its_verbosity(
    flag: str, said: list[str], quick_report_cache: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Everything read from the cache: ``--verbose`` prints the plan and what it wrote, no line per computation
    (there is none); ``-q`` nothing. What is printed, not what is drawn, is checked here: the rendering (the
    same as a first run's, above) is left out."""
    import comparison.report.build

    def render(res: object, out: Path, meta: object, tables_dir: Path) -> Path:
        (out / "REPORT.md").write_text("")
        return out / "REPORT.md"

    monkeypatch.setattr(comparison.report.build, "_write", render)
    argv = ["report", "--out", str(tmp_path), "--quick", "--cache", str(quick_report_cache)]
    code, _, err = run(capsys, *argv, "--tables", str(ROOT / "reports"), flag)
    assert code == 0 and [line[: len(p)] for line, p in zip(err.splitlines(), said, strict=True)] == said, err
    assert ", 0 to compute" in err if said else err == ""


def _timings(out: Path) -> dict[str, int]:
    """The run's cached count and its micro rows, and how many of them say "read from the cache"."""
    timings = json.loads((out / "timings.json").read_text())
    rows = [r for r in timings["timings"] if not r["method"].startswith("macro")]
    return {"cached": timings["run"]["cached"], "rows": len(rows),
            "yes": sum(r["read from the cache"] == "yes" for r in rows)}


def test_cache_and_no_cache_exclude_each_other(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "report", "--out", str(tmp_path), "--cache", str(tmp_path), "--no-cache")
    assert code == 2 and "--no-cache" in err and err.count("\n") == 1


def test_an_error_inside_a_model_is_not_a_usage_error(monkeypatch: pytest.MonkeyPatch) -> None:
    import macro

    def broken(*args: object, **kwargs: object) -> None:
        raise ValueError("a bug inside the solver")

    monkeypatch.setattr(macro, "solve", broken)
    with pytest.raises(ValueError, match="a bug inside the solver"):
        main(["macro", "--rows", "12", "--t", "1", "--m", "1/3", "--f", "0.6"])


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("storey = 5\n" + GOOD.split("[[storey]]")[0], "(line 1): storey = 5 gives no storey"),
        (GOOD.split("[[storey]]")[0].replace("friction = 0.6", "friction = 0.6\nstorey = 5"),
         "(line 6): unknown key 'storey' in [wall]"),
        (GOOD.split("[[storey]]")[0].replace("friction = 0.6", "friction = 0.6\nstoreys = 5"),
         "(line 6): unknown key 'storeys' in [wall]"),
        (GOOD.split("[[storey]]")[0] + "[storey]\nrows = 20\n", "(line 9): [storey] is a single table"),
        (GOOD.split("[[storey]]")[0], "no [[storey]] given"),
    ],
    ids=["top-level", "in-wall", "storeys-in-wall", "single-table", "none"],
)
def test_a_scene_without_storey_tables_is_told_how_to_write_them(text: str, where: str) -> None:
    """A scene without ``[[storey]]`` tables (e.g. ``storey = 5``) is told how to write one, not only that
    none is given."""
    from comparison.domain.scene import STOREY_HOWTO

    with pytest.raises(SceneError) as exc:
        parse_scene(text, source="w.toml")
    message = str(exc.value)
    assert where in message and "\n" not in message, message
    assert message.endswith(f": {STOREY_HOWTO}") or message.endswith(f"; {STOREY_HOWTO}"), message
    assert "a line [[storey]], then rows = N" in STOREY_HOWTO
