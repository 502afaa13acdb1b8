"""Failure-mode extraction and the caching runner."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from comparison.failure import failure_mode
from comparison.runner import MACRO, MICRO_ASSOC, Runner, code_version
from comparison.spec import WallSpec


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


def test_runner_caches_and_recomputes_only_what_changed(tmp_path: Path) -> None:
    spec = WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75, name="Set 12")
    lines: list[str] = []
    r1 = Runner(tmp_path, lines.append)
    a = r1.run(spec, MICRO_ASSOC)
    m = r1.run(spec, MACRO)
    assert (r1.computed, r1.hits) == (2, 0) and len(lines) == 2
    assert a.load_factor == pytest.approx(0.712047, abs=1e-5) and not a.cached
    r2 = Runner(tmp_path)
    b = r2.run(spec, MICRO_ASSOC)
    assert (r2.computed, r2.hits) == (0, 1) and b.cached
    assert b.load_factor == a.load_factor and b.values["blocks"] == 54
    assert r2.run(spec, MACRO).load_factor == m.load_factor
    # another friction is another wall: computed anew
    r2.run(WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.6), MICRO_ASSOC)
    assert r2.computed == 1
    mech = r2.mechanism(spec, MICRO_ASSOC)
    assert mech is not None and mech["velocities"].shape == (54, 3)


def test_code_version_tracks_the_package_sources() -> None:
    assert code_version("macro") != code_version("micro")
    assert len(code_version("macro")) == 16


def test_not_buildable_micro_wall_is_reported_not_raised(tmp_path: Path) -> None:
    spec = WallSpec.from_paper(t=30, m=1, rows=12, f=0.6)  # L = 0.4 is shorter than half a block (0.5)
    rec = Runner(tmp_path).run(spec, MICRO_ASSOC)
    assert rec.status == "not_applicable" and math.isnan(rec.load_factor)
    assert "half a block" in rec.values["message"]
