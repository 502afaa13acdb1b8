"""The scaling fit of the report: exact on a power law, answered records only."""

from __future__ import annotations

import math

import pytest

from comparison.report.scaling import ScalingPoint, by_method, fit


def test_fit_recovers_an_exact_power_law() -> None:
    pts = [ScalingPoint("m", f"w{b}", b, 2e-4 * b**1.5, "optimal") for b in (54, 450, 1230, 7575)]
    f = fit(pts)
    assert f is not None and f.points == 4
    assert f.exponent == pytest.approx(1.5, rel=1e-9)
    assert f.prefactor == pytest.approx(2e-4, rel=1e-9)
    assert float(f.seconds(1000)) == pytest.approx(2e-4 * 1000**1.5, rel=1e-9)


def test_fit_leaves_out_records_without_an_answer() -> None:
    pts = [ScalingPoint("m", "a", 100, 1.0, "converged"), ScalingPoint("m", "b", 1000, 10.0, "converged"),
           ScalingPoint("m", "c", 2000, 1e4, "cycling")]
    f = fit(pts)
    assert f is not None and f.points == 2 and f.exponent == pytest.approx(1.0)
    assert fit(pts[:1] + pts[2:]) is None  # one answered block count: no slope
    assert math.isclose(by_method(pts)["m"][2].seconds, 1e4)
