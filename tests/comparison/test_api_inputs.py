"""One rule for input at every public entry point of the Python API.

A bad value of any kind (type, NaN, inf, huge, wrong container) raises ``ValueError`` or ``TypeError``
naming the parameter, before any work; none reaches the models to fail deep inside
(``AttributeError``, ``OverflowError``) or to start minutes of work (``global_=1``).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import macro
import micro
from comparison.domain.wall import StoreySpec, WallSpec
from macro.checks import TooLarge
from micro.nonassociative import NonAssociativeOptions, Tuning

SPEC = WallSpec.from_paper(t=1, m=1 / 3, rows=4, f=0.6)
MACRO_WALL = SPEC.to_macro()
BLOCK_WALL = SPEC.to_micro()
HUGE = 10**400  # an int beyond the doubles: float() raises OverflowError

CASES: dict[str, tuple[Callable[[], Any], type[Exception], str]] = {
    # macro.solve
    "solve(None)": (lambda: macro.solve(None), TypeError, r"^wall must be a macro.MacroWall, got NoneType$"),  # type: ignore[arg-type]
    "solve(WallSpec)": (lambda: macro.solve(SPEC), TypeError,  # type: ignore[arg-type]
                        r"^wall must be a macro.MacroWall; WallSpec.to_macro\(\) gives one, got WallSpec$"),
    "solve(BlockWall)": (lambda: macro.solve(BLOCK_WALL), TypeError, r"^wall must be a macro.MacroWall"),  # type: ignore[arg-type]
    "solve(settings='fast')": (lambda: macro.solve(MACRO_WALL, "fast"), TypeError,  # type: ignore[arg-type]
                               r"^settings must be a macro.SearchSettings, got 'fast' \(str\)$"),
    # macro.sweep
    "sweep(chunk=0)": (lambda: macro.sweep(1, 1 / 3, 4, 0.6, chunk=0), ValueError,
                       r"^chunk must be a positive integer, got 0$"),
    "sweep(chunk=-1)": (lambda: macro.sweep(1, 1 / 3, 4, 0.6, chunk=-1), ValueError, r"^chunk must be a positive"),
    "sweep(chunk=1.5)": (lambda: macro.sweep(1, 1 / 3, 4, 0.6, chunk=1.5), ValueError, r"^chunk must be a positive"),  # type: ignore[arg-type]
    "sweep(settings='fast')": (lambda: macro.sweep(1, 1 / 3, 4, 0.6, settings="fast"), TypeError,  # type: ignore[arg-type]
                               r"^settings must be a macro.SearchSettings"),
    "sweep(storeys=None)": (lambda: macro.sweep(1, 1 / 3, 4, 0.6, storeys=None), ValueError,  # type: ignore[arg-type]
                            r"^storeys must be a positive integer, got None$"),
    "sweep(mismatched)": (lambda: macro.sweep(np.ones(3), np.full(2, 1 / 3), 4, 0.6), ValueError,
                          r"^t, m, rows, f, p must broadcast to one shape, got the shapes t \(3,\), m \(2,\)$"),
    "sweep(ragged)": (lambda: macro.sweep([[1.0], [1.0, 2.0]], 1 / 3, 4, 0.6), ValueError,
                      r"^t must be a number or an array of numbers, got \[\[1.0\], \[1.0, 2.0\]\]$"),
    "SearchSettings(cells=10**9)": (lambda: macro.SearchSettings(cells=10**9), ValueError,
                                    r"^cells must be an integer in 1..10,000"),
    # WallSpec
    "from_paper(t=array)": (lambda: WallSpec.from_paper(t=np.array([1.0, 2.0]), m=1 / 3, rows=4, f=0.6), ValueError,
                            r"^t must be one number \(a WallSpec is one wall; macro.sweep takes arrays\), got "),
    "from_paper(rows=[4])": (lambda: WallSpec.from_paper(t=1, m=1 / 3, rows=[4], f=0.6), ValueError,  # type: ignore[arg-type]
                             r"^rows must be one number"),
    "from_paper(storeys=None)": (lambda: WallSpec.from_paper(t=1, m=1 / 3, rows=4, f=0.6, storeys=None), ValueError,  # type: ignore[arg-type]
                                 r"^storeys must be a positive integer, got None$"),
    "from_paper(name=5)": (lambda: WallSpec.from_paper(t=1, m=1 / 3, rows=4, f=0.6, name=5), ValueError,  # type: ignore[arg-type]
                           r"^name must be a string, got 5$"),
    "WallSpec(storeys=None)": (lambda: WallSpec(length=12, block_length=3, block_height=1, storeys=None), ValueError,  # type: ignore[arg-type]
                               r"^storeys must be a tuple of StoreySpec"),
    "StoreySpec(rows=10**400)": (lambda: StoreySpec(rows=HUGE, thickness=1), ValueError, r"^rows must be a positive"),
    # micro.build_wall
    "build_wall(length=10**400)": (lambda: micro.build_wall(**{**_wall(), "length": HUGE}), ValueError,
                                   r"^length must be a positive number, got 1000"),
    "build_wall(rows=(10**400,))": (lambda: micro.build_wall(**{**_wall(), "rows": (HUGE,)}), ValueError,
                                    r"^rows\[0\] must be a positive integer, got 1000"),
    "build_wall(max_bytes='x')": (lambda: micro.build_wall(**{**_wall(), "max_bytes": "x"}), ValueError,
                                  r"^max_bytes must be a positive integer \(bytes\) or None, got 'x'$"),
    # micro.solve_associative
    "solve_associative(None)": (lambda: micro.solve_associative(None), TypeError,  # type: ignore[arg-type]
                                r"^wall must be a micro.BlockWall \(micro.build_wall\(...\) or WallSpec.to_micro\(\) "
                                r"gives one\), got NoneType$"),
    "solve_associative(WallSpec)": (lambda: micro.solve_associative(SPEC), TypeError, r"got WallSpec$"),  # type: ignore[arg-type]
    "solve_associative(MacroWall)": (lambda: micro.solve_associative(MACRO_WALL), TypeError, r"got MacroWall$"),  # type: ignore[arg-type]
    "solve_associative(time_limit=10**400)": (lambda: micro.solve_associative(BLOCK_WALL, time_limit=HUGE), ValueError,
                                              r"^time_limit must be a positive number of seconds, got 1000"),
    # micro.solve_nonassociative
    "solve_nonassociative(None)": (lambda: micro.solve_nonassociative(None), TypeError,  # type: ignore[arg-type]
                                   r"^wall must be a micro.BlockWall"),
    "solve_nonassociative(WallSpec)": (lambda: micro.solve_nonassociative(SPEC), TypeError, r"got WallSpec$"),  # type: ignore[arg-type]
    "tuning='b'": (lambda: micro.solve_nonassociative(BLOCK_WALL, tuning="b"), TypeError,  # type: ignore[arg-type]
                   r"^tuning must be a micro.Tuning or None, got 'b' \(str\)$"),
    "options='fast'": (lambda: micro.solve_nonassociative(BLOCK_WALL, options="fast"), TypeError,  # type: ignore[arg-type]
                       r"^options must be a micro.NonAssociativeOptions or None, got 'fast' \(str\)$"),
    "options={}": (lambda: micro.solve_nonassociative(BLOCK_WALL, options={}), TypeError,  # type: ignore[arg-type]
                   r"^options must be a micro.NonAssociativeOptions or None, got \{\} \(dict\)$"),
    "progress='print'": (lambda: micro.solve_nonassociative(BLOCK_WALL, progress="print"), TypeError,  # type: ignore[arg-type]
                         r"^progress must be a function of one LPProgress or None, got 'print'$"),
    "time_limit=10**400": (lambda: micro.solve_nonassociative(BLOCK_WALL, time_limit=HUGE), ValueError,
                           r"^time_limit must be a positive number of seconds, got 1000"),
    "max_seconds=10**400": (lambda: NonAssociativeOptions(max_seconds=HUGE), ValueError,
                            r"^max_seconds must be a positive number of seconds"),
    "GlobalOptions(direction_time_limit=10**400)": (lambda: micro.GlobalOptions(direction_time_limit=HUGE),
                                                    ValueError, r"^direction_time_limit must be a positive number"),
    "lowest_budget=10**400": (lambda: NonAssociativeOptions(lowest_budget=HUGE), ValueError,
                              r"^lowest_budget must be an integer in 0\.\."),
    "max_iterations=10**400": (lambda: NonAssociativeOptions(max_iterations=HUGE), ValueError,
                               r"^max_iterations must be an integer in 2..2,147,483,647, got 1000"),
    "GlobalOptions(node_limit=10**400)": (lambda: micro.GlobalOptions(node_limit=HUGE), ValueError,
                                          r"^node_limit must be an integer in 1..2,147,483,647"),
    "solve_global(options=1)": (lambda: micro.solve_global(BLOCK_WALL, options=1), ValueError,  # type: ignore[arg-type]
                                r"^options must be a GlobalOptions, got int$"),
    "Tuning(certify='no')": (lambda: Tuning(certify="no"), ValueError,  # type: ignore[arg-type]
                             r"^certify must be True or False, got 'no'$"),
    "Tuning(fuse=1)": (lambda: Tuning(fuse=1), ValueError,  # type: ignore[arg-type]
                       r"^fuse must be True or False or None \(by the wall's size\), got 1$"),
    "Tuning(relaxation=10**400)": (lambda: Tuning(relaxation=HUGE), ValueError, r"^relaxation must be a number in"),
    "Tuning(retry_iterations=10**400)": (lambda: Tuning(retry_iterations=HUGE), ValueError,
                                         r"^retry_iterations must be an integer in 2..2,147"),
}


def _wall() -> dict[str, Any]:
    return dict(length=12, block_length=3, block_height=1, rows=(4,), thickness=(1,), overload=(0,), unit_weight=1,
                friction=0.6)


@pytest.mark.parametrize("name", list(CASES))
def test_a_bad_value_is_refused_at_the_entry_point_naming_it(name: str) -> None:
    """A bad value is refused at the entry point, naming the parameter: never an error from deep inside (an
    ``AttributeError``, an ``OverflowError``, numpy's shape mismatch), a value dropped, or a string read as
    True."""
    call, error, match = CASES[name]
    with pytest.raises(error) as info:
        call()
    assert type(info.value) in (error, TooLarge) and re.search(match, str(info.value)), str(info.value)
    assert "\n" not in str(info.value)


def test_a_sweep_too_large_for_the_memory_is_refused_before_any_array_is_built() -> None:
    """``macro.sweep`` of more walls than the memory holds is refused at the API before any array is built:
    10^10 walls broadcast from one number take no memory as input; the estimate (about 300 bytes a wall)
    refuses them at once."""
    t = np.broadcast_to(1.0, (10**10,))
    with pytest.raises(TooLarge, match=r"^t, m, rows, f, p: a sweep of 10,000,000,000 walls of 1 storey needs an "
                                       r"estimated [\d.e+]+ GB of memory, but only"):
        macro.sweep(t=t, m=1 / 3, rows=12, f=0.6)
    s = macro.sweep(t=np.broadcast_to(1.0, (3,)), m=1 / 3, rows=12, f=0.6)  # a small broadcast one still runs
    assert s.load_factor.shape == (3,) and np.all(s.load_factor > 0)


def test_the_sweep_estimate_is_above_the_measured_peak() -> None:
    """The estimate keeps a margin above the peaks measured (258, 611 and 2,094 bytes per wall for 1, 5 and
    20 storeys)."""
    from macro.sweep import sweep_bytes

    for storeys, measured in ((1, 258), (5, 611), (20, 2094)):
        assert sweep_bytes(1, storeys) > 1.1 * measured


def test_good_values_of_every_kind_still_pass() -> None:
    assert macro.solve(MACRO_WALL, macro.SearchSettings()).status == "optimal"
    assert macro.sweep(np.array([1.0, 2.0]), 1 / 3, 12, 0.6, chunk=np.int64(1)).load_factor.shape == (2,)
    assert WallSpec.from_paper(t=np.float64(1.0), m=np.array(1 / 3), rows=np.int64(4), f=0.6).rows == 4
    assert NonAssociativeOptions(lowest=np.bool_(False), max_iterations=np.int64(10)).lowest is False
    assert Tuning(certify=np.bool_(True), fuse=None).certify is True
    r = micro.solve_associative(BLOCK_WALL, time_limit=10**6)
    assert r.ok
