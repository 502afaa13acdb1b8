"""The examples of README.md and docs/ run as written.

Every fenced ``sh`` block is a list of ``xcheck`` commands, each run in a temporary folder (with a copy
of ``examples/`` and of the report's committed tables) by the ``xcheck`` of this environment: its entry
point :func:`comparison.cli.main`, the function the console script calls, in this process (a process per
command would cost a second of imports each; the console script itself is run by
``tests/comparison/cli/test_cli_macro.py``); it fails on an exit code other than 0. A command that hangs
for :data:`TIMEOUT` seconds ends the run with every thread's traceback. Every fenced ``python`` block is
run as a script in such a folder, as ``__main__`` in this process too (:mod:`runpy`, a fresh namespace, the
folder first on ``sys.path``; an exception is exit 1), under the same hang guard. A block preceded by an
HTML comment is marked:

* ``<!-- skip-example: REASON -->``: not run (synopses with placeholders, installs, long runs);
* ``<!-- expect-exit: N -->``: its commands must exit with ``N``.

Every command that writes files names a folder of its own (``--out``), never the clone's committed
``reports/``, skipped blocks included; and the committed tables copied into each example's folder are
unchanged after it ran, so an example that wrote into ``reports/`` fails.

A command written on several pages runs once (the first page, in the order README.md, docs/ sorted);
its other blocks run only their other commands.

``text``, ``toml`` and unlabelled blocks are not examples. The dated pages of ``docs/research/`` are a log
kept as it was measured (their commands are those of their date) and are not collected.
"""

from __future__ import annotations

import contextlib
import faulthandler
import hashlib
import io
import re
import runpy
import shlex
import shutil
import sys
import traceback
from dataclasses import dataclass
from pathlib import Path

import matplotlib.figure
import pytest
from quick_report import QuickReport, Sweep

from comparison.cli import main

ROOT = Path(__file__).resolve().parents[2]
#: Longest run of one example, seconds.
TIMEOUT = 120
#: Fence languages that hold commands, and those that hold Python.
SHELL = {"sh", "bash", "console", "shell"}
PYTHON = {"python", "py"}
#: The subcommands that write files, each given ``--out``.
WRITERS = {"report", "stability", "sweep", "references"}
MARK = re.compile(r"<!--\s*(skip-example|expect-exit)\s*:\s*(.*?)\s*-->")
FENCE = re.compile(r"^```(\w*)\s*$")


@dataclass(frozen=True)
class Example:
    """One fenced block of a page."""

    page: str
    line: int
    language: str
    text: str
    skip: str | None = None
    exit_code: int = 0

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}"


def pages() -> list[Path]:
    """README.md and every page of docs/ but the research log."""
    docs = sorted(p for p in (ROOT / "docs").rglob("*.md") if "research" not in p.relative_to(ROOT / "docs").parts)
    return [ROOT / "README.md", *docs]


def blocks(path: Path) -> list[Example]:
    """The fenced blocks of ``path`` with their marks."""
    lines = path.read_text(encoding="utf-8").splitlines()
    out: list[Example] = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        j = i + 1
        while j < len(lines) and not lines[j].startswith("```"):
            j += 1
        prev = next((lines[k] for k in range(i - 1, -1, -1) if lines[k].strip()), "")
        mark = MARK.search(prev)
        skip = mark.group(2) if mark and mark.group(1) == "skip-example" else None
        code = int(mark.group(2)) if mark and mark.group(1) == "expect-exit" else 0
        out.append(Example(str(path.relative_to(ROOT)), i + 1, m.group(1), "\n".join(lines[i + 1 : j]), skip, code))
        i = j + 1
    return out


def commands(text: str) -> list[list[str]]:
    """The commands of a shell block: lines joined at a trailing backslash, ``$ `` prompts and comments
    dropped."""
    joined = re.sub(r"\\\n\s*", " ", text)
    out = []
    for line in joined.splitlines():
        line = line.strip().removeprefix("$ ")
        if line and not line.startswith("#"):
            out.append(shlex.split(line, comments=True))
    return out


