"""Property tests on random small walls (hypothesis)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import micro


@settings(max_examples=int(__import__("os").environ.get("MICRO_EXAMPLES", "15")), deadline=None)
@given(
    n_half=st.integers(2, 14),
    rows=st.lists(st.integers(1, 4), min_size=1, max_size=3),
    friction=st.floats(0.3, 1.0),
    overload=st.floats(0.0, 3.0),
    first=st.sampled_from(["full", "half"]),
    heads=st.sampled_from(["frictional", "frictionless"]),
)
def test_random_walls(n_half: int, rows: list[int], friction: float, overload: float, first: str, heads: str) -> None:
    k = len(rows)
    wall = micro.build_wall(
        length=0.75 * n_half, block_length=1.5, block_height=0.5, rows=tuple(rows), thickness=(0.5,) * k,
        overload=(overload,) * k, unit_weight=1.0, friction=friction, first_course=first,  # type: ignore[arg-type]
        head_joints=heads,  # type: ignore[arg-type]
    )
    a = micro.solve_associative(wall, solver="highs-ipm", directions="both")
    b = micro.solve_associative(wall, solver="clarabel", directions="both")
    c = micro.solve_associative(wall, solver="normal-ipm", directions="both")
    assert a.ok and b.ok and c.ok, (a.message, b.message, c.message)
    # the base cannot carry more than mu times the total vertical load
    assert a.load_factor <= friction * (1 + 1e-7)
    for d in ("+x", "-x"):
        ra, rb, rc = a.by_direction(d), b.by_direction(d), c.by_direction(d)
        assert ra.load_factor == pytest.approx(rb.load_factor, rel=1e-6, abs=1e-9)
        assert rc.load_factor == pytest.approx(rb.load_factor, rel=1e-6, abs=1e-9)
        assert abs(ra.mechanism.virtual_work_residual(ra.load_factor)) < 1e-6  # type: ignore[union-attr]
    if wall.mirror_symmetric:
        assert a.by_direction("+x").load_factor == pytest.approx(a.by_direction("-x").load_factor, rel=1e-6)
