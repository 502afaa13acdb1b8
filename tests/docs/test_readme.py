"""What a newcomer meets first in README.md: the set-up commands, the environment, how long things take,
and a synopsis whose required options are required."""

from __future__ import annotations

import argparse
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from comparison.cli import app as cli

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
#: A fenced shell block: its first line number and its text.
SHELL_BLOCK = re.compile(r"^```(?:sh|bash|shell|console)\n(.*?)^```", re.M | re.S)
#: How a line says how long it runs: a trailing comment with a duration ("~1 min", "16-19 min", "40 s").
DURATION = re.compile(r"#.*\b\d+(?:-\d+)?\s*(?:s|min|minutes|seconds|h)\b")
#: The line that activates the environment the set-up commands install into.
ACTIVATE = "source .venv/bin/activate"


def _shell_lines() -> list[tuple[int, str]]:
    """Every line of every shell block with its line number in README.md."""
    out = []
    for m in SHELL_BLOCK.finditer(README):
        first = README.count("\n", 0, m.start(1)) + 1
        out += [(first + i, line) for i, line in enumerate(m.group(1).splitlines()) if line.strip()]
    return out


def _programs(line: str) -> list[str]:
    """The program of each command of ``line`` (commands joined by ``&&``), comments dropped."""
    return [shlex.split(part, comments=True)[0] for part in line.split("#")[0].split("&&") if part.strip()]


def test_the_set_up_commands_run_what_they_install_and_say_how_long_they_take() -> None:
    """The set-up commands call the environment they install (``.venv/bin/...``: no PATH to get right), the
    first builds the quick report, not the full one, and each says on its own line how long it runs."""
    first = SHELL_BLOCK.search(README)
    assert first is not None
    lines = [line for line in first.group(1).splitlines() if line.strip()]
    assert len(lines) == 2 and all(line.startswith("python3 -m venv .venv && .venv/bin/pip install") for line in lines)
    for line in lines:
        programs = _programs(line)
        assert programs[0] == "python3" and all(p.startswith(".venv/bin/") for p in programs[1:]), line
        assert DURATION.search(line), f"README's set-up line does not say how long it runs: {line}"
    assert ".venv/bin/xcheck report --quick" in lines[0] and lines[1].split("#")[0].rstrip().endswith("pytest")


def test_each_set_up_time_says_what_it_covers() -> None:
    """A set-up line installs, then runs the report or the tests: its comment names what its figures time
    (that program alone) before the figures, and the paragraph under the block says what they leave out
    (the install and the macro kernel's first compilation), so a reader timing the whole line is told why it
    takes longer."""
    first = SHELL_BLOCK.search(README)
    assert first is not None
    lines = [line for line in first.group(1).splitlines() if line.strip()]
    for line, timed in zip(lines, ("report", "tests"), strict=True):
        comment = line.split("#", 1)[1].strip()
        assert re.match(rf"the {timed} alone: \d", comment), f"README's set-up line does not say what it times: {line}"
    after = README[first.end():].split("\n\n", 2)[1]
    assert re.search(r"leave out the install\b", after) and "first compilation" in after, after


def test_every_report_command_says_how_long_it_runs() -> None:
    """A line of README.md that starts a report says on that line how long it runs (a reader decides before
    running it)."""
    report = [(n, line) for n, line in _shell_lines() if re.search(r"\bxcheck report\b", line)]
    assert report
    for n, line in report:
        assert DURATION.search(line), f"README.md:{n}: `{line}` does not say how long it runs"


def test_the_durations_are_those_measured_on_the_speed_page() -> None:
    """Each run time is measured once, on docs/speed.md's "Run times" table: every duration a README command
    line gives ("19 s", "14 min", "20-22 min") is one that table states, so the two cannot drift apart."""
    speed = (ROOT / "docs" / "speed.md").read_text(encoding="utf-8")
    table = speed.split("## Run times", 1)[1].split("\n## ", 1)[0]
    said = [(n, d) for n, line in _shell_lines() if "#" in line
            for d in re.findall(r"\d[\d,]*(?:-\d+)?\s*(?:s|min)\b", line.split("#", 1)[1])]  # fmt: skip
    assert len(said) >= 5
    for n, duration in said:
        assert duration in table, f"README.md:{n}: {duration!r} is not a run time of docs/speed.md's table"


