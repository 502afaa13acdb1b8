"""The result cache's key is what the computation runs: every repository module it imports (by what the
module does, not its text), the versions of the packages they import, and Python's minor version.

The edits are made for real, to a copy of the repository's packages that the fingerprint is pointed at
(:data:`comparison.runner.fingerprint.ROOT`), so that the memo of each file's hash (on its stat) is
exercised as a user's edit exercises it; the code that runs is the repository's own.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest
from quick_report import Sweep

from comparison.cli import main
from comparison.runner import ResultCache
from comparison.runner import fingerprint as fp
from comparison.runner.fingerprint import behaviour, code_version, fingerprint, imported_modules
from comparison.runner.runner import compute

ROOT = Path(__file__).resolve().parents[3]
TINY = ROOT / "examples" / "sweeps" / "tiny.toml"
NEW_CONSTANT = "\nA_NEW_CONSTANT = 1\n"


@pytest.fixture(autouse=True)
def _fresh_fingerprint() -> Iterator[None]:
    fingerprint.cache_clear()
    yield
    fingerprint.cache_clear()


@pytest.fixture
def copy(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A copy of the repository's packages, which the fingerprint reads from now on."""
    root = tmp_path / "repo"
    for package in fp.REPOSITORY_PACKAGES:
        shutil.copytree(ROOT / package, root / package, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(fp, "ROOT", root)
    return root


def _edit(path: Path, text: str) -> None:
    path.write_text(text)
    fingerprint.cache_clear()


def _docstring_edited(text: str) -> str:
    """``text`` (a module that starts with its docstring, as every module here does) with it reworded."""
    assert text.startswith('"""')
    return '"""Edited. ' + text[3:]


def test_the_graph_starts_at_the_computation_and_holds_what_it_imports() -> None:
    assert compute.__module__ == fp.COMPUTATION
    graph = imported_modules()
    for module in ("comparison.domain.wall", "comparison.domain.wall_mechanism", "comparison.domain.failure",
                   "comparison.runner.records", "macro.solve", "macro.kernel", "micro.lp", "micro.hold",
                   "micro.nonassociative.iteration", "micro.backends.highs", "micro.backends.normal_ipm",
                   "micro.backends.cvxpy_"):
        assert module in graph.modules, module  # the back ends: imported by name (the registry)
    assert "comparison.cli" not in graph.modules and "comparison.report" not in graph.modules
    for package in ("numpy", "scipy", "highspy", "clarabel", "cvxopt", "numba"):
        assert package in graph.third_party
    assert not {"os", "json", "__future__", "macro", "micro", "comparison"} & set(graph.third_party)


def test_a_behaviour_edit_of_each_module_is_a_new_key_and_a_docstring_edit_is_not(copy: Path) -> None:
    """Every module of the graph is in the key by its behaviour hash; each one's hash changes with a behaviour
    edit (a new constant) and keeps with a docstring edit; and the key follows the hash of any module, here
    edited for real through the memo on its stat (the first, a middle and the last module of the graph)."""
    base = fingerprint()
    graph = imported_modules(fp.COMPUTATION, None, copy)
    modules = [path for path, _ in graph.modules.values()]
    assert len(modules) > 60 and set(base.modules) == {p.relative_to(copy).as_posix() for p in modules}
    for path in modules:
        text, package = path.read_text(), ".".join(path.relative_to(copy).with_suffix("").parts[:-1])
        sha = next(sha for file, sha in graph.modules.values() if file == path)
        edited = {"docstring": _docstring_edited(text), "behaviour": text + NEW_CONSTANT}
        facts = {what: fp.read_facts(_written(path, body), package).sha for what, body in edited.items()}
        path.write_text(text)
        assert facts["docstring"] == sha, f"a docstring edit of {path.relative_to(copy)} changed its hash"
        assert facts["behaviour"] != sha, f"a behaviour edit of {path.relative_to(copy)} kept its hash"
    for path in (modules[0], modules[len(modules) // 2], modules[-1]):
        text = path.read_text()
        _edit(path, _docstring_edited(text))
        assert code_version() == base.digest, f"a docstring edit of {path.relative_to(copy)} changed the key"
        _edit(path, text + NEW_CONSTANT)
        assert code_version() != base.digest, f"a behaviour edit of {path.relative_to(copy)} kept the key"
        _edit(path, text)
    assert code_version() == base.digest


def _written(path: Path, text: str) -> Path:
    """``path`` with ``text`` written into it."""
    path.write_text(text)
    return path


def test_a_new_module_the_computation_imports_joins_the_key(copy: Path) -> None:
    base = fingerprint().modules
    (copy / "comparison" / "new_helper.py").write_text('"""A helper."""\nVALUE = 1\n')
    local = copy / "comparison" / "domain" / "wall_mechanism.py"
    _edit(local, local.read_text() + "\nfrom comparison.new_helper import VALUE\n")
    assert set(fingerprint().modules) - set(base) == {"comparison/new_helper.py"}


def _computed(tmp_path: Path, cache: Path) -> int:
    out = tmp_path / "out"
    assert main(["sweep", str(TINY), "--out", str(out), "--cache", str(cache), "--workers", "1", "-q",
                 "--no-report"]) == 0
    return int(json.loads((out / "tiny.json").read_text())["counts"]["computed"])


def test_an_edit_of_the_walls_conversion_to_the_block_model_recomputes_the_tiny_sweep(
    tmp_path: Path, copy: Path, tiny_sweep: Sweep
) -> None:
    """The tiny sweep's 8 micro cells, computed once from an empty cache (the suite's shared run), are all
    read back; after a docstring edit of ``WallSpec.to_micro`` still all; after an edit that gives the block
    wall half the friction, all 8 are computed again."""
    cache = tmp_path / "cache"
    shutil.copytree(tiny_sweep.cache, cache)
    assert _computed(tmp_path, cache) == 0
    wall = copy / "comparison" / "domain" / "wall.py"
    text = wall.read_text()
    start = text.index("    def to_micro(")
    doc = text.index('"""', start)
    _edit(wall, text[:doc + 3] + "Reworded. " + text[doc + 3:])
    assert _computed(tmp_path, cache) == 0
    call = 'micro.build_wall(**self.dimensions(), **{"ends": self.ends, **options})'
    assert text.index(call) > start
    half = 'micro.build_wall(**{**self.dimensions(), "friction": self.friction / 2}, **{"ends": self.ends, **options})'
    _edit(wall, text.replace(call, half))
    assert _computed(tmp_path, cache) == 8


def test_another_dependency_version_or_python_misses_every_entry(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from comparison.domain.wall import WallSpec
    from comparison.runner import MACRO

    spec = WallSpec.from_paper(t=1, m=1 / 3, rows=6, f=0.75)
    cache = ResultCache(tmp_path / "cache")
    assert cache.store(spec, *compute(spec, MACRO))
    assert cache.load(spec, MACRO) is not None
    real = fp.dependency_versions
    monkeypatch.setattr(fp, "dependency_versions", lambda names: {**real(names), "highspy": "0.0.1"})
    fingerprint.cache_clear()
    assert cache.load(spec, MACRO) is None
    monkeypatch.setattr(fp, "dependency_versions", real)
    fingerprint.cache_clear()
    assert cache.load(spec, MACRO) is not None
    monkeypatch.setattr(fp, "python_minor", lambda: "3.99")
    fingerprint.cache_clear()
    assert cache.load(spec, MACRO) is None


def test_a_warm_key_parses_no_module(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A second process (an empty in-process memo) reads each file's hash from the cache folder's memo and
    parses nothing; a damaged memo is read as empty, never trusted."""
    folder = tmp_path / "cache"
    base = code_version(folder)
    assert (folder / fp.MEMO_FILE).is_file()
    monkeypatch.setattr(fp, "_READ", {})
    fingerprint.cache_clear()

    def parse(path: Path) -> bytes:
        raise AssertionError(f"{path} parsed on a warm key")

    with monkeypatch.context() as m:
        m.setattr(fp, "source", parse)
        assert code_version(folder) == base
    (folder / fp.MEMO_FILE).write_text('{"damaged')
    monkeypatch.setattr(fp, "_READ", {})
    fingerprint.cache_clear()
    assert code_version(folder) == base


def test_docstrings_are_removed_at_every_level_and_code_strings_kept() -> None:
    plain = "def f(x):\n    return x + 1\n\nclass C:\n    a = 'kept'\n"
    documented = ('"""Module."""\ndef f(x):\n    """What f does."""\n    # why\n    return x + 1\n\n'
                  'class C:\n    """A class."""\n    a = \'kept\'\n    """Attribute note."""\n')
    assert behaviour(plain.encode()) == behaviour(documented.encode())
    assert behaviour(plain.encode()) != behaviour(plain.replace("'kept'", "'other'").encode())
    assert behaviour(b"def (") == b"unparsed:def ("


def test_the_report_names_the_versions_in_the_key(monkeypatch: pytest.MonkeyPatch) -> None:
    """The report's "How to reproduce" names the versions the key holds (so a result read from the cache was
    computed under them), not a list of its own: a faked highspy version is the one it prints."""
    from comparison.report.reproduce import how_to_reproduce

    real = fp.dependency_versions
    monkeypatch.setattr(fp, "dependency_versions", lambda names: {**real(names), "highspy": "0.0.1"})
    text = how_to_reproduce({"quick": True})
    assert "highspy 0.0.1" in text and f"code fingerprint {code_version()}" in text
    for name, version in fingerprint().versions.items():
        assert f"{name} {version}" in text