ALL = [b for p in pages() for b in blocks(p)]
SHELL_BLOCKS = [b for b in ALL if b.language in SHELL]
PYTHON_BLOCKS = [b for b in ALL if b.language in PYTHON]


def _xcheck(argv: list[str]) -> list[str] | None:
    """The arguments of ``xcheck`` for ``argv`` when it is an ``xcheck`` command, else ``None``."""
    if argv and Path(argv[0]).name == "xcheck":
        return argv[1:]
    return None


def _run_xcheck(args: list[str]) -> tuple[int, str, str]:
    """Exit code, standard output and error of ``xcheck ARGS`` run by its entry point in this process, with a
    hang guard of :data:`TIMEOUT` seconds (the whole run ends with every thread's traceback)."""
    out, err = io.StringIO(), io.StringIO()
    faulthandler.dump_traceback_later(TIMEOUT, exit=True)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(args)
            except SystemExit as stop:  # argparse's --help, --version and usage errors
                code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
    finally:
        faulthandler.cancel_dump_traceback_later()
    return code, out.getvalue(), err.getvalue()


def _first_seen() -> dict[tuple[str, ...], str]:
    """Each command of an unmarked shell block, with the block that runs it (the first one)."""
    seen: dict[tuple[str, ...], str] = {}
    for b in SHELL_BLOCKS:
        if not b.skip:
            for argv in commands(b.text):
                seen.setdefault((*argv, f"exit {b.exit_code}"), b.id)
    return seen


FIRST = _first_seen()


@pytest.fixture(scope="module")
def cache(
    tmp_path_factory: pytest.TempPathFactory, quick_report: QuickReport, own_walls_sweep: Sweep, tiny_sweep: Sweep
) -> Path:
    """One result cache for every example, started from copies of the caches of the suite's shared runs
    (``tests/conftest.py``): ``report --quick``, the own-walls sweep and the tiny sweep read every computation
    from it, as on a second run, and ``references`` shares it."""
    copy = tmp_path_factory.mktemp("xcheck-cache") / "cache"
    shutil.copytree(quick_report.cache, copy)
    shutil.copytree(own_walls_sweep.cache, copy, dirs_exist_ok=True)
    shutil.copytree(tiny_sweep.cache, copy, dirs_exist_ok=True)
    return copy


def _folder(tmp_path: Path) -> Path:
    """A working folder like a clone's: ``examples/`` and the report's committed tables."""
    shutil.copytree(ROOT / "examples", tmp_path / "examples", ignore=shutil.ignore_patterns(".venv", "__pycache__"))
    shutil.copytree(ROOT / "reports" / "sweeps", tmp_path / "reports" / "sweeps")
    shutil.copy2(ROOT / "reports" / "lowest.csv", tmp_path / "reports" / "lowest.csv")
    return tmp_path


def _snapshot(folder: Path) -> dict[str, str]:
    """Every file under ``folder/reports`` with the digest of its bytes."""
    root = folder / "reports"
    return {str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(root.rglob("*"))
            if p.is_file()}  # fmt: skip


def _split(argv: list[str]) -> list[list[str]]:
    """The commands of a line chained with ``&&``."""
    out: list[list[str]] = [[]]
    for word in argv:
        if word == "&&":
            out.append([])
        else:
            out[-1].append(word)
    return [c for c in out if c]


def test_commands_that_write_name_their_own_folder() -> None:
    """Every ``xcheck report|stability|sweep|references`` of the pages (skipped blocks too: a reader runs
    them) names ``--out``, and not the clone's committed ``reports/``: without it ``report`` and
    ``stability`` write into ``reports/`` and change the committed files."""
    seen = 0
    for b in SHELL_BLOCKS:
        for line in commands(b.text):
            for argv in _split(line):
                if Path(argv[0]).name != "xcheck" or len(argv) < 2 or argv[1] not in WRITERS:
                    continue
                seen += 1
                assert "--out" in argv, f"{b.id}: `{shlex.join(argv)}` names no --out folder"
                out = Path(argv[argv.index("--out") + 1])
                assert out.parts[0] != "reports", f"{b.id}: `{shlex.join(argv)}` writes into the committed reports/"
    assert seen >= 8


