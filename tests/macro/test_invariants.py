"""Physical and numerical invariants of the macro-block model."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import macro
from comparison.domain.wall import WallSpec
from comparison.runner.macro_record import macro_record

walls = st.builds(  # t at most o m: a wall at least one block long (macro.checks.wall_bounds)
    lambda t, m, per, n, f, p: WallSpec.from_paper(t=min(t, per * n * m), m=m, rows=per * n, f=f, p=p, storeys=n)
    .to_macro(),
    t=st.floats(0.3, 4.0),
    m=st.sampled_from([0.25, 1 / 3, 0.5, 2 / 3, 1.0]),
    per=st.integers(1, 40),
    n=st.integers(1, 4),
    f=st.floats(0.2, 1.2),
    p=st.floats(0.0, 8.0),
)


def _scaled(w: macro.MacroWall, length: float, weight: float) -> macro.MacroWall:
    """Same wall in other units: lengths x ``length``, unit weight x ``weight``."""
    return replace(
        w,
        length=w.length * length,
        block_length=w.block_length * length,
        block_height=w.block_height * length,
        thickness=tuple(x * length for x in w.thickness),
        overload=tuple(q * weight * length**2 for q in w.overload),  # q ~ gamma H b
        unit_weight=w.unit_weight * weight,
    )


@settings(max_examples=40, deadline=None)
@given(w=walls, length=st.floats(1e-3, 1e3), weight=st.floats(1e-2, 1e4))
def test_scale_invariance(w: macro.MacroWall, length: float, weight: float) -> None:
    a, b = macro.solve(w), macro.solve(_scaled(w, length, weight))
    assert b.rocking_load_factor == pytest.approx(a.rocking_load_factor, rel=1e-9)
    assert b.tan_alpha_c == pytest.approx(a.tan_alpha_c, rel=1e-4)
    assert b.hinge_storey == a.hinge_storey or b.hinges[a.hinge_storey - 1].rocking_load_factor == pytest.approx(
        b.rocking_load_factor, rel=1e-9
    )


@settings(max_examples=30, deadline=None)
@given(w=walls, df=st.floats(0.01, 0.5))
def test_load_factor_grows_with_friction(w: macro.MacroWall, df: float) -> None:
    lo = macro.solve(w)
    hi = macro.solve(replace(w, friction=w.friction + df))
    assert hi.rocking_load_factor >= lo.rocking_load_factor - 1e-12
    assert hi.load_factor >= lo.load_factor - 1e-12


@settings(max_examples=40, deadline=None)
@given(w=walls)
def test_crack_within_eq11_and_bounded_by_friction(w: macro.MacroWall) -> None:
    r = macro.solve(w)
    n = sum(w.rows[: r.hinge_storey])
    lo, hi = w.overlap / (n * w.block_height), w.overlap / w.block_height
    assert lo * (1 - 1e-12) <= r.tan_alpha_c <= hi * (1 + 1e-12)
    assert 0.0 <= r.alpha_ratio <= 1.0 + 1e-12
    assert r.load_factor <= w.friction
    assert r.load_factor == pytest.approx(min(r.rocking_load_factor, w.friction))
    assert r.mechanism == ("sliding" if w.friction < r.rocking_load_factor else r.mechanism)


@settings(max_examples=15, deadline=None)
@given(w=walls)
def test_global_minimum_against_dense_grid(w: macro.MacroWall) -> None:
    """No crack angle on a 20,001-point grid of any hinge beats the search."""
    r = macro.solve(w)
    for k in range(1, w.storeys + 1):
        n = sum(w.rows[:k])
        a = np.linspace(math.atan(w.overlap / (n * w.block_height)), w.alpha_b, 20001)
        grid = macro.load_factor_curve(w, k, np.tan(a))["lambda_r"]
        assert r.rocking_load_factor <= grid.min() * (1 + 1e-10)


def test_eq10_rebuilt_from_storey_terms() -> None:
    """The audit trail reproduces Eq. (10) and Eq. (12) term by term."""
    w = WallSpec.from_paper(t=2, m=1 / 3, rows=60, f=0.6, p=2, storeys=3).to_macro()
    r = macro.solve(w)
    s = r.storeys
    stab = sum(x.W_A * x.x_WA + x.W_B * x.x_WB + x.W_C * x.x_WC + x.W_D * x.x_WD + x.Q * x.x_Q for x in s)
    over = sum(x.W_A * x.y_WA + x.W_B * x.y_WB + x.W_C * x.y_WC + x.W_D * x.y_WD + x.Q * x.y_Q for x in s)
    fric = sum(x.F_g * x.y_Fg + x.F_q * x.y_Fq for x in s)
    assert stab == pytest.approx(r.stabilising_moment)
    assert over == pytest.approx(r.overturning_moment)
    assert fric == pytest.approx(r.friction_moment)
    red = 1 - math.radians(r.alpha_c_deg) / math.radians(r.alpha_b_deg)
    assert (stab + red * fric) / over == pytest.approx(r.rocking_load_factor, rel=1e-12)
    weight = sum(x.W_A + x.W_B + x.W_C + x.W_D + x.Q for x in s)
    assert sum(x.F_g + x.F_q for x in s) / weight == pytest.approx(r.sliding_load_factor, rel=1e-12)
    # Table 1's case: alpha_p2 < alpha_c < alpha_p3: storey 1 uncrossed, 2 partly, 3 wholly crossed
    assert s[0].n_c == 0 and 0 < s[1].n_c < 20 and s[2].n_c == 20


def test_sliding_load_factor_equals_f_at_pure_rocking() -> None:
    """Eq. (12): lambda_s = f when tan(alpha_c) = tan(alpha_b) (single storey, no overload)."""
    r = macro.solve(WallSpec.from_paper(t=1, m=1, rows=12, f=0.75).to_macro())
    assert r.mechanism == "rocking"
    assert r.sliding_load_factor == pytest.approx(0.75, rel=1e-12)


def test_sweep_matches_solve() -> None:
    rng = np.random.default_rng(7)
    t, m = rng.uniform(0.4, 3, 40), rng.choice([1 / 3, 0.5, 1.0], 40)
    f, p = rng.uniform(0.3, 0.9, 40), rng.uniform(0, 8, 40)
    for n in (1, 3):
        rows = n * rng.choice([4, 12, 20], 40)
        t = np.minimum(t, rows * m)  # a wall at least one block long
        s = macro.sweep(t, m, rows, f, p, storeys=n)
        for i in range(40):
            spec = WallSpec.from_paper(t=t[i], m=m[i], rows=int(rows[i]), f=f[i], p=p[i], storeys=n)
            r = macro.solve(spec.to_macro())
            assert s.rocking_load_factor[i] == pytest.approx(r.rocking_load_factor, rel=1e-8)
            assert s.load_factor[i] == pytest.approx(r.load_factor, rel=1e-8)
            # Eq. (12) is not stationary at the optimum: it inherits the ~1e-5 rad spread of alpha_c
            assert s.sliding_load_factor[i] == pytest.approx(r.sliding_load_factor, rel=1e-4)
            assert macro.MECHANISMS[s.mechanism[i]] == r.mechanism


def test_sweep_broadcasts_and_keeps_shape() -> None:
    s = macro.sweep(np.array([[1.0], [2.0]]), 1 / 3, 60, np.array([0.4, 0.6, 0.8]), storeys=3)
    assert s.load_factor.shape == (2, 3)
    assert np.all(np.diff(s.rocking_load_factor, axis=1) > 0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(t=0), "t must be a positive number"),
        (dict(m=1.5), "m must be in (0, 1]"),
        (dict(m=0), "m must be a positive number"),
        (dict(rows=12.5), "rows must be a positive integer"),
        (dict(rows=0), "rows must be a positive integer"),
        (dict(f=0), "f must be a positive number"),
        (dict(p=-1), "p must be zero or a positive number"),
        (dict(rows=10, storeys=3), "rows: 10 rows cannot be split equally over 3 storeys"),
    ],
)
def test_sweep_bad_input(kwargs: dict[str, float], message: str) -> None:
    args = dict(t=1.0, m=1 / 3, rows=12, f=0.6, p=0.0, storeys=1) | kwargs
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("]", r"\]")):
        macro.sweep(**args)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("length", 0.0, "length must be a positive number"),
        ("block_height", -1.0, "block_height must be a positive number"),
        ("friction", 0.0, "friction must be a positive number"),
        ("rows", (20, 0), r"rows\[1\] must be a positive integer"),
        ("rows", (20, 2.5), r"rows\[1\] must be a positive integer"),
        ("rows", (), "at least one storey"),
        ("overload", (0.0, -1.0), r"overload\[1\] must be zero or a positive number"),
        ("thickness", (1.0,), "one value per storey"),
    ],
)
def test_wall_bad_input(field: str, value: object, message: str) -> None:
    base = dict(
        length=10.0, block_length=3.0, block_height=1.0, rows=(20, 20), thickness=(1.0, 1.0), overload=(0.0, 0.0)
    )
    base[field] = value
    with pytest.raises(ValueError, match=message):
        macro.MacroWall(**base)  # type: ignore[arg-type]


def test_fused_eq10_matches_term_by_term() -> None:
    """The search's fused Eq. (10) equals the Table 2 terms summed one by one."""
    from macro.equations import evaluate, load_factor
    from macro.solve import _problems

    rng = np.random.default_rng(3)
    for _ in range(60):
        n = int(rng.integers(1, 5))
        m, rows = rng.choice([0.25, 1 / 3, 0.5, 1.0]), n * int(rng.integers(1, 30))
        w = WallSpec.from_paper(
            t=min(rng.uniform(0.3, 4), rows * m), m=m, rows=rows, f=rng.uniform(0.2, 1.0), p=rng.uniform(0, 8),
            storeys=n,
        ).to_macro()  # fmt: skip
        pb = _problems(w)
        tau = np.tan(rng.uniform(0.0, 1.2, (pb.size, 40)))
        np.testing.assert_allclose(load_factor(tau, pb), evaluate(tau, pb)["lambda_r"], rtol=1e-12)



def test_a_macro_record_reads_as_a_mapping_of_its_fields() -> None:
    """The records of both models read alike: read-only mappings of their fields."""
    import dataclasses
    from collections.abc import Mapping

    rec = macro_record(macro.solve(WallSpec.from_paper(t=1, m=1 / 3, rows=60, f=0.6, storeys=3).to_macro()))
    assert isinstance(rec, Mapping)
    assert rec["hinge_storey"] == rec.hinge_storey == 3 and rec["mechanism"] == "rocking-sliding"
    assert list(rec) == [f.name for f in dataclasses.fields(rec)] and dict(rec)["load_factor"] == rec.load_factor
    with pytest.raises(KeyError):
        rec["lowest_stop"]
