"""``xcheck compare``: the verdict's sentence first, the JSON keys of the issue, exit codes (0 whatever the
verdict, 1 when a method failed, 2 on bad input with one line naming the parameter)."""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path

import pytest

import micro
from comparison.cli import main

SET12 = ["--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75"]
SET13 = ["--rows", "12", "--t", "1", "--m", "1/2", "--f", "0.75"]


def test_set13_words(capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["compare", *SET13, "--full"])
    lines = capsys.readouterr().out.splitlines()
    assert rc == 0
    assert lines[0] == ("The macro model is unsafe for this wall: its λ 0.4914 is above the certified collapse "
                        "state's 0.4895 (+0.4 %).")
    assert any(line.lstrip().startswith("macro model:") and "0.491381" in line for line in lines[1:])
    assert any("0.489459" in line and "lowest certified" in line for line in lines[1:])


def test_set13_stops_at_the_first_state_below_the_macro_value(capsys: pytest.CaptureFixture[str]) -> None:
    """Without --full the search stops at the iterated LP's certified state, already below the macro λ (by
    0.021 %, more than the solvers' accuracy): it proves the macro model unsafe; the lowest state is not
    searched for, and the output says so."""
    rc = main(["compare", *SET13])
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert rc == 0
    assert lines[0] == ("The macro model is unsafe for this wall: its λ 0.4914 is above the certified collapse "
                        "state's 0.4913 (+0.021 %).")
    assert any("0.491276" in line and "where the search stopped" in line for line in lines[1:])
    assert "non-associative: " in captured.err and "LP" in captured.err  # the progress on stderr
    assert main(["compare", *SET13, "-q"]) == 0
    assert capsys.readouterr().err == ""  # -q: no progress


def test_set12_json_and_quiet(capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["compare", *SET12, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert rc == 0
    assert (doc["verdict"], doc["proof"], doc["status"], doc["local_mechanism"]) == ("not refuted", None, "ok", None)
    assert doc["micro_load_factor"] == pytest.approx(0.6911, abs=1e-4)
    assert doc["difference_percent"] == pytest.approx(
        100 * (doc["macro_load_factor"] - doc["micro_load_factor"]) / doc["micro_load_factor"], rel=1e-12)
    assert doc["associative_load_factor"] > doc["iterated_load_factor"] >= doc["micro_load_factor"]
    assert main(["compare", *SET12, "-q"]) == 0
    assert capsys.readouterr().out == "not refuted\n"


def test_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    png = tmp_path / "c.png"
    assert main(["compare", *SET13, "--json", "--plot", str(png)]) == 0
    assert json.loads(capsys.readouterr().out)["plot"] == str(png)
    assert png.stat().st_size > 1000


@pytest.mark.usefixtures("failing_nonassociative")
def test_a_failed_method_exits_1_with_what_is_missing(capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["compare", *SET13])
    out = capsys.readouterr().out
    assert rc == 1
    assert out.startswith("No verdict for this wall")
    assert "non-associative solve failed" in out and "non-associative:" not in out  # no number for it


@pytest.mark.parametrize(
    ("argv", "word"),
    [
        (["--rows", "12", "--t", "1", "--m", "1/3"], "--f"),
        ([*SET12, "--f", "x"], "f must be"),
        ([*SET12, "--first-course", "third"], "--first-course"),
        ([*SET12, "--head-joints", "glued"], "--head-joints"),
        ([*SET12, "--lowest", "maybe"], "--lowest"),
        ([*SET12, "--node-limit", "5"], "--node-limit"),
        ([*SET12, "--global", "--node-limit", "0"], "--node-limit"),
        ([*SET12, "--time-limit", "-1"], "--time-limit"),
        ([*SET12, "--plot", "out.txt"], "--plot"),
        ([*SET12, "--plot", "/no/such/folder/c.png"], "--plot"),
        ([*SET12, "--scene", "examples/three-storey.toml"], "--scene"),
        (["--t", "1", "--m", "1/3", "--rows", "0", "--f", "0.75"], "rows"),
        ([*SET12, "--friction", "associative"], "--friction"),  # not an option of compare
    ],
)
def test_bad_input_is_one_line_and_exit_2(argv: list[str], word: str, capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["compare", *argv])
    captured = capsys.readouterr()
    assert rc == 2 and captured.out == ""
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("xcheck: error: ") and word in err[0]


def test_state_of_the_value_compared_is_written_and_verifies(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    """``--state`` writes the collapse state the verdict rests on; ``xcheck verify`` accepts it and refuses it
    with its load factor raised by 1 %."""
    path = tmp_path / "set13.json"
    assert main(["compare", *SET13, "--state", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["state"] == str(path)
    state = micro.read_state(path)
    assert state.friction == "nonassociative" and state.load_factor == pytest.approx(doc["micro_load_factor"])
    assert micro.verify_state(state).passed
    raw = json.loads(path.read_text())
    raw["load_factor"] *= 1.01
    tampered = tmp_path / "tampered.json"
    tampered.write_text(json.dumps(raw))
    assert main(["verify", str(tampered)]) == 1


def test_state_is_the_associative_one_when_the_bound_settles(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "bound.json"
    assert main(["compare", "--storeys", "2", "--rows", "24", "--t", "1", "--m", "1/3", "--f", "0.75",
                 "--state", str(path), "-q"]) == 0
    assert capsys.readouterr().out.strip() == "unsafe (associative bound)"
    state = micro.read_state(path)
    assert state.friction == "associative" and micro.verify_state(state).passed


def test_state_in_a_missing_folder_is_refused_before_the_solves(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["compare", *SET13, "--state", "/no/such/folder/s.json"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "--state" in captured.err and len(captured.err.strip().splitlines()) == 1


@pytest.mark.parametrize("option", ["--state", "--plot"])
def test_an_output_that_is_not_a_regular_file_is_refused_before_the_solves(
        tmp_path: Path, option: str, capsys: pytest.CaptureFixture[str]) -> None:
    """A device or FIFO named as an output (directly or through a link) is bad input: one line, exit 2,
    nothing solved, and the device left as it is (the writer never replaces one)."""
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    device = tmp_path / "null.png"
    device.symlink_to("/dev/null")
    for target in (device, fifo):
        assert main(["compare", *SET13, option, str(target)]) == 2
        captured = capsys.readouterr()
        assert captured.out == "" and "not a regular file" in captured.err
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode) and stat.S_ISFIFO(os.stat(fifo).st_mode)


@pytest.mark.parametrize("command", ["compare", "macro"])
def test_a_time_that_includes_compiling_the_macro_kernel_says_so(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, command: str
) -> None:
    """A time that includes compiling the macro model's kernel (its first use after an install) says so; a
    run that reads it from numba's cache says nothing more."""
    from macro import kernel

    argv = [command, "--rows", "12", "--t", "1", "--m", "1/2", "--f", "0.75", *(["-v"] if command == "macro" else [])]
    assert main(argv) == 0
    assert "first use" not in capsys.readouterr().out  # the kernel compiled or read before this run
    counts = iter(range(0, 100, 10))
    monkeypatch.setattr(kernel, "compilations", lambda: next(counts))  # as in a fresh environment
    assert main(argv) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if "blocks; macro" in x or "solved in" in x)
    assert "(compiling the macro model's kernel on its first use; later runs read it from the cache)" in line, out
