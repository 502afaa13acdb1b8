"""The physical bounds of a wall, worded alike by every validator (``macro.checks.wall_bounds``).

Extreme but finite inputs once reached the models: ``t = 1e300`` gave
``lambda = nan`` with status optimal, ``m = 1e-300`` a negative lambda,
``p = 1e300`` a RuntimeError from HiGHS. Each is now refused by the shared
bounds with the parameter named, by ``WallSpec``, ``macro.MacroWall``,
``micro.build_wall`` and the paper's parameters alike.
"""

from __future__ import annotations

from typing import Any

import pytest

import macro
import micro
from comparison.domain.wall import StoreySpec, WallSpec
from macro import checks
from micro import wall_checks

DIMENSIONAL = {"length": 12.0, "block_length": 3.0, "block_height": 1.0, "unit_weight": 1.0, "friction": 0.6}
STOREYS = {"rows": (6, 6), "thickness": (1.0, 1.0), "overload": (0.0, 0.0)}
PAPER = {"t": 1.0, "m": 1 / 3, "rows": 12, "f": 0.6, "p": 0.0, "storeys": 1}


def _message(call: Any) -> str:
    with pytest.raises(ValueError) as exc:
        call()
    return str(exc.value)


def _spec(**change: Any) -> Any:
    dims = DIMENSIONAL | STOREYS | change
    storeys = tuple(
        StoreySpec(r, t, q)
        for r, t, q in zip(dims.pop("rows"), dims.pop("thickness"), dims.pop("overload"), strict=True)
    )
    return WallSpec(storeys=storeys, **dims)


BAD_WALLS = [
    ({"length": 1e300}, "length must be in (1e-30, 1e+30], got 1e+300"),
    ({"block_height": 1e-300}, "block_height must be in (1e-30, 1e+30], got 1e-300"),
    ({"unit_weight": 1e31}, "unit_weight must be in (1e-30, 1e+30], got 1e+31"),
    ({"friction": 1e300}, "friction must be in (0.001, 10], got 1e+300"),
    ({"friction": 1e-9}, "friction must be in (0.001, 10], got 1e-09"),
    ({"block_length": 1e7, "length": 2e7}, "block_length must be in (1e-06, 1e+06], got 10000000.0"),
    ({"length": 2e6}, "length must be at most 1e+06, got 2000000.0"),
    ({"thickness": (1.0, 1e7)}, "thickness[1] must be in (1e-06, 1e+06], got 10000000.0"),
    ({"overload": (0.0, 1e300)}, "overload[1] must be at most 1e+06, got 1e+300"),
    ({"rows": (600_000, 600_000)}, "rows must be at most 1e+06, got 1200000"),
]


@pytest.mark.parametrize(("change", "start"), BAD_WALLS, ids=[str(c) for c, _ in BAD_WALLS])
@pytest.mark.parametrize("api", ["WallSpec", "MacroWall", "build_wall"])
def test_every_validator_refuses_the_same_extremes(api: str, change: dict[str, Any], start: str) -> None:
    build = {
        "WallSpec": lambda: _spec(**change),
        "MacroWall": lambda: macro.MacroWall(**(DIMENSIONAL | STOREYS | change)),
        "build_wall": lambda: micro.build_wall(**(DIMENSIONAL | STOREYS | change), max_bytes=1 << 40),
    }[api]
    assert _message(build).startswith(start)


@pytest.mark.parametrize("api", ["WallSpec", "MacroWall"])
def test_a_wall_is_at_least_one_block_long(api: str) -> None:
    change = {"length": 2.0}
    build = _spec if api == "WallSpec" else lambda **c: macro.MacroWall(**(DIMENSIONAL | STOREYS | c))
    assert _message(lambda: build(**change)) == (
        "length must be at least 3, got 2.0: a running-bond wall is at least one block long"
    )


def test_micro_spells_the_same_bounds() -> None:
    assert (wall_checks.MIN_MAGNITUDE, wall_checks.MAX_MAGNITUDE) == (checks.MIN_MAGNITUDE, checks.MAX_MAGNITUDE)
    assert (wall_checks.MAX_RATIO, wall_checks.LENGTH_SLACK) == (checks.MAX_RATIO, checks.LENGTH_SLACK)
    assert (wall_checks.MIN_FRICTION, wall_checks.MAX_FRICTION) == (checks.MIN_FRICTION, checks.MAX_FRICTION)


BAD_PAPER = [
    ({"t": 1e300}, "t must be in [1.2e-05, 4], got 1e+300: a wall at least one block long"),
    ({"t": 100}, "t must be in [1.2e-05, 4], got 100: a wall at least one block long"),
    ({"t": 1e-300}, "t must be in [1.2e-05, 4], got 1e-300"),
    ({"m": 1e-300}, "m must be in (1e-06, 1], got 1e-300"),
    ({"f": 1e300}, "f must be in (0.001, 10], got 1e+300"),
    ({"p": 1e300}, "p must be at most 83333.33333333333, got 1e+300"),
    ({"rows": 2_000_000}, "rows must be at most 1e+06, got 2000000"),
]


@pytest.mark.parametrize(("change", "start"), BAD_PAPER, ids=[str(c) for c, _ in BAD_PAPER])
@pytest.mark.parametrize("api", [WallSpec.from_paper, macro.sweep], ids=["from_paper", "sweep"])
def test_the_paper_parameters_are_bounded(api: Any, change: dict[str, Any], start: str) -> None:
    assert _message(lambda: api(**(PAPER | change))).startswith(start)


def test_an_array_names_the_entry() -> None:
    message = _message(lambda: macro.sweep(t=[1.0, 50.0], m=1 / 3, rows=12, f=0.6))
    assert message.startswith("t must be in [1.2e-05, 4], got 50.0") and message.endswith("(entry 1)")


def test_the_memory_of_the_macro_search_is_estimated_first() -> None:
    n = 100_000  # 2 TB estimated: refused before anything is allocated
    wall = macro.MacroWall(**(DIMENSIONAL | {"rows": (1,) * n, "thickness": (1.0,) * n, "overload": (0.0,) * n}))
    with pytest.raises(checks.TooLarge, match=f"storeys: the search over {n} storeys needs an estimated"):
        macro.solve(wall)
    with pytest.raises(checks.TooLarge, match="storeys: a batch of 4096 walls of 200000 storeys"):
        macro.sweep([1.0] * 5000, 1 / 3, 200_000, 0.6, storeys=200_000)
    with pytest.raises(checks.TooLarge, match="storeys"):
        checks.fits_in_memory("storeys", "a test", need=2 << 30, budget=1 << 30)
