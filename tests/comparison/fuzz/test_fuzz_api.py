"""Fuzzing the Python API: ``WallSpec.from_paper`` + ``macro.solve``, ``macro.sweep``, ``MacroWall``, and the micro LP.

Any draw either raises ``ValueError`` (a parameter named) or gives a result
whose success status comes with a finite positive load factor, no larger than
the rigid bounds (sliding ``f``, overturning). Draws with ``m`` below 1e-16
are the ones to watch: they must not come out NaN, negative or 0 with status
optimal.
"""

from __future__ import annotations

import math

import numpy as np
from fuzz_strategies import EDGES, FUZZ, finite_success, mark, mostly, numbers
from hypothesis import event, given
from hypothesis import strategies as st

import macro
import micro
from comparison.domain.wall import WallSpec
from macro.checks import TooLarge

pytestmark = mark


@st.composite
def paper(draw: st.DrawFn) -> dict[str, object]:
    """The paper's parameters: a plausible wall, with any of them now and then extreme or malformed."""
    # 300 storeys, not more: the macro search grows like N^2.6 in the storeys (0.03 s at 200, 0.2 s at 400 on
    # one core); 3,000 storeys of 15,000 rows took about a minute a wall, and hypothesis' mutations of such a
    # draw held a CI run in test_fuzz_sweep for over 15 minutes (py-spy: inside the search of 5 such walls)
    storeys = draw(mostly(st.integers(1, 4), st.sampled_from([0, -1, 2.5, 300, True])))
    per = draw(st.integers(1, 20))
    rows_ok = per * storeys if isinstance(storeys, int) and not isinstance(storeys, bool) and storeys > 0 else 12
    m = draw(mostly(st.sampled_from([1 / 4, 1 / 3, 0.5, 1.0]), st.one_of(numbers, st.floats(1e-20, 1.0))))
    m_ok = m if isinstance(m, float) and 0 < m <= 1 else 1 / 3
    return {
        "t": draw(mostly(st.floats(0.3, 1.0).map(lambda x: x * rows_ok * m_ok))),  # at most o m: one block long
        "m": m,
        "rows": draw(mostly(st.just(rows_ok), st.one_of(st.integers(-2, 10**7), st.sampled_from([12.5, math.nan])))),
        "f": draw(mostly(st.floats(0.2, 1.2))),
        "p": draw(mostly(st.floats(0.0, 8.0))),
        "storeys": storeys,
    }


def _valid_macro(r: macro.MacroResult) -> None:
    assert r.status == "optimal", r.status
    assert math.isfinite(r.load_factor) and r.load_factor > 0, r.load_factor
    assert r.load_factor <= min(r.rocking_load_factor, r.wall.friction, r.overturning_load_factor)


@FUZZ
@given(kw=paper())
def test_fuzz_from_paper_and_solve(kw: dict[str, object]) -> None:
    try:
        spec = WallSpec.from_paper(**kw)  # type: ignore[arg-type]
    except ValueError:
        event("refused")
        return
    try:
        _valid_macro(macro.solve(spec.to_macro()))
    except TooLarge:
        event("too large")
        return
    event("solved")


@FUZZ
@given(kw=paper(), n=st.integers(1, 5))
def test_fuzz_sweep(kw: dict[str, object], n: int) -> None:
    args = {k: np.full(n, v) if k in ("t", "m", "f") and not isinstance(v, bool) else v for k, v in kw.items()}
    try:
        s = macro.sweep(**args)  # type: ignore[arg-type]
    except ValueError:
        event("refused")
        return
    assert np.all(np.isfinite(s.load_factor) & (s.load_factor > 0))
    assert np.all(s.load_factor <= np.minimum(s.rocking_load_factor, s.overturning_load_factor) * (1 + 1e-12))
    event("solved")


@st.composite
def macro_walls(draw: st.DrawFn) -> dict[str, object]:
    """A dimensional wall of 1-3 storeys, each number now and then extreme (a count now and then wrong)."""
    n = draw(st.integers(1, 3))
    size = draw(mostly(st.just(n), st.integers(0, 4)))
    return {
        "length": draw(mostly(st.floats(6.0, 30.0))),
        "block_length": draw(mostly(st.floats(0.5, 6.0))),
        "block_height": draw(mostly(st.floats(0.5, 2.0))),
        "unit_weight": draw(mostly(st.floats(0.1, 30.0))),
        "friction": draw(mostly(st.floats(0.2, 1.0))),
        "rows": tuple(draw(st.lists(mostly(st.integers(1, 8), st.integers(-2, 0)), min_size=n, max_size=n))),
        "thickness": tuple(draw(st.lists(mostly(st.floats(0.5, 2.0)), min_size=size, max_size=size))),
        "overload": tuple(draw(st.lists(mostly(st.floats(0.0, 5.0)), min_size=n, max_size=n))),
    }


