"""The forged state files of issue 54: each was accepted by ``xcheck verify`` on main a21edb9 (exit 0, "a
genuine collapse state"; ``docs/research/2026-11-29-state-verify.md``), each now exits 1 (not a collapse
state) or 2 (a malformed file).

Every forgery is tried on a version-2 file as the suite writes it, on the same file as version 1 wrote it,
and where it means something on the version-1 file main a21edb9 wrote (``states/set12-v1.json``). A forger
may also delete what names the wall (the ``wall`` and the source's paper parameters): the forgeries that
change the blocks, the loads or the forces are still found; relabelling a genuine state of another wall
(Set 14's as Set 12, mu 0.5 as 0.75) then cannot be, as the last test records: without the wall the file's
structure is all there is to check.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import pytest
import state_forgeries as forge

import micro
from comparison.cli import main
from comparison.domain.wall import WallSpec

FIXTURE = Path(__file__).parent / "states" / "set12-v1.json"


def _write(wall: micro.BlockWall, spec: WallSpec, path: Path, solve: Any = None) -> dict[str, Any]:
    result = (solve or micro.solve_nonassociative)(wall)
    source = {"wall": None, "paper_parameters": spec.paper_parameters(), "first_course": "full",
              "head_joints": "frictional"}
    return json.loads(micro.write_state(result, path, wall=wall, source=source).read_text())


@pytest.fixture(scope="module")
def genuine(tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[str, Any]]:
    """Set 12 (and the states the relabelling forgeries start from) as the suite writes them."""
    folder = tmp_path_factory.mktemp("genuine")
    set12, set14, soft = (WallSpec.from_paper(t=1, m=m, rows=12, f=f) for m, f in ((1 / 3, 0.75), (1, 0.75),
                                                                                  (1 / 3, 0.5)))
    wall12 = set12.to_micro()
    keep = wall12.contact_kind != micro.geometry.HEAD
    columns = dataclasses.replace(wall12, **{k: getattr(wall12, k)[keep] for k in (
        "contact_a", "contact_b", "contact_kind", "normal", "px", "py", "mu")})
    return {
        "set12": _write(wall12, set12, folder / "set12.json"),
        "set14": _write(set14.to_micro(), set14, folder / "set14.json"),
        "soft": _write(soft.to_micro(), soft, folder / "soft.json"),
        "columns": _write(columns, set12, folder / "columns.json"),
    }


def _forged(name: str, states: dict[str, dict[str, Any]]) -> dict[str, Any] | str:
    s12 = states["set12"]
    return {
        "live loads x 1.03, lambda / 1.03": lambda: forge.live_scaled(s12),
        "a far block of 1e5 x 1e4, lambda 0.60": lambda: forge.far_block(s12, load_factor=0.60),
        "a far block of dead load 1e12, every force zero, lambda 0.01":
            lambda: forge.far_block(s12, load_factor=0.01, weight=1e12, zero_forces=True),
        "a vertex at x = 1e9 hiding a moment": lambda: forge.bogus_vertex(s12),
        "every force x 1e-308, lambda 0.05": lambda: forge.scaled_numbers(s12),
        "dead loads halved, weights unchanged": lambda: forge.dead_halved(s12),
        "Set 14's state labelled Set 12": lambda: forge.relabelled(states["set14"], s12),
        "mu 0.5 contacts labelled f 0.75": lambda: forge.friction_relabelled(states["soft"], 0.75),
        "head-joint points deleted": lambda: forge.relabelled(states["columns"], s12),
        "every contact force zero": lambda: forge.far_block(s12, load_factor=0.01, weight=1e12, zero_forces=True),
    }[name]()


#: Each forgery and its exit code now (2: refused as malformed, 1: not a collapse state).
FORGERIES = {
    "live loads x 1.03, lambda / 1.03": 1,
    "a far block of 1e5 x 1e4, lambda 0.60": 1,
    "a far block of dead load 1e12, every force zero, lambda 0.01": 1,
    "a vertex at x = 1e9 hiding a moment": 1,
    "every force x 1e-308, lambda 0.05": 2,
    "dead loads halved, weights unchanged": 1,
    "Set 14's state labelled Set 12": 1,
    "mu 0.5 contacts labelled f 0.75": 1,
    "head-joint points deleted": 1,
    "every contact force zero": 1,
}


def _verify(doc: dict[str, Any] | str, path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    code = main(["verify", str(path), "-q"])
    out, err = capsys.readouterr()
    return code, (out + err).strip()


@pytest.mark.parametrize("version", ["as written (version 2)", "as version 1 wrote it"])
@pytest.mark.parametrize("name", FORGERIES)
def test_each_forgery_is_refused(name: str, version: str, genuine: dict[str, dict[str, Any]], tmp_path: Path,
                                 capsys: pytest.CaptureFixture[str]) -> None:
    doc = _forged(name, genuine)
    assert isinstance(doc, dict)
    if version == "as version 1 wrote it":
        doc = forge.as_version_1(doc)
    code, line = _verify(doc, tmp_path / "forged.json", capsys)
    assert code == FORGERIES[name], line
    assert line.count("\n") == 0
    if code == 1:
        assert ": not a collapse state (" in line
    else:
        assert line.startswith(f"xcheck: error: state {tmp_path / 'forged.json'}")


def test_the_genuine_states_they_start_from_verify(genuine: dict[str, dict[str, Any]], tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """Set 12, Set 14 and Set 12 at f = 0.5 are genuine (the wall without head joints is not the wall its
    file names: it is forged by construction)."""
    for name in ("set12", "set14", "soft"):
        for doc in (genuine[name], forge.as_version_1(genuine[name])):
            code, line = _verify(doc, tmp_path / f"{name}.json", capsys)
            assert code == 0, line
            assert "a genuine collapse state of the wall it names" in line


@pytest.mark.parametrize("name", ["live loads x 1.03, lambda / 1.03", "dead loads halved, weights unchanged",
                                  "a far block of 1e5 x 1e4, lambda 0.60"])
def test_the_forgeries_of_the_file_main_wrote_are_refused(name: str, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    fixture = json.loads(FIXTURE.read_text())
    doc = _forged(name, {"set12": fixture})
    code, line = _verify(doc, tmp_path / "forged.json", capsys)
    assert code == 1 and ": not a collapse state (" in line


@pytest.mark.parametrize("version", [1, 2])
def test_a_rocking_blocks_toe_moved_inward_is_refused(version: int, tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """lambda 0.0833 for a block whose value is 0.25: the block rests on the ground from x = 0 to 0.3, and
    no contact point is at 0.3."""
    code, line = _verify(forge.toe_moved_inward(version=version), tmp_path / "toe.json", capsys)
    assert code == 1, line
    assert "touching_edges 1 > 0" in line and "no contact point at (0.3, 0)" in line


def test_a_duplicate_load_factor_key_is_refused(genuine: dict[str, dict[str, Any]], tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    code, line = _verify(forge.duplicate_key(genuine["set12"]), tmp_path / "twice.json", capsys)
    assert code == 2
    assert line == (f'xcheck: error: state {tmp_path / "twice.json"} (line 1): the key "load_factor" is given twice '
                    "in one object (readers differ on which copy they keep)")


#: Each forgery with the wall's name deleted (no ``wall``, no paper parameters): what the structure alone
#: still tells. A relabelled genuine state is then a genuine state of the structure in the file.
WITHOUT_THE_WALL = {
    "live loads x 1.03, lambda / 1.03": ("loads", 1),
    "a far block of 1e5 x 1e4, lambda 0.60": ("loads", 1),
    "a far block of dead load 1e12, every force zero, lambda 0.01": ("loads", 1),
    "a vertex at x = 1e9 hiding a moment": ("contact_geometry", 1),
    "dead loads halved, weights unchanged": ("loads", 1),
    "head-joint points deleted": ("touching_edges", 1),
    "Set 14's state labelled Set 12": (None, 0),
    "mu 0.5 contacts labelled f 0.75": (None, 0),
}


@pytest.mark.parametrize("name", WITHOUT_THE_WALL)
def test_without_the_wall_the_structure_alone_is_checked(name: str, genuine: dict[str, dict[str, Any]],
                                                         tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    doc = _forged(name, genuine)
    assert isinstance(doc, dict)
    doc.pop("wall")
    doc["source"] = {"program": "someone else"}
    residual, expected = WITHOUT_THE_WALL[name]
    code, line = _verify(doc, tmp_path / "forged.json", capsys)
    assert code == expected, line
    if residual is not None:
        assert f"): {residual} " in line
    else:
        assert "a genuine collapse state of the structure in the file, which names no wall" in line


def test_the_far_block_alone_does_not_set_the_scale(genuine: dict[str, dict[str, Any]], tmp_path: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    """With its loads made consistent (its live load its weight, at a lambda where it slides), the far block
    still sets no scale: Set 12's own blocks are out of equilibrium at lambda 0.60 (by 0.09 of their weight),
    and their group's power balance is off by 15 %, while the far block is a group of its own in balance."""
    doc = forge.far_block(genuine["set12"], load_factor=0.60, mu=0.60)
    doc.pop("wall")
    doc["source"] = {}
    assert doc["blocks"][-1]["live"] == [doc["blocks"][-1]["weight"], 0.0, 0.0]
    path = tmp_path / "far.json"
    path.write_text(json.dumps(doc))
    assert main(["verify", str(path), "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    failed = {r["name"]: r for r in out["residuals"] if not r["passed"]}
    assert set(failed) == {"equilibrium", "power"}
    assert failed["power"]["where"] == "groups[0]" and failed["power"]["value"] == pytest.approx(0.149, abs=0.01)
    assert failed["equilibrium"]["value"] == pytest.approx(0.0911, abs=0.01)
