"""The grid files installed with the package: the same as the examples', readable, and named by the report's
warning for a missing sweep table."""

from __future__ import annotations

import shlex
import tomllib
from pathlib import Path

import pytest

from comparison.report.committed import BOND, ERRORMAP, LOWEST, made_by
from comparison.sweep import load_grid
from comparison.sweep.grids import FOLDER, NAMES, grid_path

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize("name", NAMES)
def test_packaged_grid_is_the_example(name: str) -> None:
    """Each packaged grid is byte for byte ``examples/sweeps/NAME.toml``: the committed sweep and the one a
    user without a clone remakes run the same walls."""
    assert grid_path(name).read_bytes() == (ROOT / "examples" / "sweeps" / f"{name}.toml").read_bytes()


@pytest.mark.parametrize("name", NAMES)
def test_packaged_grid_loads(name: str) -> None:
    """The packaged file is a valid grid of the name it carries."""
    assert load_grid(grid_path(name)).name == name


def test_packaged_grids_are_package_data() -> None:
    """pyproject's package data ships every packaged grid (``*.toml`` of the grids' package)."""
    data = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]["package-data"]
    assert data["comparison.sweep.grids"] == ["*.toml"]
    assert sorted(p.stem for p in FOLDER.glob("*.toml")) == sorted(NAMES)


def test_unknown_packaged_grid_is_refused() -> None:
    with pytest.raises(ValueError, match="no packaged grid 'tiny': the package carries errormap, table9_bond"):
        grid_path("tiny")


def test_the_warning_names_a_command_that_runs_without_a_clone(tmp_path: Path) -> None:
    """The command the report prints for a missing sweep table names the installed grid file (no
    ``examples/`` path, which only a clone has) and the tables directory; each word of it is a file that exists
    or an option."""
    for name, grid in ((ERRORMAP, "errormap"), (BOND, "table9_bond")):
        argv = shlex.split(made_by(name, tmp_path / "my tables"))
        assert argv[:2] == ["xcheck", "sweep"] and "examples/" not in argv[2]
        assert Path(argv[2]) == grid_path(grid) and Path(argv[2]).is_file()
        assert argv[3:] == ["--out", str(tmp_path / "my tables" / "sweeps")]
    assert shlex.split(made_by(LOWEST, tmp_path)) == ["xcheck", "stability", "--lowest", "--out", str(tmp_path)]
