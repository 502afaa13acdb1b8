"""One wall vocabulary: every validator of a wall parameter words a bad value alike.

The same bad parameters go through ``WallSpec.from_paper``, ``WallSpec(...)``,
``StoreySpec(...)``, ``macro.MacroWall(...)``, ``macro.sweep(...)`` and
``micro.build_wall(...)``; each must raise ``ValueError`` with the shared
template of :mod:`macro.checks`, naming the parameter as the API spells it.
``micro`` spells the templates out itself (it may not import ``macro``), so
this test is what keeps the two wordings alike.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest

import macro
import micro
from comparison.domain.wall import StoreySpec, WallSpec
from macro import checks

PAPER = {"t": 1.0, "m": 1 / 3, "rows": 12, "f": 0.6, "p": 0.0, "storeys": 1}
DIMENSIONAL = {"length": 12.0, "block_length": 3.0, "block_height": 1.0, "unit_weight": 1.0, "friction": 0.6}
STOREYS = {"rows": (6, 6), "thickness": (1.0, 1.0), "overload": (0.0, 0.0)}

NOT_NUMBERS: tuple[Any, ...] = ("x", None, True)
BAD_POSITIVE: tuple[Any, ...] = (*NOT_NUMBERS, math.nan, math.inf, -math.inf, -1.0, 0.0, 0)
BAD_NON_NEGATIVE: tuple[Any, ...] = (*NOT_NUMBERS, math.nan, math.inf, -1.0, -1e-9)
BAD_INT: tuple[Any, ...] = (*NOT_NUMBERS, math.nan, 12.5, 0, -3, 0.0)


def _message(template: str, name: str, value: Any) -> str:
    return template.format(name=name, value=value, lo=checks.exact(0.0), hi=checks.exact(1.0))


def _expect(call: Callable[[], object], message: str) -> None:
    with pytest.raises(ValueError) as exc:
        call()
    assert str(exc.value) == message


def _paper_cases() -> list[Any]:
    cases = []
    for name, template, bad in (
        ("t", checks.POSITIVE, BAD_POSITIVE),
        ("f", checks.POSITIVE, BAD_POSITIVE),
        ("p", checks.NON_NEGATIVE, BAD_NON_NEGATIVE),
        ("rows", checks.POSITIVE_INT, BAD_INT),
        ("storeys", checks.POSITIVE_INT, BAD_INT),
        ("m", checks.POSITIVE, BAD_POSITIVE),
        ("m", checks.IN_RANGE, (1.5, 2)),
    ):
        cases += [pytest.param({name: v}, _message(template, name, v), id=f"{name}={v!r}") for v in bad]
    cases.append(
        pytest.param(
            {"rows": 13, "storeys": 2}, "rows: 13 rows cannot be split equally over 2 storeys", id="rows=13/storeys=2"
        )
    )
    return cases


@pytest.mark.parametrize(("bad", "message"), _paper_cases())
@pytest.mark.parametrize("api", [WallSpec.from_paper, macro.sweep], ids=["from_paper", "sweep"])
def test_paper_parameters(api: Callable[..., object], bad: dict[str, Any], message: str) -> None:
    _expect(lambda: api(**(PAPER | bad)), message)


def test_sweep_names_the_entry_of_an_array() -> None:
    _expect(
        lambda: macro.sweep(t=[1.0, -2.0], m=1 / 3, rows=12, f=0.6), "t must be a positive number, got -2.0 (entry 1)"
    )
    _expect(
        lambda: macro.sweep(t=1.0, m=[True, True], rows=12, f=0.6), "m must be a positive number, got True (entry 0)"
    )


def _dimensional_cases() -> list[Any]:
    cases = []
    for name in DIMENSIONAL:
        cases += [pytest.param(name, v, _message(checks.POSITIVE, name, v), id=f"{name}={v!r}") for v in BAD_POSITIVE]
    return cases


@pytest.mark.parametrize(("name", "value", "message"), _dimensional_cases())
@pytest.mark.parametrize("api", ["WallSpec", "MacroWall", "build_wall"])
def test_dimensional_parameters(api: str, name: str, value: Any, message: str) -> None:
    if api == "WallSpec":
        storeys = tuple(StoreySpec(r, t, q) for r, t, q in zip(*STOREYS.values(), strict=True))
        _expect(lambda: WallSpec(storeys=storeys, **(DIMENSIONAL | {name: value})), message)
    elif api == "MacroWall":
        _expect(lambda: macro.MacroWall(**(DIMENSIONAL | STOREYS | {name: value})), message)
    else:
        _expect(lambda: micro.build_wall(**(DIMENSIONAL | STOREYS | {name: value})), message)


def _storey_cases() -> list[Any]:
    cases = []
    for name, template, bad in (
        ("rows", checks.POSITIVE_INT, BAD_INT),
        ("thickness", checks.POSITIVE, BAD_POSITIVE),
        ("overload", checks.NON_NEGATIVE, BAD_NON_NEGATIVE),
    ):
        cases += [pytest.param(name, v, template, id=f"{name}[1]={v!r}") for v in bad]
    return cases


@pytest.mark.parametrize(("name", "value", "template"), _storey_cases())
@pytest.mark.parametrize("api", ["StoreySpec", "MacroWall", "build_wall"])
def test_per_storey_parameters(api: str, name: str, value: Any, template: str) -> None:
    if api == "StoreySpec":
        good = {"rows": 6, "thickness": 1.0, "overload": 0.0}
        _expect(lambda: StoreySpec(**(good | {name: value})), _message(template, name, value))
        return
    entries = STOREYS[name][:1] + (value,)
    build = macro.MacroWall if api == "MacroWall" else micro.build_wall
    _expect(lambda: build(**(DIMENSIONAL | STOREYS | {name: entries})), _message(template, f"{name}[1]", value))


@pytest.mark.parametrize("api", ["MacroWall", "build_wall"])
@pytest.mark.parametrize("name", ["thickness", "overload"])
def test_per_storey_counts(api: str, name: str) -> None:
    build = macro.MacroWall if api == "MacroWall" else micro.build_wall
    message = checks.PER_STOREY.format(name=name, count=1, storeys=2)
    _expect(lambda: build(**(DIMENSIONAL | STOREYS | {name: (1.0,)})), message)


@pytest.mark.parametrize("api", ["MacroWall", "build_wall"])
def test_no_storey(api: str) -> None:
    build = macro.MacroWall if api == "MacroWall" else micro.build_wall
    _expect(
        lambda: build(**(DIMENSIONAL | {"rows": (), "thickness": (), "overload": ()})),
        checks.NO_STOREY.format(name="rows"),
    )
