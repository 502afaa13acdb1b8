"""A sweep over walls of cut ends whose top course ends with a sliver: the table and the page tell the local
mechanism apart, compare the macro model with the wall as built and give the held wall's value beside it.

Grid: t = 1, 3/2; m = 1/3, 1/2; 8 rows; f = 0.65; ``ends = "cut"``. (t, m) = (1, 1/3) and (3/2, 1/2) end
their top course with a piece 1/2 and 1/3 wide that tips over alone (non-associative: at lambda = width);
the other two do not.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from comparison.cli import main
from comparison.sweep import read_table
from comparison.sweep.wall_comparisons import walls

GRID = """name = "local"

[axes]
t = [1.0, 1.5]
m = ["1/3", "1/2"]
rows = 8
f = 0.65

[bond]
ends = "cut"

[[method]]
kind = "macro"

[[method]]
kind = "micro-assoc"

[[method]]
kind = "micro-nonassoc"
"""
#: (t, m) -> the width of the top course's cut end piece, for the walls that have a local mechanism.
LOCAL = {(1.0, 1 / 3): 0.5, (1.5, 0.5): 1 / 3}


@pytest.fixture(scope="module")
def swept(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[dict[str, str]]]:
    tmp = tmp_path_factory.mktemp("local")
    grid = tmp / "local.toml"
    grid.write_text(GRID)
    out = tmp / "out"
    code = main(["sweep", str(grid), "--out", str(out), "--cache", str(tmp / "cache"), "--quiet", "--workers", "1"])
    assert code == 0
    return out, read_table(out / "local.csv")


def _key(row: dict[str, str]) -> tuple[float, float]:
    return float(row["t"]), round(float(row["m"]), 12)


def test_table_names_the_local_mechanism_and_the_held_walls_value(swept) -> None:
    _, rows = swept
    micro_rows = [r for r in rows if r["kind"].startswith("micro")]
    assert len(micro_rows) == 8
    for r in micro_rows:
        whole = _key(r) == (1.0, 0.5)  # 8 half blocks; the other three walls are cut
        assert r["ends"] == "cut" and (float(r["half_blocks"]) == round(float(r["half_blocks"]))) == whole
        lam = float(r["load_factor"])
        width = next((w for (t, m), w in LOCAL.items() if _key(r) == (t, round(m, 12))), None)
        if width is None:
            assert r["local_mechanism"] == "" and r["held_load_factor"] == ""
            continue
        assert r["local_mechanism"].startswith("the cut end piece of course 8 (right end")
        assert float(r["held_load_factor"]) > lam + 0.01
        if r["kind"] == "micro-nonassoc":
            assert lam == pytest.approx(width, rel=1e-7)


def test_page_compares_the_wall_as_built_and_lists_local_walls_apart(swept) -> None:
    out, rows = swept
    ws = walls(rows)
    built = {(_key(r), r["kind"]): float(r["load_factor"]) for r in rows if r["kind"].startswith("micro")}
    for w in ws:
        key = (w.t, round(w.m, 12))
        assert w.nonassoc == built[(key, "micro-nonassoc")] and w.assoc == built[(key, "micro-assoc")]
        assert bool(w.local) == (key in {(t, round(m, 12)) for t, m in LOCAL})
        assert w.cut == (key != (1.0, 0.5)) and w.ends == "cut"
    text = (out / "local.md").read_text()
    section = text.split("## Local mechanisms", 1)[1].split("\n## ", 1)[0]
    assert section.count("tips over alone |") == 4  # two walls, two micro methods
    assert "3 walls of a length that is not a whole number of half blocks**: their courses end in cut pieces" in text
    assert "--ends cut --full --plot" in text
