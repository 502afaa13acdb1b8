"""The command line under misuse: one line naming the parameter and exit 2, never a traceback.

Usage and version, a reader that goes away (``| head``), output and cache
directories that cannot be written, conflicting flags, scene files that are
not UTF-8 text, and extreme but finite numbers that once reached a solver.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.cli.app import EXIT_BROKEN_PIPE

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "examples" / "three-storey.toml"
WALL = ["--rows", "12", "--t", "1", "--m", "1/3", "--f", "0.75"]


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def one_line_error(code: int, err: str, *words: str) -> None:
    assert code == 2, err
    assert err.startswith("xcheck: error: ") and err.count("\n") == 1, err
    for word in words:
        assert word in err, (word, err)


def test_bare_xcheck_prints_usage(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys)
    assert code == 2 and out == ""
    assert err.startswith("usage: xcheck") and "macro" in err and "report" in err


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "--version")
    assert code == 0 and out.startswith("xcheck ") and out.strip().split()[1][0].isdigit()


@pytest.mark.processes  # a console process on a real pipe
def test_a_closed_pipe_ends_quietly() -> None:
    """``xcheck macro --json | head``: the reader closes before the output is written."""
    proc = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys; from comparison.cli import main; sys.exit(main())",
            "macro",
            *WALL,
            "--json",
        ],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == EXIT_BROKEN_PIPE
    assert err == ""


@pytest.mark.parametrize("where", ["a file", "under a file", "in /proc"])
@pytest.mark.parametrize("option", ["--out", "--cache"])
def test_an_unwritable_directory_is_refused_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], option: str, where: str
) -> None:
    afile = tmp_path / "afile"
    afile.write_text("x")
    bad = {"a file": afile, "under a file": afile / "sub", "in /proc": Path("/proc/xcheck-test")}[where]
    dirs = {"--out": str(tmp_path / "out"), "--cache": str(tmp_path / "cache")} | {option: str(bad)}
    code, _, err = run(capsys, "report", "--quick", "--out", dirs["--out"], "--cache", dirs["--cache"])
    one_line_error(code, err, option, "cannot write")
    assert not (tmp_path / "out" / "REPORT.md").exists()


def test_stability_out_is_checked_first(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    afile = tmp_path / "afile"
    afile.write_text("x")
    code, _, err = run(capsys, "stability", "--quick", "--out", str(afile))
    one_line_error(code, err, "--out", "cannot write")


@pytest.mark.parametrize("extra", [["--p", "1"], ["--storeys", "3"], ["--rows", "12"], ["--f", "0.6"]])
def test_scene_excludes_the_paper_parameters(capsys: pytest.CaptureFixture[str], extra: list[str]) -> None:
    code, _, err = run(capsys, "macro", "--scene", str(EXAMPLE), *extra)
    one_line_error(code, err, "--scene", extra[0])


@pytest.mark.parametrize(
    ("content", "words"),
    [
        (EXAMPLE.read_text().encode("utf-16"), ["UTF-16"]),
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe", ["not UTF-8", "line 1"]),
        (b"[wall]\nlength = 6\n\xff\xfe", ["not UTF-8", "line 3"]),
        (b"\x00" * 64, ["malformed TOML"]),
        (b"storey = [1, 2]\n[wall]\nlength = 6\nfriction = 0.6\n[block]\nlength = 0.3\nheight = 0.1\n", ["storey"]),
    ],
    ids=["utf-16", "png", "latin byte", "nul bytes", "storey not a table"],
)
def test_a_scene_that_is_not_a_toml_text_names_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], content: bytes, words: list[str]
) -> None:
    scene = tmp_path / "wall.toml"
    scene.write_bytes(content)
    code, _, err = run(capsys, "macro", "--scene", str(scene))
    one_line_error(code, err, str(scene), *words)


def test_a_scene_with_a_byte_order_mark_is_read(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "bom.toml"
    scene.write_bytes(EXAMPLE.read_text().encode("utf-8-sig"))
    code, _, _ = run(capsys, "macro", "--scene", str(scene))
    assert code == 0


@pytest.mark.parametrize(
    ("command", "argv", "words"),
    [
        ("macro", ["--rows", "12", "--t", "1e300", "--m", "1/3", "--f", "0.6"], ["t must be in", "one block long"]),
        ("macro", ["--rows", "12", "--t", "100", "--m", "1/3", "--f", "0.6"], ["t must be in", "one block long"]),
        ("macro", ["--rows", "12", "--t", "1", "--m", "1e-300", "--f", "0.6"], ["m must be in"]),
        ("macro", ["--rows", "12", "--t", "1", "--m", "1/3", "--f", "1e300"], ["f must be in"]),
        ("macro", ["--rows", "2000000", "--t", "1", "--m", "1/3", "--f", "0.6"], ["rows must be at most"]),
        ("micro", [*WALL, "--p", "1e300"], ["p must be at most"]),
        ("micro", ["--rows", "12", "--t", "1e-300", "--m", "1/3", "--f", "0.6"], ["t must be in"]),
    ],
)
def test_extreme_numbers_are_refused(
    capsys: pytest.CaptureFixture[str], command: str, argv: list[str], words: list[str]
) -> None:
    code, _, err = run(capsys, command, *argv)
    one_line_error(code, err, *words)


@pytest.mark.parametrize(
    ("replace", "words"),
    [
        (("length = 6.0", "length = 1e300"), ["line 7", "wall.length must be in"]),
        (("length = 6.0", "length = 0.2"), ["wall.length must be at least", "one block long"]),
        (("height = 0.10", "height = 1e-300"), ["block.height must be in"]),
        (("overload = 0.0", "overload = 1e30"), ["overload must be at most"]),
    ],
)
def test_extreme_scene_values_name_the_key_and_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], replace: tuple[str, str], words: list[str]
) -> None:
    text = EXAMPLE.read_text()
    assert replace[0] in text
    scene = tmp_path / "wall.toml"
    scene.write_text(text.replace(replace[0], replace[1], 1))
    code, _, err = run(capsys, "macro", "--scene", str(scene))
    one_line_error(code, err, str(scene), *words)


def test_a_scene_too_large_for_the_macro_search(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """45,000 one-row storeys (405 GB estimated): refused from the memory estimate before anything is allocated."""
    storeys = "".join("[[storey]]\nrows = 1\n" for _ in range(45_000))
    scene = tmp_path / "tall.toml"
    scene.write_text(f"[wall]\nlength = 6\nfriction = 0.6\n[block]\nlength = 0.3\nheight = 0.1\n{storeys}")
    code, _, err = run(capsys, "macro", "--scene", str(scene))
    one_line_error(code, err, "storeys", "GB")


@pytest.mark.processes  # a console process whose standard output is /dev/full
@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize("argv", [["macro", *WALL, "--json"], ["macro", *WALL], ["micro", *WALL, "--json"]])
def test_a_full_disk_on_stdout_is_one_line_and_exit_1(argv: list[str]) -> None:
    """A full disk on standard output (``xcheck macro ... --json > /dev/full``) is one line and exit 1,
    no traceback: the input was fine, the output could not be written."""
    with open("/dev/full", "w") as full:
        proc = subprocess.run(
            [sys.executable, "-c", "import sys; from comparison.cli import main; sys.exit(main())", *argv],
            cwd=ROOT, stdout=full, stderr=subprocess.PIPE, text=True, timeout=120,
        )
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr == "xcheck: error: cannot write the output: No space left on device\n"


def test_macro_json_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    """``macro --json`` and ``micro --json`` both print one line (a pipeline reads one record a line)."""
    for command in ("macro", "micro"):
        code, out, _ = run(capsys, command, *WALL, "--json")
        assert code == 0 and out.count("\n") == 1 and out.startswith("{"), (command, out[:200])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--rows", "1e300"], "rows must be at most 1e+06, got 1e300: rows in all"),
        (["--rows", "1e400"], "rows must be a positive integer, got 1e400"),
        (["--t", "1e400"], "t must be a positive number, got 1e400"),
        (["--m", "1e-400"], "m must be a positive number, got 1e-400"),
        (["--f", "2e999"], "f must be a positive number, got 2e999"),
        (["--rows", "12.0000000000000001"], "rows must be a positive integer, got '12.0000000000000001'"),
        (["--storeys", "2.0000000000000001"], "storeys must be a positive integer, got '2.0000000000000001'"),
    ],
    ids=["rows-1e300", "rows-1e400", "t-1e400", "m-1e-400", "f-2e999", "rows-not-quite-12", "storeys"],
)
def test_a_bad_number_is_echoed_as_given(capsys: pytest.CaptureFixture[str], argv: list[str], message: str) -> None:
    """A bad number is echoed as the user wrote it (not as a 300-digit integer for ``--rows 1e300`` nor
    ``inf`` for ``--t 1e400``), and ``--rows 12.0000000000000001`` is refused, not read through a float
    as 12."""
    given = dict(zip(WALL[::2], WALL[1::2], strict=True)) | dict(zip(argv[::2], argv[1::2], strict=True))
    code, _, err = run(capsys, "macro", *[x for kv in given.items() for x in kv])
    one_line_error(code, err)
    assert err == f"xcheck: error: {message}\n"


def test_an_integer_option_is_read_exactly(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "macro", "--rows", "1.2e1", "--t", "1", "--m", "1/3", "--f", "0.75", "-q")
    assert code == 0 and out == "0.648067\n"  # 1.2e1 rows are 12 rows exactly


@pytest.mark.parametrize(
    "argv",
    [
        ["report", "--quick", "--out", ""],
        ["report", "--quick", "--cache", ""],
        ["stability", "--quick", "--out", ""],
        ["sweep", str(ROOT / "examples" / "sweeps" / "tiny.toml"), "--out", ""],
        ["references", "--out", ""],
    ],
    ids=["report-out", "report-cache", "stability-out", "sweep-out", "references-out"],
)
def test_an_empty_path_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    """An empty ``--out ''`` is refused: it would write into the working directory (``references --out ''``:
    over the installed package's own file)."""
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *argv)
    one_line_error(code, err, "must name a", "got ''")
    assert [p for p in tmp_path.rglob("*") if p.is_file()] == []


