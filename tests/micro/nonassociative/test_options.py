"""NonAssociativeOptions: validation with the parameter named, overrides."""

from __future__ import annotations

import pytest

import micro
from comparison.wall import WallSpec
from micro.nonassociative import solve_nonassociative

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey,
#: 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


def wall(t: float, m: float, rows: int = 12, storeys: int = 1, f: float = 0.75, **kw: object) -> micro.BlockWall:
    return WallSpec.from_paper(t=t, m=m, rows=rows, f=f, p=0, storeys=storeys).to_micro(**kw)


@pytest.mark.parametrize(
    "kw, word",
    [
        (dict(scheme="c"), "scheme"),
        (dict(relaxation=0.0), "relaxation"),
        (dict(relaxation=1.5), "relaxation"),
        (dict(relaxation=True), "relaxation"),
        (dict(max_iterations=1), "max_iterations"),
        (dict(window=2), "window"),
        (dict(directions="up"), "directions"),
        (dict(start="warm"), "start"),
        (dict(lambda_tol=0.0), "lambda_tol"),
        (dict(alpha0=1e-4, alpha_min=1e-3), "alpha_min"),
        (dict(alpha_factor=2.0), "alpha_factor"),
        (dict(time_limit=-1.0), "time_limit"),
        (dict(settle_tol=1.0), "settle_tol"),
        (dict(settle_window=1), "settle_window"),
        (dict(state_solver="gurobi"), "state_solver"),
    ],
)
def test_bad_inputs(kw: dict, word: str) -> None:
    with pytest.raises(ValueError, match=word):
        solve_nonassociative(wall(1.0, 1 / 3, rows=6), **kw)


def test_options_are_frozen_defaults_and_overrides() -> None:
    import dataclasses

    o = micro.NonAssociativeOptions()
    assert o.scheme == "a" and o.beta == 0.6 and o.relaxation is None and o.max_iterations == 100
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.scheme = "b"  # type: ignore[misc]
    b = o.with_overrides(scheme="b", max_seconds=20)
    assert b.scheme == "b" and b.max_seconds == 20.0 and isinstance(b.max_seconds, float) and o.scheme == "a"
    with pytest.raises(TypeError, match="unknown option"):
        o.with_overrides(shceme="b")
    with pytest.raises(ValueError, match="relaxation"):
        micro.NonAssociativeOptions(relaxation=2.0)
    # the options object and keyword overrides give the same run
    w = wall(1.0, 1 / 3, rows=6)
    r1 = solve_nonassociative(w, micro.NonAssociativeOptions(scheme="b"), max_iterations=10)
    r2 = solve_nonassociative(w, scheme="b", max_iterations=10)
    assert [h.load_factor for h in r1.history] == [h.load_factor for h in r2.history]
    assert r1.options == r2.options and r1.summary()["options"]["relaxation"] == 0.6
