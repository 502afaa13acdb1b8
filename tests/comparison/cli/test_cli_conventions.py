"""Conventions every subcommand shares: ``--quiet``/``--verbose`` and the documented exit codes."""

from __future__ import annotations

import pytest

from comparison.cli import build_parser, main
from comparison.cli.options import EXIT_FAILED, EXIT_USAGE, NORMAL, QUIET, VERBOSE

WALL = ["--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75"]  # Table 7, Set 12


@pytest.mark.parametrize("command", ["compare", "macro", "micro", "report", "stability"])
def test_every_command_has_verbosity_and_documents_exit_codes(command: str) -> None:
    parser = build_parser()
    extra = WALL if command in ("compare", "macro", "micro") else []
    assert parser.parse_args([command, *extra]).verbosity == NORMAL
    assert parser.parse_args([command, *extra, "-q"]).verbosity == QUIET
    assert parser.parse_args([command, *extra, "--verbose"]).verbosity == VERBOSE
    help_text = parser._subparsers._group_actions[0].choices[command].format_help()  # type: ignore[union-attr]
    for code in ("0 ", "1 ", "2 ", "130"):
        assert f"\n  {code}" in help_text


def test_quiet_and_verbose_exclude_each_other(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["macro", *WALL, "-q", "-v"]) == EXIT_USAGE
    assert capsys.readouterr().err.count("\n") == 1


def test_quiet_prints_the_load_factor_alone(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["macro", *WALL, "--quiet"]) == 0
    assert capsys.readouterr().out == "0.648067\n"  # Table 7, Set 12: the paper's 0.65
    assert main(["micro", *WALL, "--solver", "clarabel", "--quiet"]) == 0
    assert float(capsys.readouterr().out) == pytest.approx(0.712047, abs=2e-6)


def test_verbose_prints_more(capsys: pytest.CaptureFixture[str]) -> None:
    main(["macro", *WALL])
    normal = capsys.readouterr().out
    main(["macro", *WALL, "--verbose"])
    verbose = capsys.readouterr().out
    assert verbose.startswith(normal) and "paper parameters: t = 1" in verbose
    main(["micro", *WALL, "--friction", "nonassociative", "-v"])
    lines = capsys.readouterr().out.splitlines()
    assert any(line.strip().startswith("7  0.708622") and line.endswith("certified") for line in lines)


def test_failed_method_exits_1_and_prints_no_number(capsys: pytest.CaptureFixture[str]) -> None:
    rc = main(["micro", *WALL, "--friction", "nonassociative", "--max-iterations", "2", "--tuning", "selection=vertex",
               "--quiet"])
    out = capsys.readouterr().out
    assert rc == EXIT_FAILED
    assert out.startswith("status max_iterations")
