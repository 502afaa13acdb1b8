"""Fuzzing collapse state files: random bytes, random JSON, a valid state with one entry replaced.

A state file either reads into a state that ``verify`` checks (every residual a number or NaN, passed or
not; never an exception) or fails with one ``StateFileError`` line naming the file; through the command
line, exit 0, 1 or 2 and never a traceback.
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import math
import tempfile
from pathlib import Path
from typing import Any

from fuzz_strategies import EDGES, FUZZ, mark, one_line_error
from hypothesis import given
from hypothesis import strategies as st

from comparison.cli import main
from micro import StateFileError, read_state, verify_state

pytestmark = mark

B, H, W = 0.3, 1.2, 0.36
#: One block rocking on its base (``tests/micro/test_state.py``): a genuine collapse state.
ROCKING: dict[str, Any] = {
    "format": "xcheck-masonry collapse state", "version": 1, "friction": "nonassociative", "load_factor": B / H,
    "direction": "+x",
    "blocks": [{"vertices": [[0, 0], [B, 0], [B, H], [0, H]], "centroid": [B / 2, H / 2], "weight": W,
                "dead": [0, -W, 0], "live": [W, 0, 0]}],
    "points": [{"blocks": [-1, 0], "position": [0, 0], "normal": [0, 1], "tangent": [1, 0], "mu": 0.6},
               {"blocks": [-1, 0], "position": [B, 0], "normal": [0, 1], "tangent": [1, 0], "mu": 0.6}],
    "normal_forces": [0, W], "shear_forces": [0, -W * B / H], "velocities": [[H / 2, B / 2, -1]],
    "opening_rates": [B, 0], "slip_rates": [0, 0], "contact_states": ["opening", "closed"],
}

json_values = st.recursive(
    st.one_of(st.none(), st.booleans(), st.floats(allow_nan=False, allow_infinity=False), st.sampled_from(
        [x for x in EDGES if math.isfinite(x)]), st.integers(-(10**30), 10**30), st.text(max_size=6)),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=6), inner, max_size=4)),
    max_leaves=12,
)


def _paths(doc: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Every path to an entry of ``doc``."""
    out = [prefix] if prefix else []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += _paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            out += _paths(v, (*prefix, i))
    return out


PATHS = _paths(ROCKING)


def _check(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "state.json"
        path.write_bytes(data)
        try:
            check = verify_state(read_state(path))
        except StateFileError as exc:
            assert str(exc).startswith(f"state {path}") and "\n" not in str(exc)
        else:
            assert all(isinstance(r.value, float) for r in check.residuals)
            assert check.passed == all(r.passed for r in check.residuals)
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["verify", str(path), "-q"])
        assert code in (0, 1, 2)
        assert (code == 2) == one_line_error(err.getvalue()) and (code == 2 or err.getvalue() == "")


@FUZZ
@given(st.binary(max_size=200))
def test_random_bytes(data: bytes) -> None:
    _check(data)


@FUZZ
@given(json_values)
def test_random_json(doc: Any) -> None:
    _check(json.dumps(doc).encode())


@FUZZ
@given(st.sampled_from(PATHS), json_values)
def test_a_valid_state_with_one_entry_replaced(path: tuple[Any, ...], value: Any) -> None:
    doc = copy.deepcopy(ROCKING)
    target = doc
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    _check(json.dumps(doc).encode())


@FUZZ
@given(st.sampled_from([p for p in PATHS if isinstance(p[-1], int) or p[-1] in ("load_factor", "mu", "weight")]),
       st.sampled_from(EDGES[:-3] + (1e308, -1e308, 1e-320)))
def test_a_valid_state_with_an_extreme_number(path: tuple[Any, ...], value: float) -> None:
    doc = copy.deepcopy(ROCKING)
    target = doc
    for key in path[:-1]:
        target = target[key]
    if isinstance(target[path[-1]], (int, float)) and not isinstance(target[path[-1]], bool):
        target[path[-1]] = value
    _check(json.dumps(doc, allow_nan=True).encode())
