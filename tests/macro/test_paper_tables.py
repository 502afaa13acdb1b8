"""Golden values: the paper's Tables 5, 7 and 9 against the faithful model.

Two kinds of assertion per case:

* ``FAITHFUL`` pins what this implementation computes (Eq. 10 minimised
  globally), to 1e-6 relative in lambda and 2e-3 degrees in alpha_c, so that
  any change that moves a number fails here, naming the case;
* the published value must agree within the paper's rounding (half a unit in
  the last printed decimal) unless the case is listed in ``KNOWN_GAPS`` with
  the gap measured and explained (README, "Where the paper and the model
  differ"); a listed gap must stay what it is, so it cannot silently grow or
  vanish.
"""

from __future__ import annotations

import pytest

import macro
from comparison.domain.cases import CASES, case

# case: (Eq. 10 minimum lambda_r, alpha_c [deg], hinge storey)
FAITHFUL = {
    "Ref": (0.582516, 40.1473, 3),
    "1": (0.519368, 35.5124, 3),
    "2": (0.626076, 43.3403, 3),
    "3": (0.575624, 40.1217, 3),
    "4": (0.575077, 40.1194, 3),
    "5": (0.587888, 40.1739, 3),
    "6": (0.585175, 40.1600, 3),
    "7": (0.408980, 55.6946, 3),
    "8": (0.292912, 56.3099, 3),
    "9": (0.450589, 35.1249, 3),
    "10": (0.252135, 26.5651, 3),
    "11": (0.648067, 42.6463, 1),
    "12": (0.648067, 42.6461, 1),
    "13": (0.491381, 37.7175, 1),
    "14": (0.261667, 26.5651, 1),
    "15": (0.611827, 42.6070, 5),
    "16": (0.606016, 48.0282, 5),
    "17": (0.603511, 48.2253, 5),
}

# (case, quantity): (relative gap of ours vs published, tolerance on that gap, reason)
KNOWN_GAPS = {
    ("3", "lambda"): (-0.0041, 0.0005, "p reading / floor-load terms: 0.5756 vs 0.578"),
    ("3", "alpha_c_deg"): (0.00029, 0.0001, "p reading / floor-load terms: 40.122 vs 40.11 deg"),
    ("4", "lambda"): (-0.0016, 0.0005, "p reading / floor-load terms: 0.5751 vs 0.576"),
    ("4", "hinge_storey"): (2.0, 0.0, "hinges within 1e-4 of each other; paper: top storey"),
    ("5", "lambda"): (0.1460, 0.0005, "o = 36: paper 0.513 contradicts its own 'rows irrelevant'"),
    ("5", "alpha_c_deg"): (0.0736, 0.0005, "o = 36: see lambda"),
    ("5", "alpha_ratio"): (0.0810, 0.0010, "o = 36: see lambda"),
    ("7", "lambda"): (0.0073, 0.0005, "crack leaving through the side: C/D drawn with tan(alpha*)"),
    ("7", "alpha_c_deg"): (0.00098, 0.0001, "as lambda: 55.695 vs 55.64 deg"),
    ("8", "lambda"): (0.0100, 0.0005, "crack leaving through the side: C/D drawn with tan(alpha*)"),
    ("15", "lambda"): (0.3018, 0.0010, "Table 9 matches m = 1/2, not the m = 1/3 of Table 6"),
    ("16", "lambda"): (0.2894, 0.0010, "Table 9 matches m = 1/2, not the m = 1/3 of Table 6"),
    ("17", "lambda"): (0.2841, 0.0010, "Table 9 matches m = 1/2, not the m = 1/3 of Table 6"),
}


@pytest.fixture(scope="module")
def results() -> dict[str, macro.MacroResult]:
    return {c.case: macro.solve(c.spec().to_macro()) for c in CASES}


@pytest.mark.parametrize("name", list(FAITHFUL))
def test_faithful_values_pinned(results: dict[str, macro.MacroResult], name: str) -> None:
    lam, alpha, hinge = FAITHFUL[name]
    r = results[name]
    assert r.rocking_load_factor == pytest.approx(lam, rel=1e-6, abs=5e-7), f"Set {name}: lambda_r moved"
    assert r.alpha_c_deg == pytest.approx(alpha, abs=2e-3), f"Set {name}: alpha_c moved"
    assert r.hinge_storey == hinge, f"Set {name}: hinge moved"
    assert r.status == "optimal"


def _ours(r: macro.MacroResult, quantity: str) -> float:
    return {
        "lambda": r.rocking_load_factor,  # the paper tabulates Eq. (10)'s minimum
        "alpha_c_deg": r.alpha_c_deg,
        "alpha_ratio": r.alpha_ratio,
        "hinge_storey": float(r.hinge_storey),
    }[quantity]


PUBLISHED = [(c.case, v.quantity, v.value, v.rounding) for c in CASES for v in c.published if v.model == "proposed"]


@pytest.mark.parametrize(
    ("name", "quantity", "value", "rounding"), PUBLISHED, ids=[f"{p[0]}-{p[1]}" for p in PUBLISHED]
)
def test_published_values(
    results: dict[str, macro.MacroResult], name: str, quantity: str, value: float, rounding: float
) -> None:
    ours = _ours(results[name], quantity)
    gap = KNOWN_GAPS.get((name, quantity))
    if gap is None:
        assert abs(ours - value) <= rounding + 1e-12, (
            f"Set {name} {quantity}: ours {ours:.6g} vs published {value} (rounding {rounding})"
        )
    elif quantity == "hinge_storey":
        assert ours - value == gap[0], f"Set {name}: {gap[2]}"
    else:
        rel = (ours - value) / value
        assert rel == pytest.approx(gap[0], abs=gap[1]), f"Set {name} {quantity}: gap {rel:+.4f}, {gap[2]}"


def test_table9_matches_half_unit_shape_ratio() -> None:
    """The evidence for the Table 9 note: with m = 1/2 all three sets print 0.47."""
    for name in ("15", "16", "17"):
        c = case(name)
        spec = type(c.spec()).from_paper(t=c.t, m=0.5, rows=c.rows, f=c.f, p=c.p, storeys=c.storeys)
        assert round(macro.solve(spec.to_macro()).load_factor, 2) == 0.47


def test_set1_exceeds_base_sliding() -> None:
    """Set 1 (f = 0.4): Eq. (10) gives the published 0.519 > f, so base sliding governs."""
    r = macro.solve(case("1").spec().to_macro())
    assert r.rocking_load_factor == pytest.approx(0.519, abs=5e-4)
    assert r.load_factor == pytest.approx(0.4)
    assert r.mechanism == "sliding"


def test_p_reading_matters_little() -> None:
    """Reading H in p = q/(gamma H b) as the storey height moves Table 5 by < 0.25 %."""
    for name in ("3", "4"):
        a = macro.solve(case(name).spec("wall").to_macro()).rocking_load_factor
        b = macro.solve(case(name).spec("storey").to_macro()).rocking_load_factor
        assert 0.0 < abs(a - b) / a < 0.0025
