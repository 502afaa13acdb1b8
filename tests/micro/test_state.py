"""The collapse state file: written, read back bit for bit, and verified from its own data.

A genuine state passes every residual; a state tampered with (lambda raised by 1 %, a force's sign
flipped, one block's velocity scaled) fails, naming the residual; a state written by hand as another
program would (one block rocking on its base, lambda = b/h in closed form) verifies; every malformed file
is refused with one line naming the file and the field or line.
"""

from __future__ import annotations

import copy
import dataclasses
import errno
import json
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from micro_walls import table7_wall, three_storey_wall

import micro
import micro.files
from comparison.domain.wall import WallSpec
from micro.state import CollapseStateData, collapse_state, parse_state, read_state, verify_state, write_state
from micro.state import check as state_check
from micro.state import file as state_file

SCHEMA = Path(__file__).parents[2] / "docs" / "schemas" / "state.schema.json"
#: The small walls: Table 7's Sets 12-14 and a wall whose courses end with cut blocks (L = 8 blocks
#: heights, l = 3: 5.33 half blocks).
WALLS = ("set12", "set13", "set14", "cut")
FRICTIONS = ("associative", "nonassociative")


def _wall(name: str) -> micro.BlockWall:
    if name == "cut":
        return WallSpec.from_paper(t=1, m=1 / 3, rows=8, f=0.65).to_micro()
    return table7_wall(name)


@pytest.fixture(scope="module")
def solved() -> dict[tuple[str, str], tuple[micro.BlockWall, Any]]:
    out = {}
    for name in WALLS:
        wall = _wall(name)
        out[name, "associative"] = wall, micro.solve_associative(wall)
        out[name, "nonassociative"] = wall, micro.solve_nonassociative(wall)
    return out


def test_the_cut_wall_has_cut_blocks() -> None:
    wall = _wall("cut")
    lengths = np.unique(np.round(wall.block_lengths, 9))
    assert len(lengths) > 2  # full, half and cut blocks


