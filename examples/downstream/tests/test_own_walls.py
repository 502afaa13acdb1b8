"""Your own walls (``walls.toml``) and the plugin's ``xcheck_case`` fixture.

``pytest --xcheck-walls walls.toml`` runs ``test_physical_bounds`` on those
walls; without options it runs on every case of the paper.
"""

from __future__ import annotations

from pathlib import Path

import toy_macro

from comparison.pytest_plugin import walls_from_file

WALLS = Path(__file__).with_name("walls.toml")


def test_physical_bounds(xcheck_case) -> None:
    """Whatever the wall, the toy's λ is positive and never above f or the whole wall's overturning L/H."""
    lam = toy_macro.load_factor(xcheck_case.t, xcheck_case.m, xcheck_case.f)
    assert 0.0 < lam <= min(xcheck_case.f, 1.0 / xcheck_case.t) + 1e-12


def test_walls_file_reads() -> None:
    walls = walls_from_file(WALLS)
    assert [w.label for w in walls] == ["slender pier", "squat wall"]
    assert walls[0].m == 1 / 3