def test_references_writes_into_the_working_directory_by_default(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``xcheck references`` writes ``references.json`` in the working directory unless ``--out`` says,
    never by default over the installed package's own file."""
    from comparison.pytest_plugin import generate
    from comparison.pytest_plugin.references import References

    written: list[Path] = []

    def fake_generate(out: Path, **kwargs: object) -> References:
        written.append(Path(out))
        return References([])

    monkeypatch.setattr(generate, "generate", fake_generate)
    monkeypatch.chdir(tmp_path)
    code, out, _ = run(capsys, "references", "--no-cache")
    assert code == 0 and written == [Path("references.json")]
    assert out == "wrote references.json: 0 cells, 0 with a value\n"
    package_file = Path(generate.__file__).with_name("references.json")
    assert written[0].resolve() != package_file.resolve()
    code, _, err = run(capsys, "references", "--no-cache", "--out", str(tmp_path))
    one_line_error(code, err, "is a directory")


def test_stability_takes_workers_like_report_and_sweep(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``stability`` takes ``--workers`` as ``report`` and ``sweep`` do; the old name ``--processes`` is still
    read, with a warning, and the two together are refused."""
    import comparison.stability

    seen: list[int] = []

    def fake_study(out: str, *, processes: int, quick: bool, verbosity: int) -> dict[str, Path]:
        seen.append(processes)
        return {}

    monkeypatch.setattr(comparison.stability, "main_study", fake_study)
    monkeypatch.setattr("os.cpu_count", lambda: 2)
    out = str(tmp_path / "o")
    assert run(capsys, "stability", "--quick", "--out", out, "--workers", "1")[0] == 0
    assert run(capsys, "stability", "--quick", "--out", out)[0] == 0
    code, _, err = run(capsys, "stability", "--quick", "--out", out, "--processes", "1")
    assert code == 0 and err == "xcheck: warning: --processes is deprecated: use --workers\n"
    code, _, err = run(capsys, "stability", "--quick", "--out", out, "--workers", "9")
    assert code == 0 and "using 2 workers" in err
    assert seen == [1, 2, 1, 2]
    code, _, err = run(capsys, "stability", "--quick", "--out", out, "--workers", "1", "--processes", "1")
    one_line_error(code, err, "--processes is the old name of --workers")


@pytest.mark.parametrize("command", ["micro --scene", "macro --scene", "compare --scene", "sweep"])
def test_a_file_nested_too_deep_is_one_line_and_exit_2(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, command: str
) -> None:
    """A scene or grid holding ``a = [[[...]]]`` 1,500 deep is one line naming the file, exit 2."""
    deep = tmp_path / "deep.toml"
    deep.write_text("a = " + "[" * 1500 + "1" + "]" * 1500 + "\n")
    argv = [*command.split(), str(deep)] + (["--out", str(tmp_path / "out")] if command == "sweep" else [])
    code, out, err = run(capsys, *argv)
    one_line_error(code, err, "deep.toml", "malformed TOML: arrays or tables nested too deep to read")
    assert out == ""


@pytest.mark.parametrize(("rows", "bound"), [("6", "166666.66666666666"), ("12", "83333.33333333333")])
def test_a_bound_is_printed_unrounded(capsys: pytest.CaptureFixture[str], rows: str, bound: str) -> None:
    """A bound in a message is printed with every digit it has, never rounded onto the value it refuses."""
    code, _, err = run(capsys, "macro", "--rows", rows, "--t", "1", "--m", "1/3", "--f", "0.6", "--p", "166667")
    one_line_error(code, err, f"p must be at most {bound}, got 166667")


@pytest.mark.parametrize("option, name", [("--plot", "wall.png"), ("--state", "state.json")])
@pytest.mark.parametrize("where", ["dangling link", "folder not writable"])
def test_an_output_that_cannot_be_written_is_refused_before_the_solve(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, tmp_path: Path, option: str, name: str,
    where: str,
) -> None:
    """``--state`` or ``--plot`` through a link to nothing, or into a folder this process cannot write, is
    refused before the solve, exit 2. (The tests run as root, who may write anywhere: the folder's
    permission is what ``os.access`` answers for it.)"""
    import micro

    target = tmp_path / name
    if where == "dangling link":
        target.symlink_to(tmp_path / "missing" / name)
    else:
        real = os.access
        monkeypatch.setattr(os, "access", lambda p, mode, **kw: Path(p) != tmp_path and real(p, mode, **kw))

    def no_solve(*args: object, **kwargs: object) -> None:
        raise AssertionError("the solve ran")

    monkeypatch.setattr(micro, "solve_nonassociative", no_solve)
    monkeypatch.setattr(micro, "solve_associative", no_solve)
    code, out, err = run(capsys, "micro", *WALL, option, str(target))
    reason = "is a symbolic link to nothing" if where == "dangling link" else "cannot write into the folder of"
    one_line_error(code, err, option, reason)
    assert out == ""
