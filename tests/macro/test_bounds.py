"""The rigid-body bounds of the macro load factor (``macro.bounds``) and the success invariant.

A wall one block long (t = o m) came out of Eq. (10) above the load factor at
which it overturns as one rigid body (0.0501 against L/H = 0.05 for 60 rows):
the paper's mechanism assumes a crack inside the wall. The result now reports
the least of Eq. (10), sliding (f) and overturning, with the mechanism.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import macro
from comparison.domain.wall import WallSpec
from comparison.runner.macro_record import macro_record
from macro.bounds import overturning_load_factor


def test_a_wall_one_block_long_overturns_as_one_body() -> None:
    spec = WallSpec.from_paper(t=20, m=1 / 3, rows=60, f=0.6)  # L = l = 3, H = 60
    r = macro.solve(spec.to_macro())
    assert r.rocking_load_factor > 0.05  # Eq. (10), kept as the paper's number
    assert r.load_factor == pytest.approx(0.05, rel=1e-12) and r.mechanism == "overturning"
    assert r.overturning_load_factor == pytest.approx(spec.length / spec.height, rel=1e-12)
    s = macro.sweep(t=20, m=1 / 3, rows=60, f=0.6)
    assert float(s.load_factor) == pytest.approx(r.load_factor, rel=1e-12)
    assert macro.MECHANISMS[int(s.mechanism)] == "overturning"


def test_overturning_bound_in_closed_form() -> None:
    # one storey: (W + Q) L/2 over W H/2 + Q H
    L, H, q = 6.0, 12.0, 5.0
    lam = overturning_load_factor([L], [1.0], [1.0], [[12]], [[1.0]], [[q]])[0]
    W, Q = L * H, q * L
    assert lam == pytest.approx((W + Q) * L / 2 / (W * H / 2 + Q * H), rel=1e-14)
    # the least over the hinge storeys: over a very thick ground storey the two upper storeys overturn first
    lam3 = overturning_load_factor([L], [1.0], [1.0], [[4, 4, 4]], [[1.0, 1.0, 100.0]], [[0.0] * 3])[0]
    assert lam3 == pytest.approx(L / 8, rel=1e-14)


walls = st.builds(
    lambda blocks, m, per, n, f, p: WallSpec.from_paper(
        t=per * n * m / blocks, m=m, rows=per * n, f=f, p=p, storeys=n
    ).to_macro(),
    blocks=st.floats(1.0, 6.0),  # L/l: slender walls
    m=st.sampled_from([0.25, 1 / 3, 0.5, 1.0]),
    per=st.integers(1, 30),
    n=st.integers(1, 3),
    f=st.floats(0.2, 1.2),
    p=st.floats(0.0, 4.0),
)


@settings(max_examples=60, deadline=None)
@given(w=walls)
def test_the_load_factor_never_exceeds_the_rigid_bounds(w: macro.MacroWall) -> None:
    r = macro.solve(w)
    assert r.status == "optimal" and math.isfinite(r.load_factor) and r.load_factor > 0
    assert r.load_factor <= min(r.rocking_load_factor, w.friction, r.overturning_load_factor)
    no_floor = all(q == 0 for q in w.overload)
    if no_floor:
        assert r.overturning_load_factor == pytest.approx(w.length / (sum(w.rows) * w.block_height), rel=1e-12)


def test_an_optimal_result_needs_a_finite_positive_load_factor() -> None:
    r = macro.solve(WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.6).to_macro())
    for bad in (math.nan, math.inf, -0.1, 0.0):
        with pytest.raises(ValueError, match="finite positive load factor"):
            dataclasses.replace(r, load_factor=bad)
        with pytest.raises(ValueError, match="finite positive load factor"):
            dataclasses.replace(macro_record(r), load_factor=bad)
    assert dataclasses.replace(r, load_factor=math.nan, status="numerical_error").status == "numerical_error"


def test_sweep_and_solve_agree_on_slender_walls() -> None:
    t = np.array([20.0, 16.0, 13.0, 10.0])  # L/l from 1 to 2 with 60 rows, m = 1/3
    s = macro.sweep(t, 1 / 3, 60, 0.6)
    for i, ti in enumerate(t):
        r = macro.solve(WallSpec.from_paper(t=float(ti), m=1 / 3, rows=60, f=0.6).to_macro())
        assert s.load_factor[i] == pytest.approx(r.load_factor, rel=1e-8)
        assert macro.MECHANISMS[s.mechanism[i]] == r.mechanism
