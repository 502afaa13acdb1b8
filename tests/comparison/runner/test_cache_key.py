"""The result cache is keyed on what the code does, not on its text.

A docstring, comment or layout edit of a hashed module keeps every cached result (a sweep run again computes
nothing); a change of behaviour (a constant) recomputes them. The edits are made to the sources
:func:`~comparison.runner.cache.code_version` hashes, through its :func:`~comparison.runner.cache.source`
seam, so the package itself is not touched.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
from quick_report import Sweep

from comparison.cli import main
from comparison.runner import cache as cache_module
from comparison.runner.cache import behaviour, code_version

ROOT = Path(__file__).resolve().parents[3]
TINY = ROOT / "examples" / "sweeps" / "tiny.toml"
LP = ROOT / "micro" / "lp.py"
TEXT = LP.read_text()

#: Edits of ``micro/lp.py`` that change no behaviour: its module docstring, a comment, the layout.
KEEPS = {
    "docstring": lambda s: s.replace('"""Assembly of the static', '"""Assembly (reworded) of the static', 1),
    "comment": lambda s: s.replace("\nfrom __future__ import annotations\n",
                                   "\nfrom __future__ import annotations  # a new comment\n", 1),
    "layout": lambda s: s.replace("\nfrom __future__ import annotations\n",
                                  "\n\n\nfrom __future__ import annotations\n", 1),
}


def _edited(monkeypatch: pytest.MonkeyPatch, edit: Callable[[str], str]) -> None:
    """``micro/lp.py`` as ``edit`` makes it, for the cache key from now on."""
    new = edit(TEXT)
    assert new != TEXT
    real = cache_module.source
    monkeypatch.setattr(cache_module, "source", lambda path: new.encode() if path == LP else real(path))
    code_version.cache_clear()


@pytest.fixture(autouse=True)
def _fresh_versions():
    code_version.cache_clear()
    yield
    code_version.cache_clear()


def _computed(tmp_path: Path, cache: Path) -> int:
    out = tmp_path / "out"
    assert main(["sweep", str(TINY), "--out", str(out), "--cache", str(cache), "--workers", "1", "-q"]) == 0
    return int(json.loads((out / "tiny.json").read_text())["counts"]["computed"])


@pytest.mark.parametrize("edit", list(KEEPS))
def test_an_edit_that_changes_no_behaviour_keeps_the_key(monkeypatch: pytest.MonkeyPatch, edit: str) -> None:
    before = code_version("micro")
    _edited(monkeypatch, KEEPS[edit])
    assert code_version("micro") == before


def test_a_docstring_edit_leaves_the_tiny_sweep_nothing_to_compute_and_a_behaviour_change_everything(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, tiny_sweep: Sweep
) -> None:
    """The tiny sweep's 8 micro cells, computed from an empty cache by the unedited code (the suite's shared
    run, ``tests/conftest.py``, in a copy of its cache), are all read back; after a docstring edit still all;
    after a change of behaviour all 8 are computed again."""
    assert int(json.loads((tiny_sweep.out / "tiny.json").read_text())["counts"]["computed"]) == 8
    cache = tmp_path / "cache"
    shutil.copytree(tiny_sweep.cache, cache)
    assert _computed(tmp_path, cache) == 0
    _edited(monkeypatch, KEEPS["docstring"])
    assert _computed(tmp_path, cache) == 0
    _edited(monkeypatch, lambda s: s + "\nA_NEW_CONSTANT = 1\n")
    assert _computed(tmp_path, cache) == 8


def test_docstrings_are_removed_at_every_level_and_code_strings_kept() -> None:
    plain = "def f(x):\n    return x + 1\n\nclass C:\n    a = 'kept'\n"
    documented = ('"""Module."""\ndef f(x):\n    """What f does."""\n    # why\n    return x + 1\n\n'
                  'class C:\n    """A class."""\n    a = \'kept\'\n    """Attribute note."""\n')
    assert behaviour(plain.encode()) == behaviour(documented.encode())
    assert behaviour(plain.encode()) != behaviour(plain.replace("'kept'", "'other'").encode())
    assert behaviour(b"def (") == b"unparsed:def ("