def test_the_environment_is_activated_before_the_first_bare_xcheck() -> None:
    """The README says to activate ``.venv`` once, before its first bare ``xcheck`` command (without it the
    command is not found after the set-up line)."""
    bare = next(n for n, line in _shell_lines() if _programs(line) and _programs(line)[0] == "xcheck")
    said = README.find(ACTIVATE)
    assert said >= 0, f"README.md never says `{ACTIVATE}`"
    assert README.count("\n", 0, said) + 1 < bare, f"README.md says `{ACTIVATE}` after its first bare xcheck"
    assert README.count(ACTIVATE) == 1


@pytest.mark.skipif(sys.prefix == sys.base_prefix or os.name != "posix", reason="the tests run outside a venv")
def test_the_activation_line_makes_xcheck_a_command() -> None:
    """The README's activation line, run for this environment in a shell whose PATH lacks it, makes
    ``xcheck`` a command."""
    bin_dir = Path(sys.prefix) / "bin"
    if not (bin_dir / "xcheck").exists():
        pytest.skip("xcheck is not installed in this environment")
    line = ACTIVATE.replace(".venv", shlex.quote(sys.prefix))
    path = os.pathsep.join(p for p in os.environ.get("PATH", "").split(os.pathsep) if Path(p) != bin_dir)
    env = {**os.environ, "PATH": path}
    env.pop("VIRTUAL_ENV", None)
    before = subprocess.run(["bash", "-c", "command -v xcheck"], env=env, capture_output=True, text=True)
    assert Path(before.stdout.strip() or "/").parent != bin_dir
    run = subprocess.run(["bash", "-c", f"{line} && xcheck --version"], env=env, capture_output=True, text=True,
                         timeout=60)  # fmt: skip
    assert run.returncode == 0 and run.stdout.startswith("xcheck "), run.stderr


def _synopsis() -> dict[str, str]:
    """The README's synopsis: each command's text (continuation lines joined), and ``WALL``'s."""
    block = README.split("## Command line", 1)[1].split("```text\n", 1)[1].split("```", 1)[0]
    out: dict[str, str] = {}
    last = ""
    for line in block.splitlines():
        if line.startswith("xcheck "):
            last = line.split()[1]
            out[last] = line.split(None, 2)[2]
        elif line.startswith("WALL ="):
            last = "WALL"
            out[last] = line.split("=", 1)[1].split("(")[0]
        elif line.startswith(" ") and last:
            out[last] += " " + line.strip()
    return out


def _shown_required(text: str) -> list[str]:
    """The options ``text`` shows outside brackets and outside ``( | )`` alternatives."""
    depth, out, word = 0, [], ""
    for ch in text + " ":
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        elif ch.isspace():
            if word.startswith("--") and depth == 0:
                out.append(word)
            word = ""
            continue
        if depth == 0 and ch not in "[]()":
            word += ch
    return out


FULL_WALL = {"--storeys": "3", "--rows": "12", "--t": "1", "--m": "1/3", "--f": "0.75"}


def test_the_synopsis_shows_every_optional_option_in_brackets(capsys: pytest.CaptureFixture[str]) -> None:
    """An option the synopsis shows outside brackets is required: argparse requires it, or (the wall's
    parameters) the command refuses the wall without it (exit 2); an option with a default, such as
    ``--friction``, is in brackets."""
    synopsis = _synopsis()
    assert {"macro", "micro", "report", "sweep", "WALL"} <= set(synopsis)
    sub = next(a for a in cli.build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    wrong = []
    for command, text in synopsis.items():
        for option in _shown_required(text):
            if command == "WALL":
                argv = [x for k, v in FULL_WALL.items() if k != option for x in (k, v)]
                if cli.main(["macro", *argv, "-q"]) != 2:
                    wrong.append(f"WALL: {option} (the wall is accepted without it)")
                continue
            action = next(a for a in sub.choices[command]._actions if option in a.option_strings)
            if not action.required:
                wrong.append(f"xcheck {command}: {option} (default {action.default!r})")
    capsys.readouterr()
    assert not wrong, "README's synopsis shows optional options as required: " + "; ".join(wrong)


def test_the_first_screen_carries_no_dated_measurement() -> None:
    """The README's first 30 lines carry no date, host or machine load: measurements live in docs/
    (docs/speed.md, dated pages in docs/research/), linked."""
    head = "\n".join(README.splitlines()[:30])
    for pattern in (r"\b20\d\d-\d\d-\d\d\b", r"\bhosts?\b", r"\bload of\b"):
        found = re.search(pattern, head, re.I)
        assert found is None, f"README's first 30 lines: {found.group(0)!r}"
    assert "docs/speed.md" in head
