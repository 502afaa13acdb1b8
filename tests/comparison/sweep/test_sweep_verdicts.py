"""A sweep's page counts its walls by verdict and proof, as ``xcheck compare`` gives them, and a wall above
the grid's block limit still gets the associative LP and a verdict by its bound."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from comparison.cli import main
from comparison.domain.verdict import compare
from comparison.domain.wall import WallSpec
from comparison.sweep import read_table

#: Set 12 (12 rows, 54 blocks: not refuted) and the same t, m, f with 24 rows (204 blocks, above the grid's
#: limit: no non-associative solve; its macro λ 0.6270 lies above the associative 0.6143).
GRID = """
name = "verdicts"
[axes]
t = 1
m = "1/3"
rows = [12, 24]
f = 0.75
[limits]
max_blocks = 100
[[method]]
kind = "macro"
[[method]]
kind = "micro-assoc"
[[method]]
kind = "micro-nonassoc"
"""


def test_the_page_counts_walls_by_verdict_as_compare_gives_them(tmp_path: Path) -> None:
    grid = tmp_path / "verdicts.toml"
    grid.write_text(GRID)
    out = tmp_path / "out"
    assert main(["sweep", str(grid), "--out", str(out), "--cache", str(tmp_path / "cache"), "--quiet",
                 "--workers", "1"]) == 0
    status = {(r["kind"], r["rows"]): r["status"] for r in read_table(out / "verdicts.csv")}
    assert status[("micro-assoc", "24")] == "optimal" and status[("micro-nonassoc", "24")] == "not_run"
    text = (out / "verdicts.md").read_text()
    assert ("| macro column | unsafe, by the associative bound | unsafe, by a certified state | not refuted "
            "| no verdict |") in text
    assert "| macro | 1 | 0 | 1 | 0 |" in text
    worst = json.loads(json.dumps(_numbers(out)))
    for wall in worst:  # the same verdict as compare's on each wall
        c = compare(WallSpec.from_paper(t=1, m=1 / 3, rows=wall["rows"], f=0.75))
        assert (wall["verdict"], wall["proof"]) == (c.verdict, c.proof)


def _numbers(out: Path) -> list[dict[str, object]]:
    from comparison.sweep.page import render

    page = render(read_table(out / "verdicts.csv"), out, title="t", intro="", prefix="again", source="verdicts.csv")
    walls = page.numbers["worst"]["macro"]
    assert page.numbers["columns"]["macro"]["verdicts"] == {
        "unsafe, by the associative bound": 1, "unsafe, by a certified state": 0, "not refuted": 1, "no verdict": 0}
    return walls


@pytest.mark.parametrize(("quoted", "label"), [("lowest certified", "unsafe, by a certified state"),
                                               ("iterated", "no verdict"), ("", "no verdict")])
def test_a_value_above_the_quoted_one_is_proven_only_by_a_certified_state(quoted: str, label: str) -> None:
    """The iterated LP's value (or a table too old to say) is not known to be a certified state: a macro value
    above it is not proven unsafe, and without a converged certified value nothing else proves either way."""
    from comparison.sweep.wall_comparisons import walls

    base = {"t": "1", "m": "0.5", "rows": "12", "f": "0.75", "p": "0", "storeys": "1", "first_course": "full",
            "head_joints": "frictional", "blocks": "78", "quoted": "", "message": ""}
    rows = [{**base, "method": "macro", "kind": "macro", "load_factor": "0.4914", "status": "optimal"},
            {**base, "method": "micro-assoc", "kind": "micro-assoc", "load_factor": "0.5564", "status": "optimal"},
            {**base, "method": "micro-nonassoc", "kind": "micro-nonassoc", "load_factor": "0.4895",
             "status": "converged", "quoted": quoted}]
    (w,) = walls(rows)
    assert w.verdict_label("macro") == label


def test_a_worst_wall_s_plot_command_draws_that_wall(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """The worst-walls table gives, per wall, the ``xcheck compare --plot`` command of exactly that wall:
    run, it draws the figure and compares the same wall (same macro λ)."""
    from comparison.sweep.page import plot_command
    from comparison.sweep.wall_comparisons import Wall

    w = Wall(t=1.0, m=1 / 3, rows=12, f=0.75, p=0.2, storeys=2, first_course="half", head_joints="frictional",
             blocks=0, macro={"macro": 0.5}, assoc=float("nan"), nonassoc=float("nan"))
    command = plot_command(w, "worst-1.png")
    assert command == ("xcheck compare --t 1 --m 1/3 --rows 12 --f 0.75 --p 0.2 --storeys 2 --first-course half "
                       "--full --plot worst-1.png")  # --full: the non-associative state, whose value is compared
    monkeypatch.chdir(tmp_path)
    assert main([*command.split()[1:], "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    expected = compare(WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75, p=0.2, storeys=2), first_course="half")
    assert doc["macro_load_factor"] == pytest.approx(expected.macro_load_factor, rel=1e-12)
    assert doc["plot"] == "worst-1.png" and (tmp_path / "worst-1.png").stat().st_size > 0


def test_where_needed_runs_the_dry_friction_method_above_the_limit_only_where_the_verdict_needs_it(
        tmp_path: Path) -> None:
    """Above ``max_blocks``, ``where_needed`` runs the non-associative method on the walls whose macro λ is not
    above the associative bound (Set 12, 54 blocks: macro 0.6481 against 0.7120), not on those the bound
    settles (24 rows, 204 blocks: 0.6270 against 0.6143)."""
    grid = tmp_path / "needed.toml"
    grid.write_text(GRID.replace('name = "verdicts"', 'name = "needed"')
                    .replace("max_blocks = 100", "max_blocks = 50\nwhere_needed = true"))
    out = tmp_path / "out"
    assert main(["sweep", str(grid), "--out", str(out), "--cache", str(tmp_path / "cache"), "--quiet",
                 "--workers", "1"]) == 0
    rows = {(r["kind"], r["rows"]): r for r in read_table(out / "needed.csv")}
    needed, settled = rows[("micro-nonassoc", "12")], rows[("micro-nonassoc", "24")]
    assert needed["status"] == "converged" and float(needed["load_factor"]) == pytest.approx(0.6911, abs=1e-4)
    assert settled["status"] == "not_run" and "the associative bound settles the verdict" in settled["message"]
    assert json.loads((out / "needed.json").read_text())["grid"]["where_needed"] is True