@pytest.mark.parametrize("friction", FRICTIONS)
@pytest.mark.parametrize("name", WALLS)
def test_round_trip_reads_back_bit_for_bit_and_verifies(solved, name: str, friction: str, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved[name, friction]
    path = write_state(result, tmp_path / "state.json", wall=wall, source={"wall": name})
    state, back = collapse_state(result, wall, source={"wall": name}), read_state(path)
    for f in dataclasses.fields(CollapseStateData):
        a, b = getattr(state, f.name), getattr(back, f.name)
        if isinstance(a, np.ndarray):
            assert np.array_equal(a, b), f.name
        elif f.name == "vertices":
            assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
        else:
            assert a == b, f.name
    check = verify_state(path)
    assert check.passed, check.worst.describe()
    assert check.friction == friction and check.blocks == wall.n_blocks and check.points == wall.n_points


@pytest.mark.parametrize("friction", FRICTIONS)
def test_the_state_written_is_the_value_to_quote(solved, friction: str) -> None:  # type: ignore[no-untyped-def]
    """Non-associative: the lowest certified state (the value the CLI prints first); associative: the LP's."""
    wall, result = solved["set13", friction]
    state = collapse_state(result, wall)
    if friction == "associative":
        assert state.load_factor == result.load_factor and state.source["state"] == "associative LP"
    else:
        assert state.load_factor == result.load_factor == result.lowest_load_factor
        assert state.source["state"] == "lowest certified"
        assert state.load_factor < result.iterated_load_factor  # Set 13: the descent moved below the iterated LP
    plain = micro.solve_nonassociative(wall, lowest=False)
    iterated = collapse_state(plain, wall)
    assert iterated.load_factor == plain.load_factor == plain.iterated_load_factor
    assert iterated.source["state"] == "iterated LP"
    assert verify_state(iterated).passed


@pytest.mark.parametrize("friction", FRICTIONS)
def test_velocities_do_unit_work_and_rates_are_those_of_the_velocities(solved, friction: str) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved["set12", friction]
    s = collapse_state(result, wall)
    assert float(s.live.ravel() @ s.velocities.ravel()) == pytest.approx(1.0, rel=1e-9)
    Bn, Bs = s.equilibrium_matrices()
    assert np.array_equal(s.opening_rate, Bn.T @ s.velocities.ravel())
    assert np.array_equal(s.slip_rate, Bs.T @ s.velocities.ravel())
    # the equilibrium matrix of the file's geometry is the LP's, rescaled (lengths in block heights)
    lp = micro.assemble(wall)
    assert abs(Bn[:, :].toarray()[0::3] - lp.Bn.toarray()[0::3]).max() < 1e-12


@pytest.mark.parametrize("friction", FRICTIONS)
def test_a_state_in_minus_x_holds_its_live_load_as_applied(friction: str, tmp_path: Path) -> None:
    """The cut wall is not its own mirror image: its -x state is another state, live loads pushing to -x."""
    wall = _wall("cut")
    solve = micro.solve_associative if friction == "associative" else micro.solve_nonassociative
    result = solve(wall, directions="-x")
    back = read_state(write_state(result, tmp_path / "minus.json", wall=wall))
    assert back.direction == "-x" and np.all(back.live[:, 0] <= 0) and back.live[:, 0].sum() < 0
    assert verify_state(back).passed
    assert float(back.live.ravel() @ back.velocities.ravel()) == pytest.approx(1.0, rel=1e-9)


@pytest.mark.parametrize("friction", FRICTIONS)
@pytest.mark.parametrize("bond", [("half", "frictional"), ("full", "frictionless"), ("half", "frictionless")])
@pytest.mark.parametrize("name", ["set12", "set14"])
def test_the_bond_variants_of_table_7_verify(name: str, bond: tuple[str, str], friction: str) -> None:
    """The report's other bonds: a half block first, and frictionless head joints (mu = 0 at their points)."""
    wall = table7_wall(name, first_course=bond[0], head_joints=bond[1])
    result = micro.solve_associative(wall) if friction == "associative" else micro.solve_nonassociative(wall)
    state = collapse_state(result, wall)
    assert (0.0 in state.mu) == (bond[1] == "frictionless")
    check = verify_state(parse_state(state_file.dumps_state(state)))
    assert check.passed, check.worst.describe()


@pytest.mark.parametrize("friction", FRICTIONS)
def test_a_wall_with_floor_loads_verifies(friction: str) -> None:
    """Three storeys of unequal thickness with floor loads: dead loads beyond the weight, live moments."""
    wall = three_storey_wall()
    result = micro.solve_associative(wall) if friction == "associative" else micro.solve_nonassociative(wall)
    state = collapse_state(result, wall)
    assert np.any(state.live[:, 2] != 0) and np.any(-state.dead[:, 1] > state.weight)
    check = verify_state(parse_state(state_file.dumps_state(state)))
    assert check.passed, check.worst.describe()


# --------------------------------------------------------------------------- tampered states
@pytest.mark.parametrize("friction", FRICTIONS)
@pytest.mark.parametrize("name", WALLS)
def test_a_load_factor_raised_by_one_percent_fails(solved, name: str, friction: str) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved[name, friction]
    state = collapse_state(result, wall)
    check = verify_state(dataclasses.replace(state, load_factor=state.load_factor * 1.01))
    assert not check.passed
    assert {r.name for r in check.failed} >= {"power", "equilibrium"}
    assert check.worst.name in ("power", "equilibrium")
    assert check.residual("power").value == pytest.approx(0.01, rel=0.05)


def _tamper(state: CollapseStateData, **arrays: np.ndarray) -> CollapseStateData:
    return dataclasses.replace(state, **arrays)


@pytest.mark.parametrize("friction", FRICTIONS)
def test_a_normal_force_with_its_sign_flipped_fails_no_tension_and_equilibrium(solved, friction: str) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved["set12", friction]
    state = collapse_state(result, wall)
    n = state.normal_force.copy()
    k = int(np.argmax(n))
    n[k] = -n[k]
    check = verify_state(_tamper(state, normal_force=n))
    assert {r.name for r in check.failed} >= {"no_tension", "equilibrium"}
    assert check.residual("no_tension").value == pytest.approx(1.0)  # the largest force, reversed
    assert check.worst.name == "equilibrium"  # twice the largest force unbalanced


def test_a_shear_force_with_its_sign_flipped_at_a_slipping_point_fails(solved) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved["set13", "nonassociative"]
    state = collapse_state(result, wall)
    s = state.shear_force.copy()
    slipping = np.abs(state.slip_rate) * np.abs(s)
    k = int(np.argmax(slipping))
    s[k] = -s[k]
    check = verify_state(_tamper(state, shear_force=s))
    assert not check.passed
    assert {"friction", "equilibrium"} <= {r.name for r in check.failed}  # the power balance reads the law, not s


@pytest.mark.parametrize("friction", FRICTIONS)
def test_one_block_velocity_scaled_fails_compatibility(solved, friction: str) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved["set14", friction]
    state = collapse_state(result, wall)
    v = state.velocities.copy()
    k = int(np.argmax(np.abs(v).sum(axis=1)))  # the fastest block
    v[k] *= 1.1
    check = verify_state(_tamper(state, velocities=v))
    assert not check.passed and check.worst.name == "compatibility"


def test_an_associative_mechanism_is_not_a_nonassociative_state(solved) -> None:  # type: ignore[no-untyped-def]
    """The associative LP's state dilates where it slides: read as zero-dilatancy, it fails there."""
    wall, result = solved["set12", "associative"]
    state = dataclasses.replace(collapse_state(result, wall), friction="nonassociative")
    check = verify_state(state)
    assert not check.passed and not check.residual("dilatancy").passed


def test_a_state_at_rest_is_no_mechanism(solved) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved["set12", "nonassociative"]
    state = collapse_state(result, wall)
    zero = np.zeros_like(state.opening_rate)
    rest = _tamper(state, velocities=np.zeros_like(state.velocities), opening_rate=zero, slip_rate=zero,
                   contact_state=("closed",) * state.n_points)
    check = verify_state(rest)
    assert [r.name for r in check.failed] == ["mechanism"]


def test_a_declared_contact_state_that_contradicts_the_rates_fails(solved) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved["set12", "nonassociative"]
    state = collapse_state(result, wall)
    k = state.contact_state.index("sliding")
    states = list(state.contact_state)
    states[k] = "closed"
    check = verify_state(_tamper(state, contact_state=tuple(states)))
    assert [r.name for r in check.failed] == ["contact_states"] and check.residual("contact_states").value == 1


# --------------------------------------------------------------------------- another program's file
def rocking_block(b: float = 0.3, h: float = 1.2, mu: float = 0.6, lam: float | None = None) -> dict[str, Any]:
    """One block ``b`` wide and ``h`` high on the ground, pushed in +x by its weight times lambda, rocking
    about its right toe: lambda = b/h (the moment of the weight about the toe, W b/2, against the push's,
    lambda W h/2). The whole weight W rests on the toe, whose shear holds the push (b/h <= mu). Rotation
    -1 about the toe (b, 0): the centroid moves by (h/2, b/2), the left corner opens at rate b."""
    W = b * h  # unit weight, unit thickness
    lam = b / h if lam is None else lam
    return {
        "format": "xcheck-masonry collapse state", "version": 1, "friction": "nonassociative",
        "load_factor": lam, "direction": "+x", "source": {"program": "a hand calculation"},
        "blocks": [{"vertices": [[0, 0], [b, 0], [b, h], [0, h]], "centroid": [b / 2, h / 2], "weight": W,
                    "dead": [0, -W, 0], "live": [W, 0, 0]}],
        "points": [{"blocks": [-1, 0], "position": [0, 0], "normal": [0, 1], "tangent": [1, 0], "mu": mu},
                   {"blocks": [-1, 0], "position": [b, 0], "normal": [0, 1], "tangent": [1, 0], "mu": mu}],
        "normal_forces": [0, W], "shear_forces": [0, -lam * W],
        "velocities": [[h / 2, b / 2, -1]],
        "opening_rates": [b, 0], "slip_rates": [0, 0], "contact_states": ["opening", "closed"],
    }


@pytest.mark.parametrize("friction", FRICTIONS)
def test_a_state_written_by_hand_verifies(friction: str, tmp_path: Path) -> None:
    doc = rocking_block()
    doc["friction"] = friction
    path = tmp_path / "rocking.json"
    path.write_text(json.dumps(doc, indent=2))
    check = verify_state(path)
    assert check.passed, check.worst.describe()
    assert check.load_factor == pytest.approx(0.25)


def test_the_hand_written_block_at_one_percent_more_fails(tmp_path: Path) -> None:
    b, h = 0.3, 1.2
    doc = rocking_block(lam=1.01 * b / h)
    check = verify_state(parse_state(json.dumps(doc)))
    assert not check.passed and check.worst.name in ("equilibrium", "power")


def test_the_hand_written_block_slides_before_it_rocks_when_friction_is_low() -> None:
    """mu = 0.2 < b/h = 0.25: the toe cannot hold the push."""
    check = verify_state(parse_state(json.dumps(rocking_block(mu=0.2))))
    assert [r.name for r in check.failed] == ["coulomb"]


def test_written_files_and_the_hand_written_one_match_the_schema(solved, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads(SCHEMA.read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    for friction in FRICTIONS:
        wall, result = solved["cut", friction]
        doc = json.loads(write_state(result, tmp_path / f"{friction}.json", wall=wall).read_text())
        assert [e.message for e in validator.iter_errors(doc)] == []
    assert [e.message for e in validator.iter_errors(rocking_block())] == []
    bad = rocking_block()
    bad["points"][0]["friction"] = 0.6
    assert list(validator.iter_errors(bad))


# --------------------------------------------------------------------------- malformed files
def _bad(mutate: Any) -> str:
    doc = copy.deepcopy(rocking_block())
    mutate(doc)
    return json.dumps(doc)


MALFORMED = [
    ("not json", "{\n  \"format\": \n", "(line 3, column 1): not JSON"),
    ("nan", json.dumps(rocking_block()).replace("0.25", "NaN", 1), "not strict JSON (NaN is not a JSON number)"),
    ("array", "[1, 2]", "the document must be an object"),
    ("format", _bad(lambda d: d.update(format="other")), "format must be 'xcheck-masonry collapse state'"),
    ("version", _bad(lambda d: d.update(version=2)), "version this reader reads version 1, the file is version 2"),
    ("missing", _bad(lambda d: d.pop("velocities")), "velocities is missing"),
    ("unknown key", _bad(lambda d: d["points"][1].update(friction=0.6)), "points[1].friction is not a key"),
    ("friction", _bad(lambda d: d.update(friction="coulomb")), "friction must be one of associative, nonassociative"),
    ("bool", _bad(lambda d: d.update(load_factor=True)), "load_factor must be a number, got True"),
    ("string", _bad(lambda d: d["blocks"][0].update(weight="1")), "blocks[0].weight must be a number"),
    ("huge", _bad(lambda d: d.update(load_factor=10**400)), "load_factor must be a finite number"),
    ("negative mu", _bad(lambda d: d["points"][0].update(mu=-0.1)), "points[0].mu must be at least 0"),
    ("vertices", _bad(lambda d: d["blocks"][0].update(vertices=[[0, 0], [1, 0]])),
     "blocks[0].vertices must hold at least 3"),
    ("normal", _bad(lambda d: d["points"][1].update(normal=[0, 2])), "points[1].normal must be a unit vector"),
    ("tangent", _bad(lambda d: d["points"][1].update(tangent=[0, 1])),
     "points[1].tangent must be a unit vector orthogonal"),
    ("block number", _bad(lambda d: d["points"][0].update(blocks=[-1, 1])),
     "points[0].blocks must be two block numbers"),
    ("itself", _bad(lambda d: d["points"][0].update(blocks=[0, 0])), "points[0].blocks joins block 0 to itself"),
    ("forces", _bad(lambda d: d["normal_forces"].pop()), "normal_forces must hold 2 numbers, holds 1"),
    ("velocity", _bad(lambda d: d["velocities"][0].pop()), "velocities[0] must hold 3 numbers"),
    ("blocks", _bad(lambda d: d.update(blocks=[])), "blocks must hold at least 1 entry"),
    ("state name", _bad(lambda d: d["contact_states"].__setitem__(0, "open")), "contact_states[0] must be one of"),
    ("direction", _bad(lambda d: d.update(direction="-x")), "direction is '-x' but the live loads push towards +x"),
    ("deep", "[" * 200_000 + "]" * 200_000, "nested too deeply"),
]


@pytest.mark.parametrize(("text", "expected"), [m[1:] for m in MALFORMED], ids=[m[0] for m in MALFORMED])
def test_a_malformed_file_is_one_line_naming_the_file_and_the_field(text: str, expected: str, tmp_path: Path) -> None:
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(micro.StateFileError) as info:
        read_state(path)
    message = str(info.value)
    assert message.startswith(f"state {path}") and "\n" not in message
    assert expected in message


def test_files_that_are_not_state_files_are_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    cases = {
        fifo: "cannot read (not a regular file: a named pipe)",
        tmp_path: "cannot read (not a regular file: a directory)",
        tmp_path / "missing.json": "cannot read (No such file or directory)",
    }
    binary = tmp_path / "binary.json"
    binary.write_bytes(b'{"format":\n "\xff\xfe"}')
    cases[binary] = "(line 2): not UTF-8 text (byte 0xff at offset 13)"
    utf16 = tmp_path / "utf16.json"
    utf16.write_text(json.dumps(rocking_block()), encoding="utf-16")
    cases[utf16] = "UTF-16 or UTF-32 text"
    big = tmp_path / "big.json"
    with open(big, "wb") as fh:  # sparse: no disk used
        fh.truncate(state_file.MAX_STATE_BYTES + 1)
    cases[big] = f"larger than {state_file.MAX_STATE_BYTES:,} bytes"
    for path, expected in cases.items():
        with pytest.raises(micro.StateFileError, match=None) as info:
            verify_state(path)
        assert str(info.value) == f"state {path}: {expected}" or (
            str(info.value).startswith(f"state {path}") and expected in str(info.value)), str(info.value)


def test_a_byte_order_mark_is_allowed(tmp_path: Path) -> None:
    path = tmp_path / "bom.json"
    path.write_bytes(b"\xef\xbb\xbf" + json.dumps(rocking_block()).encode())
    assert verify_state(path).passed


# --------------------------------------------------------------------------- writing
def test_a_state_that_cannot_be_written_leaves_no_file(solved, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:  # type: ignore[no-untyped-def]
    def half(path: Path, data: bytes) -> None:
        path.write_bytes(data[: len(data) // 2])
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(micro.files, "_write_new", half)
    wall, result = solved["set12", "associative"]
    target = tmp_path / "state.json"
    with pytest.raises(OSError) as info:
        write_state(result, target, wall=wall)
    assert info.value.filename == str(target)
    assert list(tmp_path.iterdir()) == []


def test_an_existing_file_is_replaced_whole(solved, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    target = tmp_path / "state.json"
    target.write_text("old")
    wall, result = solved["set12", "associative"]
    write_state(result, target, wall=wall)
    assert verify_state(target).passed and [p.name for p in tmp_path.iterdir()] == ["state.json"]


def test_write_state_refuses_what_it_cannot_write(solved, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    wall, result = solved["set12", "associative"]
    with pytest.raises(TypeError, match="needs its wall"):
        write_state(result, tmp_path / "x.json")
    with pytest.raises(TypeError, match="not with a CollapseStateData"):
        write_state(collapse_state(result, wall), tmp_path / "x.json", wall=wall)
    with pytest.raises(TypeError, match="LimitResult or a micro.NonAssociativeResult"):
        collapse_state(wall, wall)
    with pytest.raises(ValueError, match="not of this wall"):
        collapse_state(result, _wall("set13"))
    failed = micro.solve_nonassociative(wall, max_iterations=2, tuning=micro.Tuning(selection="vertex"),
                                        lowest=False)
    if not failed.ok:
        with pytest.raises(ValueError, match="no collapse state"):
            collapse_state(failed, wall)
    assert list(tmp_path.iterdir()) == []


def test_the_residuals_are_named_with_their_tolerances() -> None:
    check = verify_state(parse_state(json.dumps(rocking_block())))
    assert [r.name for r in check.residuals] == list(state_check.MEANINGS)
    assert check.residual("power").tolerance == state_check.POWER_TOL
    assert check.to_dict()["passed"] is True and check.to_dict()["worst"] in state_check.MEANINGS
    with pytest.raises(KeyError):
        check.residual("nonsense")