def test_examples_are_collected() -> None:
    """The collector sees the README's commands and Python, and every page's blocks are marked or runnable."""
    readme = [b for b in SHELL_BLOCKS if b.page == "README.md" and not b.skip]
    assert sum(len(commands(b.text)) for b in readme) >= 4
    assert any(b.page == "README.md" and not b.skip for b in PYTHON_BLOCKS)
    # an unmarked shell block holds xcheck commands only: nothing is silently left out
    for b in SHELL_BLOCKS:
        if not b.skip:
            for argv in commands(b.text):
                assert _xcheck(argv) is not None, f"{b.id}: {shlex.join(argv)} is not an xcheck command; mark the block"
    # every skip says why
    assert all(b.skip.strip() for b in ALL if b.skip is not None)


@pytest.mark.parametrize("block", SHELL_BLOCKS, ids=[b.id for b in SHELL_BLOCKS])
def test_shell_example(block: Example, tmp_path: Path, cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if block.skip:
        pytest.skip(block.skip)
    folder = _folder(tmp_path)
    committed = _snapshot(folder)
    monkeypatch.chdir(folder)
    monkeypatch.setenv("XCHECK_CACHE", str(cache))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    # the figures are drawn but not encoded (placeholders): what they show is the figures' tests' business
    # (tests/comparison/report/test_report_figures.py, ...); a command's run and its files are this test's
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", _placeholder)
    for argv in commands(block.text):
        if FIRST[(*argv, f"exit {block.exit_code}")] != block.id:
            continue  # run where it is first written
        args = _xcheck(argv)
        assert args is not None, f"{block.id}: not an xcheck command: {shlex.join(argv)}"
        code, out, err = _run_xcheck(args)
        assert code == block.exit_code, (
            f"{block.id}: `{shlex.join(argv)}` exited with {code}, expected {block.exit_code}\n"
            f"stdout: {out[-2000:]}\nstderr: {err[-2000:]}"
        )
    assert _snapshot(folder) == committed, f"{block.id}: an example wrote into the committed reports/"


def _placeholder(fig: matplotlib.figure.Figure, fname: object, **kwargs: object) -> None:
    """``Figure.savefig`` without the encoding: a few bytes where the image would be."""
    if hasattr(fname, "write"):
        fname.write(b"a figure")
    else:
        Path(str(fname)).write_bytes(b"a figure")


def _run_script(script: Path) -> tuple[int, str]:
    """Exit code and standard error of ``python SCRIPT`` run as ``__main__`` in this process (:mod:`runpy`:
    a fresh namespace, so a missing import fails as in a process of its own; a process per example would
    cost a second of imports each), with the hang guard of :func:`_run_xcheck`; an exception is exit 1 with
    its traceback, as the interpreter gives it."""
    err = io.StringIO()
    faulthandler.dump_traceback_later(TIMEOUT, exit=True)
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            try:
                runpy.run_path(str(script), run_name="__main__")
                code = 0
            except SystemExit as stop:
                code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
            except Exception:
                traceback.print_exc()
                code = 1
    finally:
        faulthandler.cancel_dump_traceback_later()
        if "matplotlib.pyplot" in sys.modules:  # an example's figures do not outlive it
            sys.modules["matplotlib.pyplot"].close("all")
    return code, err.getvalue()


@pytest.mark.parametrize("block", PYTHON_BLOCKS, ids=[b.id for b in PYTHON_BLOCKS])
def test_python_example(block: Example, tmp_path: Path, cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if block.skip:
        pytest.skip(block.skip)
    folder = _folder(tmp_path)
    committed = _snapshot(folder)
    script = folder / "example.py"
    script.write_text(block.text + "\n", encoding="utf-8")
    monkeypatch.chdir(folder)
    monkeypatch.setenv("XCHECK_CACHE", str(cache))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.syspath_prepend(str(folder))  # the script's folder first on sys.path, as for ``python SCRIPT``
    code, err = _run_script(script)
    assert code == block.exit_code, f"{block.id}: exited with {code}\n{err[-3000:]}"
    assert _snapshot(folder) == committed, f"{block.id}: the example wrote into the committed reports/"
