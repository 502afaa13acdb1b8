"""Outputs that cannot be written: the result is printed all the same, no cut or empty file is left,
and the exit code is 1 (the input was fine), never 2 or a traceback.

A full disk is simulated by a write that stores half its bytes and then fails with ENOSPC (what a
filling disk does); ``/dev/full`` where a real device is enough.
"""

from __future__ import annotations

import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import micro.files
from comparison.cli import main

WALL = ["--t", "1", "--m", "1/3", "--rows", "6", "--f", "0.6"]


@pytest.fixture()
def full_disk(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every image write stores half its bytes, then fails with ENOSPC."""

    def half(path: Path, data: bytes) -> None:
        with open(path, "wb") as fh:
            fh.write(data[: len(data) // 2])
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(micro.files, "_write_new", half)


@pytest.mark.parametrize("friction", ["associative", "nonassociative"])
def test_a_plot_that_cannot_be_written_leaves_no_file_and_the_result_is_printed_first(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], full_disk: None, friction: str
) -> None:
    """A plot that cannot be written: the result is printed first, then one line, exit 1, and no cut file."""
    png = tmp_path / "x.png"
    code = main(["micro", *WALL, "--friction", friction, "--plot", str(png), "-q"])
    out, err = capsys.readouterr()
    assert code == 1
    assert float(out.strip()) == pytest.approx(0.6, abs=1e-6)  # lambda, as -q prints it
    assert err.strip() == f"xcheck: error: --plot: cannot write {str(png)!r} (No space left on device)"
    assert list(tmp_path.iterdir()) == []  # neither the image nor its temporary file


def test_the_json_of_a_plot_that_failed_says_no_plot(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], full_disk: None
) -> None:
    code = main(["micro", *WALL, "--plot", str(tmp_path / "x.png"), "--json"])
    out, err = capsys.readouterr()
    summary = json.loads(out)
    assert code == 1 and summary["plot"] is None and summary["status"] == "optimal"
    assert err.count("\n") == 1 and "--plot: cannot write" in err


def test_a_plot_named_only_by_its_extension_is_written_under_that_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """``--plot .png`` writes ``.png``, the name the JSON gives."""
    monkeypatch.chdir(tmp_path)
    code = main(["micro", *WALL, "--plot", ".png", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert code == 0 and summary["plot"] == ".png"
    assert sorted(p.name for p in tmp_path.iterdir()) == [".png"]
    assert (tmp_path / ".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_report_figure_on_a_full_disk_leaves_no_empty_file(tmp_path: Path, full_disk: None) -> None:
    """A report figure that cannot be written on a full disk leaves no file (no ``histories.png`` of 0 bytes)."""
    from comparison.report.figures import pyplot, save_figure

    fig = pyplot().figure()
    with pytest.raises(OSError, match="No space left") as info:
        save_figure(fig, tmp_path / "histories.png")
    assert info.value.filename == str(tmp_path / "histories.png")
    assert list(tmp_path.iterdir()) == []


def test_a_figure_keeps_the_modes_a_new_file_gets(tmp_path: Path) -> None:
    from comparison.report.figures import pyplot, save_figure

    path = save_figure(pyplot().figure(), tmp_path / "f.svg")
    mask = os.umask(0)
    os.umask(mask)
    assert path.stat().st_mode & 0o777 == 0o666 & ~mask
    assert path.read_bytes().lstrip().startswith(b"<?xml")


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
def test_references_to_a_full_device_exit_1_not_2(monkeypatch: pytest.MonkeyPatch,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """The cells are computed; writing them fails for want of space, not for bad input."""
    from comparison.pytest_plugin import generate

    def write_only(out: Path, **_: object) -> list[object]:
        out.write_text("{}" * 10_000, encoding="utf-8")  # the generator's last step
        return []

    monkeypatch.setattr(generate, "generate", write_only)
    code = main(["references", "--out", "/dev/full"])
    err = capsys.readouterr().err
    assert code == 1 and err.strip() == "xcheck: error: cannot write /dev/full: No space left on device", err


def test_worker_memory_beyond_any_machine_is_one_line_exit_2(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    """``--worker-memory 1e308``: an OverflowError traceback (1e308 GB in bytes)."""
    grid = Path(__file__).resolve().parents[3] / "examples" / "sweeps" / "tiny.toml"
    code = main(["sweep", str(grid), "--out", str(tmp_path), "--worker-memory", "1e308"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--worker-memory must be a positive number of gigabytes" in err


def test_a_closed_standard_output_is_one_line_exit_1_before_any_work() -> None:
    """``xcheck micro ... -q >&-`` (``sys.stdout`` is None): one line, exit 1, before any work."""
    proc = subprocess.run(
        [sys.executable, "-c", "import sys; from comparison.cli import main; sys.exit(main(sys.argv[1:]))",
         "micro", *WALL, "-q"],
        stderr=subprocess.PIPE, text=True, timeout=120, preexec_fn=lambda: os.close(1),
    )
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr.strip() == "xcheck: error: cannot write the output: standard output is closed"


def test_a_plot_named_by_a_symbolic_link_is_written_through_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--plot link.png`` where the link points elsewhere: the image the link points to is replaced, the link
    stays (a rename over the link replaced the link with a file)."""
    (tmp_path / "figures").mkdir()
    target = tmp_path / "figures" / "wall.png"
    target.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(Path("figures") / "wall.png")
    assert main(["micro", *WALL, "--plot", str(link), "-q"]) == 0
    capsys.readouterr()
    assert link.is_symlink() and os.readlink(link) == str(Path("figures") / "wall.png")
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figures", "link.png"]
    assert sorted(p.name for p in (tmp_path / "figures").iterdir()) == ["wall.png"]  # no temporary left
