"""Names a user gives: one rule (comparison/utilities/names.py) for a sweep's user model and a walls file's walls."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from comparison.pytest_plugin.walls import walls_from_file
from comparison.runner.methods import MACRO, MICRO_ASSOC, MICRO_NONASSOC
from comparison.sweep.usermodel import UserModel
from comparison.utilities.names import BUILT_IN, label, own_method


def test_the_built_in_names_are_the_runners_kinds() -> None:
    assert tuple(m.kind for m in (MACRO, MICRO_ASSOC, MICRO_NONASSOC)) == BUILT_IN


@pytest.mark.parametrize("name", ["my model", "wedge-2", "Set 12 (mine)", "λ model", "macros", "micro"])
def test_a_name_of_ones_own_is_kept_as_given(name: str) -> None:
    assert own_method("name", name) == name == UserModel(name, lambda *a: 0.5).name


@pytest.mark.parametrize("name", ["", "  ", " a", "a ", "a|b", "a`b", "a\nb", "a\tb", None, 3])
def test_a_name_outside_the_rule_is_refused(name: object) -> None:
    with pytest.raises(ValueError, match=r"^name must be a non-empty text without"):
        label("name", name)


@pytest.mark.parametrize("name", ["macro", "micro-assoc", "micro-nonassoc", "MACRO", "micro-assoc (clarabel)",
                                  "micro-nonassoc (scheme b)"])
def test_a_user_model_named_like_a_built_in_method_is_refused(name: str) -> None:
    with pytest.raises(ValueError, match="^" + re.escape(f"name {name!r} is a built-in method's")):
        UserModel(name, lambda *a: 0.5)


def _walls(tmp_path: Path, *names: str) -> Path:
    path = tmp_path / "w.toml"
    path.write_text("".join(f'[[wall]]\nname = "{n}"\nt = 1\nm = 0.5\nrows = 6\nf = 0.6\n' for n in names))
    return path


def test_a_wall_name_given_twice_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"w.toml: wall\[2\]: the name 'pier' is wall\[0\]'s; each wall needs a name"):
        walls_from_file(_walls(tmp_path, "pier", "squat", "pier"))


@pytest.mark.parametrize("name", ["Ref", "12", "Set 12", "7", "table 7", "all"])
def test_a_wall_named_like_a_paper_case_or_table_is_refused(tmp_path: Path, name: str) -> None:
    # "12" would be compared against Set 12's published values (references.case_label reads it so)
    with pytest.raises(ValueError, match=rf"wall\[0\]: the name {name!r} is the paper's"):
        walls_from_file(_walls(tmp_path, name))


@pytest.mark.parametrize("name", [" pier", "a|b"])
def test_a_wall_name_outside_the_rule_is_refused(tmp_path: Path, name: str) -> None:
    with pytest.raises(ValueError, match=r"wall\[0\]: name must be a non-empty text"):
        walls_from_file(_walls(tmp_path, name))
