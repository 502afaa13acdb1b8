"""The collapse state file: written, read back bit for bit, and verified against its wall and its own data.

A genuine state passes every residual; a state tampered with (lambda raised by 1 %, a force's sign
flipped, one block's velocity scaled) fails, naming the residual; a state written by hand as another
program would (one block rocking on its base, lambda = b/h in closed form; two blocks side by side) verifies
in both versions of the format; a held wall's state names its bodies; every malformed file is refused with
one line naming the file, the field and its line. The forgeries of issue 54: ``test_state_forgeries.py``.
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
from micro.state import file as state_file
from micro.state import verify as state_check

SCHEMA = Path(__file__).parents[2] / "docs" / "schemas" / "state.schema.json"
#: The small walls: Table 7's Sets 12-14 and a wall 5.33 half blocks long (L = 8 block heights, l = 3)
#: whose courses end with cut blocks (``ends="cut"``) or with closers (the default).
WALLS = ("set12", "set13", "set14", "cut", "closers")
FRICTIONS = ("associative", "nonassociative")


def _wall(name: str) -> micro.BlockWall:
    if name in ("cut", "closers"):
        return WallSpec.from_paper(t=1, m=1 / 3, rows=8, f=0.65, ends=name).to_micro()
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
    # relative to the point's own load: the larger of its two blocks' (block by block, not the file's largest)
    blocks = [b for b in (state.point_a[k], state.point_b[k]) if b >= 0]
    own = max(max(state.weight[b], np.hypot(*state.dead[b, :2]), state.load_factor * np.hypot(*state.live[b, :2]))
              for b in blocks)
    assert check.residual("no_tension").value == pytest.approx(n[k] * -1 / own)
    assert check.residual("no_tension").where == f"points[{k}]"
    assert check.worst.name == "equilibrium"  # twice the force unbalanced, over a block's own load


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
def rocking_block(b: float = 0.3, h: float = 1.2, mu: float = 0.6, lam: float | None = None,
                  version: int = 1) -> dict[str, Any]:
    """One block ``b`` wide and ``h`` high on the ground, pushed in +x by its weight times lambda, rocking
    about its right toe: lambda = b/h (the moment of the weight about the toe, W b/2, against the push's,
    lambda W h/2). The whole weight W rests on the toe, whose shear holds the push (b/h <= mu). Rotation
    -1 about the toe (b, 0): the centroid moves by (h/2, b/2), the left corner opens at rate b. Version 2
    names its unit weight (1), its member block (0) and thickness (1)."""
    W = b * h  # unit weight, unit thickness
    lam = b / h if lam is None else lam
    doc = {
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
    if version == 2:
        doc.update(version=2, unit_weight=1.0)
        doc["blocks"][0].update(members=[0], thickness=1.0)
    return doc


def two_blocks(mu: float = 0.75, lam: float = 0.5) -> dict[str, Any]:
    """Two blocks 1 wide and 2 high side by side on the ground (version 2, unit weight and thickness), pushed
    in +x: both rock about their right toes, the head joint between them closed and slipping. Each block's
    weight W = 2 rests on its toe; lambda = b/h = 1/2, the head joint carrying no force (the lower end of
    the mechanism's band [1/2, 8/13] of ``docs/micro/global-search.md``). Rotation -1 about each toe: the
    centroids move by (1, 1/2); at the head joint (x = 1) the right block's left face moves up by 1 relative
    to the left block's right face, a slip rate of -1 along the tangent (0, -1); no opening."""
    W = 2.0
    blocks = [{"members": [k], "vertices": [[k, 0], [k + 1, 0], [k + 1, 2], [k, 2]], "centroid": [k + 0.5, 1],
               "thickness": 1.0, "weight": W, "dead": [0, -W, 0], "live": [W, 0, 0]} for k in (0, 1)]
    ground = [{"blocks": [-1, k], "position": [x, 0], "normal": [0, 1], "tangent": [1, 0], "mu": mu}
              for k in (0, 1) for x in (k, k + 1)]
    head = [{"blocks": [0, 1], "position": [1, y], "normal": [1, 0], "tangent": [0, -1], "mu": mu} for y in (0, 2)]
    # the points: ground 0 at (0, 0) and its toe (1, 0), ground 1 at (1, 0) and its toe (2, 0), head (1, 0), (1, 2)
    return {
        "format": "xcheck-masonry collapse state", "version": 2, "friction": "nonassociative", "load_factor": lam,
        "direction": "+x", "unit_weight": 1.0, "source": {"program": "a hand calculation"}, "blocks": blocks,
        "points": ground + head,
        "normal_forces": [0, W, 0, W, 0, 0], "shear_forces": [0, -lam * W, 0, -lam * W, 0, 0],
        "velocities": [[1, 0.5, -1], [1, 0.5, -1]],
        "opening_rates": [1, 0, 1, 0, 0, 0], "slip_rates": [0, 0, 0, 0, -1, -1],
        "contact_states": ["opening", "closed", "opening", "closed", "sliding", "sliding"],
    }


@pytest.mark.parametrize("version", [1, 2])
@pytest.mark.parametrize("friction", FRICTIONS)
def test_a_state_written_by_hand_verifies(friction: str, version: int, tmp_path: Path) -> None:
    doc = rocking_block(version=version)
    doc["friction"] = friction
    path = tmp_path / "rocking.json"
    path.write_text(json.dumps(doc, indent=2))
    check = verify_state(path)
    assert check.passed, check.worst.describe()
    assert check.load_factor == pytest.approx(0.25)
    assert check.wall == "" and check.unchecked[0].startswith("wall: the file names no wall")
    assert len(check.unchecked) == (3 if version == 1 else 1)  # version 1: the loads' areas, the held blocks


def test_two_blocks_written_by_hand_verify_and_every_part_of_them_is_checked() -> None:
    doc = two_blocks()
    check = verify_state(parse_state(json.dumps(doc)))
    assert check.passed, check.worst.describe()
    assert [r.name for r in check.residuals][:3] == ["contact_geometry", "touching_edges", "loads"]
    # a head-joint point deleted: the two blocks touch from (1, 0) to (1, 2), one end has no point
    cut = copy.deepcopy(doc)
    for key in ("normal_forces", "shear_forces", "opening_rates", "slip_rates", "contact_states"):
        cut[key] = cut[key][:5]
    cut["points"] = cut["points"][:5]
    check = verify_state(parse_state(json.dumps(cut)))
    assert [r.name for r in check.failed] == ["touching_edges"]
    assert "no contact point at (1, 2)" in check.residual("touching_edges").where
    # a block 1 % heavier than its outline: the loads
    heavy = copy.deepcopy(doc)
    heavy["blocks"][1]["weight"] *= 1.01
    check = verify_state(parse_state(json.dumps(heavy)))
    assert check.residual("loads").where == "blocks[1]" and not check.residual("loads").passed
    # a point off the outline: moved into the block's face
    off = copy.deepcopy(doc)
    off["points"][5]["position"] = [1, 1.5]
    assert not verify_state(parse_state(json.dumps(off))).residual("touching_edges").passed
    # a normal that points out of the block above instead of into it
    flipped = copy.deepcopy(doc)
    flipped["points"][0]["normal"], flipped["points"][0]["tangent"] = [0, -1], [-1, 0]
    assert verify_state(parse_state(json.dumps(flipped))).residual("contact_geometry").value == np.inf


def test_a_state_of_two_blocks_written_by_hand_exits_0(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from comparison.cli import main

    path = tmp_path / "two.json"
    path.write_text(json.dumps(two_blocks(), indent=2))
    assert main(["verify", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{path}: a genuine collapse state of the structure in the file, which names no wall "
                          "(non-associative friction, lambda = 0.500000 (+x), 2 blocks, 6 contact points)")
    assert "  not checked: wall: the file names no wall" in out


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
    ("version", _bad(lambda d: d.update(version=3)), "version this reader reads versions 1, 2, the file is version 3"),
    ("version 2 keys", _bad(lambda d: d.update(version=2)), "unit_weight is missing"),
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
    assert [r.name for r in check.residuals] == [m for m in state_check.MEANINGS if m != "wall"]  # no wall named
    assert check.residual("power").tolerance == state_check.POWER_TOL
    assert check.to_dict()["passed"] is True and check.to_dict()["worst"] in state_check.MEANINGS
    with pytest.raises(KeyError):
        check.residual("nonsense")


# --------------------------------------------------------------------------- held walls, version 2's checks
def _sliver() -> micro.BlockWall:
    """Two courses 1.55 blocks long: the top course ends in a 0.05-wide piece (block 4) that tips alone."""
    return WallSpec.from_paper(t=40 / 31, m=1, rows=2, f=0.6, ends="cut").to_micro()


@pytest.mark.parametrize("friction", FRICTIONS)
def test_a_held_wall_names_its_bodies_and_verifies_against_the_wall_rebuilt(friction: str, tmp_path: Path) -> None:
    """The piece held to the block below: one body of two members, its outline their union (six corners),
    its weight theirs, its dead load's moment the piece's about the host's centroid; the file says which
    block is held, and the wall built again from it is the same, body by body."""
    wall = _sliver()
    held = micro.hold_blocks(wall, [4])
    solve = micro.solve_associative if friction == "associative" else micro.solve_nonassociative
    path = write_state(solve(held.wall), tmp_path / "held.json", wall=held)
    doc = json.loads(path.read_text())
    assert doc["wall"]["held"] == [4] and len(doc["blocks"]) == wall.n_blocks - 1
    body = next(b for b in doc["blocks"] if len(b["members"]) > 1)
    assert body["members"] == [1, 4]  # the host first
    assert body["vertices"] == [[1.0, 0.0], [1.55, 0.0], [1.55, 2.0], [1.5, 2.0], [1.5, 1.0], [1.0, 1.0]]
    assert body["weight"] == pytest.approx(0.55 + 0.05)
    assert body["dead"][2] == pytest.approx(-0.05 * (1.525 - 1.275))  # the piece's weight, 0.25 right of the host's
    check = verify_state(path)
    assert check.passed, check.worst.describe()
    assert check.residual("wall").value == 0.0 and "built again" in check.wall
    # the same state without its held block named: the wall has one more body than the file
    doc["wall"]["held"] = []
    check = verify_state(parse_state(json.dumps(doc)))
    assert check.residual("wall").value == np.inf and "5" in check.residual("wall").where


def test_a_block_held_to_the_ground_is_part_of_it(tmp_path: Path) -> None:
    """A block of the bottom course held: fixed, part of the ground; the block above touches it, so its
    points are ground points on the fixed block's outline."""
    wall = _sliver()
    held = micro.hold_blocks(wall, [1])  # the bottom course's end piece, 0.55 wide
    result = micro.solve_nonassociative(held.wall)
    doc = json.loads(write_state(result, tmp_path / "fixed.json", wall=held).read_text())
    assert doc["fixed"] == [{"members": [1], "vertices": [[1.0, 0.0], [1.55, 0.0], [1.55, 1.0], [1.0, 1.0]]}]
    check = verify_state(parse_state(json.dumps(doc)))
    assert check.passed, check.worst.describe()
    doc["fixed"] = []  # without it, the ground's points lie at two heights: its outline is not known
    check = verify_state(parse_state(json.dumps(doc)))
    assert any(u.startswith("the ground: its contact points lie at several heights") for u in check.unchecked)
    assert not check.residual("wall").passed  # the wall rebuilt has the block fixed


def test_a_multi_storey_wall_writes_its_floor_loads_and_checks_them() -> None:
    wall = three_storey_wall()
    state = collapse_state(micro.solve_associative(wall), wall)
    doc = state_file.state_document(state)
    floors = [f for b in doc["blocks"] for f in b.get("floor", [])]
    assert floors and all(q > 0 for _, _, q in floors)
    heavier = copy.deepcopy(doc)
    b = next(b for b in heavier["blocks"] if "floor" in b)
    b["floor"][0][2] *= 2  # a floor load doubled, the dead load left as it was
    check = verify_state(parse_state(json.dumps(heavier)))
    assert not check.residual("loads").passed and not check.residual("wall").passed


def test_a_key_twice_is_refused_naming_it_and_its_line(tmp_path: Path) -> None:
    text = json.dumps(rocking_block(), indent=1)
    text = text.replace('"load_factor": 0.25', '"load_factor": 0.2,\n "load_factor": 0.25')
    path = tmp_path / "twice.json"
    path.write_text(text)
    line = text.splitlines().index(' "load_factor": 0.25,') + 1
    with pytest.raises(micro.StateFileError) as info:
        read_state(path)
    assert str(info.value) == (f'state {path} (line {line}): the key "load_factor" is given twice in one object '
                               "(readers differ on which copy they keep)")


def test_a_field_is_named_with_its_line(solved, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    """The writer puts one block per line: a bad block is named with the line a person opens the file at."""
    wall, result = solved["set12", "associative"]
    path = write_state(result, tmp_path / "s.json", wall=wall)
    lines = path.read_text().splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith('"blocks"')) + 1 + 7  # blocks[7]
    lines[k] = lines[k].replace('"weight": 3.0', '"weight": "3"')
    path.write_text("\n".join(lines))
    with pytest.raises(micro.StateFileError) as info:
        read_state(path)
    assert str(info.value).startswith(f"state {path} (line {k + 1}): blocks[7].weight must be a number")


@pytest.mark.parametrize(("mutate", "expected"), [
    (lambda d: d["blocks"][0].update(weight=3e-308), "blocks[0].weight must be at least 1e-100"),
    (lambda d: d.update(unit_weight=1e-200), "unit_weight must be at least 1e-100"),
    (lambda d: d.update(load_factor=1e200), "load_factor must be a finite number of at most 1e+100"),
    (lambda d: d["blocks"][0].update(vertices=[[0, 0], [1e-120, 0], [1e-120, 1e-120], [0, 1e-120]]),
     "blocks[0].vertices span 1.41421e-120: outside [1e-100, 1e+100]"),
    (lambda d: d["blocks"][0].update(vertices=[[0, 0], [1, 0], [2, 0]]), "blocks[0].vertices enclose no area"),
    (lambda d: d.update(velocities=[[1e-200, 0, 0]]), "velocities are all below 1e-100"),
    (lambda d: d["blocks"][0].pop("thickness"), "blocks[0] must give either thickness or parts"),
    (lambda d: d["blocks"][0].update(members=[0, 0]), "blocks[0].members must be distinct numbers of blocks"),
])
def test_numbers_outside_the_range_the_check_computes_in_are_refused(mutate: Any, expected: str) -> None:
    doc = rocking_block(version=2)
    mutate(doc)
    with pytest.raises(micro.StateFileError) as info:
        parse_state(json.dumps(doc))
    assert expected in str(info.value)


def test_a_version_1_state_cannot_be_written_as_version_2(tmp_path: Path) -> None:
    state = read_state(Path(__file__).parent / "states" / "set12-v1.json")
    assert state.version == 1 and state.wall is None and state.members == ()
    with pytest.raises(ValueError, match="a state of version 1 cannot be written as version 2"):
        write_state(state, tmp_path / "x.json")
    assert list(tmp_path.iterdir()) == []
