"""Failure-mode extraction: the micro mechanism read in the macro model's terms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from comparison.domain.failure import FailureMode, failure_mode
from comparison.domain.wall import WallSpec


def _rotating_region(wall, slope: float, offset: float, mirror: bool) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Velocities of the blocks left of x = offset + slope*y rotating about the base corner."""
    xc, yc = 0.5 * (wall.x0 + wall.x1), 0.5 * (wall.y0 + wall.y1)
    x = wall.length - xc if mirror else xc
    moving = x < offset + slope * yc
    omega = 0.01
    vel = np.zeros((xc.size, 3))
    # rotation about the hinge corner, in scaled units (block height 1 here)
    vel[:, 0] = np.where(moving, -omega * yc, 0.0) * (-1 if mirror else 1)
    vel[:, 1] = np.where(moving, omega * x, 0.0)
    vel[:, 2] = np.where(moving, omega, 0.0) * (-1 if mirror else 1)
    return vel


@pytest.mark.parametrize("mirror", [False, True])
def test_failure_mode_recovers_a_known_crack(mirror: bool) -> None:
    wall = WallSpec.from_paper(t=0.5, m=1 / 3, rows=24, f=0.75).to_micro()
    vel = _rotating_region(wall, slope=1.0, offset=1.5, mirror=mirror)
    fm = failure_mode(wall, vel, "+x" if mirror else "-x")
    assert fm.hinge_storey == 1
    assert fm.crack_slope == pytest.approx(1.0, abs=0.1)
    assert fm.crack_angle_deg == pytest.approx(45.0, abs=3.0)
    assert fm.whole_length_courses == 0
    assert 0.0 < fm.moving_fraction < 1.0


def test_failure_mode_rejects_bad_input() -> None:
    wall = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75).to_micro()
    with pytest.raises(ValueError, match="no block moves"):
        failure_mode(wall, np.zeros((wall.n_blocks, 3)), "+x")
    with pytest.raises(ValueError, match="direction"):
        failure_mode(wall, np.ones((wall.n_blocks, 3)), "up")
    with pytest.raises(ValueError, match="shape"):
        failure_mode(wall, np.ones((3, 3)), "+x")


def test_failure_mode_round_trips_through_json_ready_dict() -> None:
    fm = FailureMode(10, 0.5, 1, 0, math.nan, math.nan, 42.0, 2, math.inf, "+x")
    d = fm.to_dict()
    assert d["crack_slope"] is None and d["rotation"] is None
    back = FailureMode.from_dict(d)
    assert back.moving_blocks == 10 and back.direction == "+x" and math.isnan(back.crack_slope)
