"""Every option given either acts or is refused (one line, exit 2): none is silently ignored, and every
research knob can be set through ``--tuning``."""

from __future__ import annotations

import typing

import pytest

import micro
from comparison.cli import main
from comparison.cli.micro import parse_tuning
from comparison.domain.wall import WallSpec
from micro.nonassociative import TUNING_KNOBS

WALL = ["--rows", "4", "--t", "1", "--m", "1/3", "--f", "0.6"]


def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize(("extra", "line"), [
    (["--max-iterations", "5"], "--max-iterations applies to --friction nonassociative only"),
    (["--global"], "--global applies to --friction nonassociative only"),
    (["--node-limit", "3"], "--node-limit applies to --friction nonassociative only"),
    (["--lowest", "off"], "--lowest applies to --friction nonassociative only"),
    (["--lowest", "auto"], "--lowest applies to --friction nonassociative only"),
    (["--tuning", "scheme=b"], "--tuning applies to --friction nonassociative only"),
    (["--global", "--tuning", "scheme=b"], "--global, --tuning apply to --friction nonassociative only"),
    (["--friction", "nonassociative", "--node-limit", "3"],
     "--node-limit applies to --global only (the branch and bound's nodes)"),
])
def test_an_option_that_does_not_apply_is_refused(extra: list[str], line: str,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """``--max-iterations``, ``--global``, ``--node-limit`` and ``--lowest`` with associative friction, and
    ``--node-limit`` without ``--global``, are refused in one line, as ``--tuning`` and ``--solver`` in the
    wrong mode are."""
    code, out, err = _run(["micro", *WALL, *extra], capsys)
    assert (code, out, err) == (2, "", f"xcheck: error: {line}\n")


def test_the_options_that_apply_still_run(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(["micro", *WALL, "-q", "--friction", "nonassociative", "--lowest", "off",
                         "--max-iterations", "20"], capsys)
    assert (code, out) == (0, "0.600000\n")
    code, out, _ = _run(["micro", *WALL, "-q"], capsys)
    assert (code, out) == (0, "0.600000\n")


@pytest.mark.parametrize("extra", [["--lowest"], ["--quick"], ["--workers", "1"], ["--lowest", "--quick"]])
def test_stability_table7_refuses_the_options_it_ignored(extra: list[str], tmp_path: typing.Any,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    """``xcheck stability --table7 --lowest`` ran only ``--table7``."""
    code, out, err = _run(["stability", "--table7", *extra, "--out", str(tmp_path)], capsys)
    assert code == 2 and out == "" and err.startswith(
        "xcheck: error: --table7 runs its four walls alone in this process; drop --") and err.count("\n") == 1
    assert extra[0] in err and not any(tmp_path.iterdir())


@pytest.mark.parametrize(("item", "key", "value"), [
    ("start=vertex", "start", "vertex"),
    ("scheme=b", "scheme", "b"),
    ("selection=none", "selection", None),
    ("fuse=auto", "fuse", None),
    ("fuse=on", "fuse", True),
    ("retry_iterations=5", "retry_iterations", 5),
    ("relaxation=0.5", "relaxation", 0.5),
    ("max_simplex_iterations=none", "max_simplex_iterations", None),
])
def test_every_kind_of_knob_can_be_set(item: str, key: str, value: object) -> None:
    """Every knob of the tuning can be set by ``--tuning``, each read by its declared type (``start=vertex``: a
    choice among ``Literal['interior', 'vertex']``, not an int)."""
    assert getattr(parse_tuning([item]), key) == value


def test_every_knob_reads_its_own_default_back() -> None:
    """Each knob's default, written as the command line would, reads back as that default."""
    default = micro.Tuning()
    for key in TUNING_KNOBS:
        value = getattr(default, key)
        text = "none" if value is None else str(value).lower()
        assert getattr(parse_tuning([f"{key}={text}"]), key) == value, key


@pytest.mark.parametrize(("item", "message"), [
    ("start=edge", "--tuning start must be one of interior, vertex, got 'edge'"),
    ("selection=closest", "--tuning selection must be one of vertex, proximal, vertex+proximal, none, got 'closest'"),
    ("scheme=3", "--tuning scheme must be one of a, b, got '3'"),
    ("retry_iterations=2.5", "--tuning retry_iterations must be an integer of at most 2,147,483,647, got '2.5'"),
    ("retry_iterations=1_0", "--tuning retry_iterations must be an integer of at most 2,147,483,647, got '1_0'"),
])
def test_a_bad_knob_value_names_the_choices(item: str, message: str, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(["micro", *WALL, "--friction", "nonassociative", "--tuning", item], capsys)
    assert (code, out, err) == (2, "", f"xcheck: error: {message}\n")


@pytest.mark.parametrize("rows", [1, 5, 12, 13, 35])
def test_a_wall_of_exactly_a_million_block_heights_is_accepted(rows: int, capsys: pytest.CaptureFixture[str]) -> None:
    """o/t = 1e6 exactly is accepted, as the message ``o/t <= 1e+06`` says, even where the length ``o/t``
    comes out a unit in the last place above 1e6."""
    t = rows / 1e6
    spec = WallSpec.from_paper(t=t, m=1, rows=rows, f=0.6)
    assert spec.length == pytest.approx(1e6, rel=1e-15)
    code, out, _ = _run(["macro", "--rows", str(rows), "--t", repr(t), "--m", "1", "--f", "0.6", "-q"], capsys)
    assert code == 0 and float(out) > 0
    with pytest.raises(ValueError, match=r"^t must be in \[.*o/t <= 1e\+06\)$"):
        WallSpec.from_paper(t=t * (1 - 1e-9), m=1, rows=rows, f=0.6)