@FUZZ
@given(kw=macro_walls())
def test_fuzz_macro_wall(kw: dict[str, object]) -> None:
    try:
        wall = macro.MacroWall(**kw)  # type: ignore[arg-type]
    except ValueError:
        event("refused")
        return
    _valid_macro(macro.solve(wall))
    event("solved")


@FUZZ
@given(
    blocks=st.integers(1, 4),  # L/l, kept small: the LP stays tiny
    block_length=mostly(st.floats(0.2, 3.0), st.sampled_from(EDGES)),
    block_height=mostly(st.floats(0.2, 3.0), st.sampled_from(EDGES)),
    unit_weight=mostly(st.floats(0.1, 30.0), st.sampled_from(EDGES)),
    friction=mostly(st.floats(0.2, 1.0), st.sampled_from(EDGES)),
    rows=st.lists(st.integers(1, 4), min_size=1, max_size=3),
    overload=mostly(st.floats(0.0, 10.0), st.sampled_from(EDGES)),
    solver=st.sampled_from(["highs-ipm", "clarabel", "highs-simplex"]),
)
def test_fuzz_micro_wall_and_lp(
    blocks: int, block_length: float, block_height: float, unit_weight: float, friction: float, rows: list[int],
    overload: float, solver: str,
) -> None:  # fmt: skip
    n = len(rows)
    length = blocks * block_length if math.isfinite(block_length) else block_length
    try:
        wall = micro.build_wall(
            length=length, block_length=block_length, block_height=block_height, rows=tuple(rows),
            thickness=(block_height,) * n, overload=(overload,) * n, unit_weight=unit_weight, friction=friction,
        )  # fmt: skip
    except ValueError:
        event("refused")
        return
    r = micro.solve_associative(wall, solver=solver)
    assert finite_success(r.status, r.load_factor), (r.status, r.load_factor)
    assert r.ok or math.isnan(r.load_factor)
    event("solved" if r.ok else f"failed: {r.status}")


#: Anything a caller might pass by mistake (``None``, a ``WallSpec`` where a wall is expected,
#: ``tuning='b'``, ``options='fast'``, ``progress='print'``, ``time_limit=10**400``, ``chunk=0``, arrays).
ODD = st.one_of(
    st.none(), st.sampled_from([0, -1, 10**400, -(10**400), 2.5, "b", "fast", "print", "", [], {}, [1.0, 2.0],
                                np.array([1.0, 2.0]), np.ones((2, 2)), math.nan, math.inf, 5e-324, 1e300]),
    numbers, st.text(max_size=4),
)  # fmt: skip
_SPEC = WallSpec.from_paper(t=1, m=1 / 3, rows=4, f=0.6)
#: Each entry point with valid arguments; the fuzz replaces one of them.
ENTRY_POINTS: dict[str, tuple[object, dict[str, object]]] = {
    "macro.solve": (macro.solve, {"wall": _SPEC.to_macro(), "settings": macro.SearchSettings()}),
    "macro.sweep": (macro.sweep, {"t": np.array([1.0, 2.0]), "m": 1 / 3, "rows": 12, "f": 0.6, "p": 0.0,
                                  "storeys": 1, "p_height": "wall", "chunk": 4096}),
    "WallSpec.from_paper": (WallSpec.from_paper, {"t": 1.0, "m": 1 / 3, "rows": 4, "f": 0.6, "p": 0.0, "storeys": 1,
                                                  "p_height": "wall", "name": "w"}),
    "micro.solve_associative": (micro.solve_associative, {"wall": _SPEC.to_micro(), "solver": "normal-ipm",
                                                          "directions": "auto", "time_limit": 60}),
    "micro.solve_nonassociative": (micro.solve_nonassociative, {
        "wall": _SPEC.to_micro(), "options": None, "tuning": None, "progress": None, "time_limit": 60,
        "max_iterations": 20, "max_seconds": 60, "lowest": False, "lowest_budget": 500.0, "directions": "auto"}),
}


@FUZZ
@given(entry=st.sampled_from(list(ENTRY_POINTS)), data=st.data())
def test_fuzz_entry_points_refuse_a_bad_value_of_any_kind(entry: str, data: st.DataObject) -> None:
    """One parameter replaced by an odd value: a result, or ``ValueError``/``TypeError`` naming a parameter;
    never ``AttributeError`` or ``OverflowError`` from deep inside, nor numpy's "truth value of an array is
    ambiguous" (``directions=array``) or "unhashable type" (``solver=[]``), which the fuzz found."""
    function, kwargs = ENTRY_POINTS[entry]
    name = data.draw(st.sampled_from(list(kwargs)))
    value = data.draw(ODD)
    try:
        function(**{**kwargs, name: value})  # type: ignore[operator]
    except (ValueError, TypeError) as exc:
        assert any(k in str(exc) for k in kwargs), (name, str(exc))  # a parameter named (t when rows moved it)
        event("refused")
        return
    event("accepted")
