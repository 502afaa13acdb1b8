"""Fuzzing scene files: random bytes, random TOML and extreme numbers.

A scene either reads into a wall the macro model solves (finite positive
lambda, status optimal) or fails with one ``SceneError`` line naming the file;
through the command line, exit 0 or 2 and never a traceback.
"""

from __future__ import annotations

import contextlib
import io
import math
import tempfile
from pathlib import Path
from typing import Any

from fuzz_strategies import EDGES, FUZZ, mark, one_line_error
from hypothesis import event, given
from hypothesis import strategies as st

import macro
from comparison.cli import main
from comparison.domain.scene import SceneError, load_scene
from macro.checks import TooLarge

pytestmark = mark

KEYS = {
    "": ["name", "wall", "block", "storey", "colour"],
    "wall": ["length", "unit_weight", "friction", "height"],
    "block": ["length", "height", "width"],
    "storey": ["rows", "thickness", "overload", "roof"],
}


def _toml_number(x: float) -> str:
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


scalar = st.one_of(
    st.floats().map(_toml_number),
    st.sampled_from(EDGES).map(_toml_number),
    st.floats(0.01, 50.0).map(_toml_number),
    st.integers(-(10**25), 10**25).map(str),
    st.integers(1, 40).map(str),
    st.text(max_size=5).map(lambda s: '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'),
    st.sampled_from(["true", "[1, 2]", "{ a = 1 }", '"1/3"', "1979-05-27", "0x1F", "1e400"]),
)


@st.composite
def scene_text(draw: st.DrawFn) -> str:
    """A TOML text with the scene's tables, some keys missing, some unknown, random values."""
    lines: list[str] = []
    if draw(st.booleans()):
        lines.append(f"name = {draw(scalar)}")
    for table in ("wall", "block"):
        if draw(st.integers(0, 9)):
            lines.append(f"[{table}]")
            lines += [f"{k} = {draw(scalar)}" for k in KEYS[table] if draw(st.integers(0, 3))]
    for _ in range(draw(st.integers(0, 4))):
        lines.append(draw(st.sampled_from(["[[storey]]", "[[storey]]", "[storey]", "[[wall]]"])))
        lines += [f"{k} = {draw(scalar)}" for k in KEYS["storey"] if draw(st.integers(0, 3))]
    if draw(st.integers(0, 9)) == 0:
        lines.insert(draw(st.integers(0, len(lines))), draw(st.text(max_size=20)))
    return "\n".join(lines) + "\n"


def plausible_scene(draw: st.DrawFn) -> str:
    """A well-formed scene whose numbers are ordinary, now and then extreme."""

    def value(lo: float, hi: float) -> str:
        extreme = draw(st.sampled_from([False] * 11 + [True]))
        return _toml_number(draw(st.one_of(st.sampled_from(EDGES), st.floats()) if extreme else st.floats(lo, hi)))

    storeys = "".join(
        f"[[storey]]\nrows = {draw(st.integers(1, 30))}\nthickness = {value(0.05, 0.5)}\n"
        f"overload = {value(0.0, 10.0)}\n"
        for _ in range(draw(st.integers(1, 4)))
    )
    return (
        f"[wall]\nlength = {value(2.0, 20.0)}\nunit_weight = {value(1.0, 30.0)}\nfriction = {value(0.2, 1.0)}\n"
        f"[block]\nlength = {value(0.1, 1.0)}\nheight = {value(0.05, 0.5)}\n{storeys}"
    )


def _check_scene(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "fuzz.toml"
        path.write_bytes(data)
        try:
            spec = load_scene(path)
        except SceneError as exc:
            assert str(path) in str(exc) and "\n" not in str(exc)
            event("refused")
            spec = None
        if spec is not None:
            try:
                r = macro.solve(spec.to_macro())
            except TooLarge:
                pass
            else:
                assert r.status == "optimal" and math.isfinite(r.load_factor) and r.load_factor > 0, r
                event("solved")
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["macro", "--scene", str(path), "--json"])
        assert code in (0, 2), (code, err.getvalue())
        if code == 2:
            assert one_line_error(err.getvalue()) and str(path) in err.getvalue(), err.getvalue()
        else:
            d: dict[str, Any] = __import__("json").loads(out.getvalue())
            assert d["status"] == "optimal" and d["load_factor"] > 0


@FUZZ
@given(data=st.one_of(st.binary(max_size=200), scene_text().map(lambda s: s.encode("utf-16"))))
def test_fuzz_scene_bytes(data: bytes) -> None:
    _check_scene(data)


@FUZZ
@given(text=scene_text())
def test_fuzz_scene_toml(text: str) -> None:
    _check_scene(text.encode())


@FUZZ
@given(text=st.composite(plausible_scene)())
def test_fuzz_scene_extreme_numbers(text: str) -> None:
    _check_scene(text.encode())
