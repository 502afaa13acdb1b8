"""README.md's findings ("What the comparison shows"), generated from a report's data.

The block between :data:`BEGIN` and :data:`END` in ``README.md`` is :func:`findings` of the committed
report: ``reports/report.json``, and for the two studies the report reads rather than recomputes, its
committed tables ``sweeps/errormap.csv`` and ``lowest.csv`` (through the report's own readers). Every
figure of the block is computed here from the field it names; the words around them are fixed. A
sentence also states facts the data must bear out (a single wall below, a set whose verdict depends on
the head joints, ...): when the data no longer does, :func:`findings` raises :class:`StaleProse` naming
the sentence, to be reworded here, rather than print a false one. After the report is regenerated::

    python -m comparison.report.readme            # rewrites the block of ./README.md from ./reports
    python -m comparison.report.readme --check    # exit 1 when the block differs from the data

``tests/docs/test_readme_figures.py`` checks that the README's block equals :func:`findings` of
``reports/``.

How a figure is printed: a value (``0.583``, ``+9.6 %``, a range ``2.8-26.5 %``) is the data rounded to
the printed decimals; a bound (``within 7.4 %``, ``up to 25.1 %``) is the value as the report prints it
(one decimal), never below the data; a count is exact.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import textwrap
import tomllib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

#: The comment lines around the generated block in README.md.
BEGIN = "<!-- findings: generated from reports/ by `python -m comparison.report.readme`; do not edit by hand -->"
END = "<!-- end of the generated findings -->"
#: Table 5 prints λ to three decimals: a set reproduces it "within its rounding" when ours is within half a unit.
TABLE5_ROUNDING = 5e-4
#: Relative differences below this are equal load factors (the LPs are solved to about 1e-6).
SAME = 1e-6
#: Where the README wraps its prose.
WIDTH = 105
#: The grid of the error map (its ``max_blocks`` is quoted), relative to the repository.
ERRORMAP_GRID = Path("examples") / "sweeps" / "errormap.toml"
WORDS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine")


class StaleProse(ValueError):
    """The data no longer bears out a sentence of the block: reword the sentence in this module."""


def _require(ok: bool, sentence: str, why: str) -> None:
    if not ok:
        raise StaleProse(f"README findings, {sentence!r}: {why}")


def _shown(value: Any) -> float:
    """A cell of report.json as a number (percentages are strings such as ``"+24.4"``); NaN for text."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def _num(x: float, decimals: int) -> str:
    """``x`` to ``decimals`` places, the minus typographic."""
    return f"{x:.{decimals}f}".replace("-", "−")


def _bound(x: float, decimals: int = 1) -> str:
    """An upper bound of ``x`` printed to ``decimals`` places: rounded up."""
    scale = 10**decimals
    return _num(math.ceil(round(x * scale, 9)) / scale, decimals)


def _range(lo: float, hi: float, decimals: int = 1) -> str:
    return f"{_num(lo, decimals)}-{_num(hi, decimals)}"


def _count(n: int) -> str:
    return WORDS[n] if 0 <= n < len(WORDS) else f"{n:,}"


def _sets(names: Sequence[str]) -> str:
    """``Sets 11, 12 and 14`` from ``["Set 11", "Set 12", "Set 14"]``."""
    numbers = [n.removeprefix("Set ") for n in names]
    if len(numbers) == 1:
        return f"Set {numbers[0]}"
    return f"Sets {', '.join(numbers[:-1])} and {numbers[-1]}"


class Data:
    """The report's data: ``report.json``'s tables and the committed tables beside it."""

    def __init__(self, reports: Path, root: Path) -> None:
        self.reports, self.root = reports, root
        self.json: dict[str, Any] = json.loads((reports / "report.json").read_text(encoding="utf-8"))

    def table(self, name: str) -> list[dict[str, Any]]:
        tables = self.json["tables"]
        _require(name in tables, name, f"report.json has no table {name!r}")
        return list(tables[name])


def _paper(d: Data) -> str:
    rows = d.table("table5")
    off = sum(abs(r["λ paper"] - r["λ ours (Eq. 10)"]) > TABLE5_ROUNDING for r in rows)
    return (
        f"**The macro model reproduces the paper**: Table 5 within its rounding but for {_count(off)} sets whose "
        "gaps are measured and explained (Set 5: most likely a transcription error; Table 9: most likely computed "
        "with m = 1/2, not Table 6's 1/3); Tables 7 and 9 likewise."
    )


def _validation(d: Data) -> str:
    rows = d.table("table7")
    cases = {r["row"]: r for r in d.table("all_cases")}
    sets = [r["row"] for r in rows]
    o = {cases[s]["o"] for s in sets}
    _require(len(o) == 1, "Table 7, N rows", f"Table 7's walls have several numbers of rows: {sorted(o)}")
    macro = max(abs(_shown(r["Δ % macro vs micro-nonassoc (lowest certified)"])) for r in rows)
    orduna = [abs(_shown(r["Δ % vs Orduña (micro-nonassoc)"])) for r in rows]
    iterated = [abs(round(100 * (cases[r["row"]]["micro-nonassoc iterated LP λ"] / r["Orduña micro"] - 1), 1))
                for r in rows]
    return (
        f"**On the paper's validation walls (Table 7, {o.pop():g} rows)** the macro λ lies within "
        f"{_bound(macro)} % of the micro values, and the lowest certified non-associative state comes within "
        f"{_range(min(orduna), max(orduna))} % of Orduña's micro values (the iterated LP's own fixed point "
        f"within {_range(min(iterated), max(iterated))} %)."
    )


def _beyond(d: Data) -> str:
    validation = {r["row"] for r in d.table("table7")}
    name = "Δ % macro vs micro (non-assoc., else assoc.)"
    built = [r for r in d.table("all_cases") if r["row"] not in validation and math.isfinite(_shown(r[name]))]
    above = [_shown(r[name]) for r in built if _shown(r[name]) > 0]
    below = [r for r in built if _shown(r[name]) <= 0]
    _require(len(below) == 1, "below it only", f"walls beyond Table 7 with the macro λ below: {len(below)}")
    b = below[0]
    return (
        "**Beyond them the macro model is on the unsafe side.** The rigid-block wall loses strength as its "
        "blocks get smaller; the macro model hardly does. "
        f"On {len(above)} of the {len(built)} other walls the micro model can build "
        f"({min(r['o'] for r in built):g}-{max(r['o'] for r in built):g} rows) the macro λ exceeds the micro λ "
        f"by {_range(min(above), max(above))} % (below it only {b['row']}, m = {_shown(b['m']):g}: "
        f"{_num(_shown(b[name]), 1)} %):"
    )


def _rows_table(d: Data) -> list[str]:
    """The table of the Table 5 wall by rows (report.json's sensitivity to the rows)."""
    rows = [r for r in d.table("sensitivity") if r["parameter"] == "rows"]
    macro = [r["macro λ"] for r in rows]
    micro = [r["micro-nonassoc (lowest certified) λ"] for r in rows]
    excess = []
    for a, b in zip(macro, micro, strict=True):
        e = 100 * (a / b - 1)
        excess.append("0 %" if abs(e) < 0.05 else f"{e:+.1f} %".replace("-", "−"))
    return [
        f"| rows of the Table 5 wall | {' | '.join(r['value'] for r in rows)} |",
        "|---" + "|--:" * len(rows) + "|",
        f"| macro λ | {' | '.join(f'{x:.3f}' for x in macro)} |",
        f"| micro λ, lowest certified | {' | '.join(f'{x:.3f}' for x in micro)} |",
        f"| macro above micro | {' | '.join(excess)} |",
    ]


def _robustness(d: Data) -> str:
    rows = d.table("robustness")
    deltas = [k for k in rows[0] if k.startswith("Δ % macro, ")]
    base = [r for r in rows if r["row"].startswith("base wall")]

    def every(r: dict[str, Any]) -> bool:
        n, of = r["macro above micro in"].split(" of ")
        return n == of != "0"

    first = min(int(r["row"].rsplit("= ", 1)[1]) for r in base if every(r))
    beyond = [r for r in base if int(r["row"].rsplit("= ", 1)[1]) >= first]
    _require(all(every(r) for r in beyond), "From N rows on ... under every bond", "not on every wall from there")
    above = [_shown(r[k]) for r in beyond for k in deltas if math.isfinite(_shown(r[k]))]
    sets = {r["row"]: r for r in rows if r["row"].startswith("Set ")}
    below = sorted((s for s, r in sets.items() if r["macro above micro in"].startswith("0 of")),
                   key=lambda s: int(s.split()[1]))
    depends = [s for s, r in sets.items() if not r["macro above micro in"].startswith("0 of")]
    _require(len(depends) == 1, "on Set N the verdict depends on the head joints", f"such sets: {depends}")
    s = sets[depends[0]]
    frictional = [_shown(s[k]) for k in deltas if "frictionless" not in k]
    frictionless = [-_shown(s[k]) for k in deltas if "frictionless" in k]
    _require(min(frictional) > 0 and min(frictionless) > 0, "above with frictional ones, below with frictionless",
             f"{depends[0]}: {frictional}, {frictionless}")
    return (
        "**Under every bond?** The micro wall can start with a full or a half block and have head joints with or "
        f"without friction. From {first} rows on, the macro λ lies above the micro one under every bond where the "
        f"micro model settles (by {_range(min(above), max(above))} %); on Table 7's walls it lies below under every "
        f"bond on {_sets(below)}, while on {depends[0]} the verdict depends on the head joints: above by "
        f"{_range(min(frictional), max(frictional))} % with frictional ones, below by "
        f"{_range(min(frictionless), max(frictionless))} % with frictionless ones (REPORT.md, \"How robust the "
        "finding is\")."
    )


def _errormap(d: Data) -> str:
    from comparison.report.errormap import load
    from comparison.sweep.wall_comparisons import AGREEMENT

    summary = d.json["errormap"]["summary"]
    nonassoc, verdicts = summary["nonassoc"], summary["verdicts"]
    cells = load(d.reports / "sweeps" / "errormap.csv")
    limits = tomllib.loads((d.root / ERRORMAP_GRID).read_text(encoding="utf-8"))["limits"]
    limit = limits["max_blocks"]
    with_ref = [c for c in cells if c.reference_kind == "non-assoc" and math.isfinite(c.error("macro"))]

    def above_from(rows: int) -> bool:
        return all(c.error("macro") > AGREEMENT for c in with_ref if c.rows >= rows and c.m < 1)

    first = min(r for r in {c.rows for c in with_ref} if above_from(r))
    fs = {c.f for c in cells}
    _require(len(fs) == 1, "at f = F", f"the error map has several f: {sorted(fs)}")
    larger = sum(c.blocks > limit for c in with_ref)
    _require(not larger or limits.get("where_needed", False), "of up to N blocks",
             "a wall above the grid's max_blocks without where_needed")
    bound, state = verdicts.get("unsafe, by the associative bound", 0), verdicts.get("unsafe, by a certified state", 0)
    open_, none = verdicts.get("not refuted", 0), verdicts.get("no verdict", 0)
    _require(bound + state + open_ + none == len(cells), "walls by verdict", "the verdicts do not add up to the walls")
    return (
        f"**The error map** ({len(cells)} walls: t × m × rows × storeys at f = {fs.pop():g}; the non-associative "
        f"micro model on the {nonassoc['walls'] - larger} of up to {limit:,} blocks"
        + (f" and on the {larger} larger ones whose verdict needs it" if larger else "")
        + f", the associative LP on all): the macro "
        f"model is unsafe on {bound + state} walls, proven by the associative bound on {bound} and by a certified "
        f"collapse state on {state}; it is not refuted on {open_}"
        + (f", and {none} walls above the block limit have no verdict" if none else ", and every wall has a verdict")
        + f". Against the non-associative value the macro λ lies above on {nonassoc['unsafe']} of "
        f"{nonassoc['walls']} walls, by more than 10 % on {nonassoc['above_10pct']}, by up to "
        f"{_bound(100 * nonassoc['max'])} %; from {first} rows on it is above on every wall with m < 1."
    )


def _lowest(d: Data) -> str:
    from comparison.report.lowest import load

    closed = [r for r in load(d.reports / "lowest.csv") if r["global_status"] == "optimal"]
    off = [r["wall"] for r in closed if abs(float(r["lowest_over_global"])) > SAME]
    _require(not off, "the lowest certified state is the global minimum every time", f"not on {off}")
    over = [100 * float(r["iterated_over_global"]) for r in closed if float(r["iterated_over_global"]) > SAME]
    return (
        "**The non-associative collapse load is not unique**, and the iterated LP's value is not the lowest: "
        f"where the global search closes ({len(closed)} small walls) the lowest certified state is the global "
        f"minimum every time, while the iterated LP is {_range(min(over), max(over), 0)} % above it on "
        f"{len(over)}. Every output gives the lowest certified state first, the iterated LP's value beside it "
        "([which value to quote](docs/micro/nonassociative.md#which-value-to-quote))."
    )


#: Phrases not broken across lines: ``x = y`` and a link's text.
UNBROKEN = re.compile(r"\S+ = \S+|\[[^\]]*\]\([^)]*\)")


def _bullet(text: str) -> str:
    """``text`` as a bullet wrapped at :data:`WIDTH`, its :data:`UNBROKEN` phrases on one line."""
    glued = UNBROKEN.sub(lambda m: m.group(0).replace(" ", "\0"), text)
    wrapped = textwrap.fill(glued, WIDTH, initial_indent="* ", subsequent_indent="  ", break_on_hyphens=False,
                            break_long_words=False)
    return wrapped.replace("\0", " ")


def findings(reports: Path, root: Path | None = None) -> str:
    """The README's findings block (without its markers) from the report in ``reports`` (``report.json``,
    ``sweeps/errormap.csv``, ``lowest.csv``); ``root``: the repository (for the error map's grid; default
    the parent of ``reports``).

    Raises:
        StaleProse: the data no longer bears out a sentence.
    """
    d = Data(reports, reports.parent if root is None else root)
    table = "\n".join("  " + line for line in _rows_table(d))
    return "\n".join([
        _bullet(_paper(d)),
        _bullet(_validation(d)),
        _bullet(_beyond(d)) + "\n\n" + table + "\n",
        _bullet(_robustness(d)),
        _bullet(_errormap(d)),
        _bullet(_lowest(d)),
    ]) + "\n"


def block(readme: str) -> str:
    """The generated block of ``readme``'s text (between the markers)."""
    m = re.search(re.escape(BEGIN) + r"\n(.*?)" + re.escape(END), readme, re.S)
    if m is None:
        raise ValueError(f"README.md has no block between {BEGIN!r} and {END!r}")
    return m.group(1)


def replace(readme: str, new: str) -> str:
    """``readme`` with its generated block replaced by ``new``."""
    old = block(readme)
    return readme.replace(f"{BEGIN}\n{old}{END}", f"{BEGIN}\n{new}{END}", 1)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comparison.report.readme", description=__doc__.split("\n")[0])
    parser.add_argument("--readme", type=Path, default=Path("README.md"))
    parser.add_argument("--reports", type=Path, default=Path("reports"))
    parser.add_argument("--check", action="store_true", help="exit 1 when the block differs, write nothing")
    args = parser.parse_args(argv)
    text = args.readme.read_text(encoding="utf-8")
    new = findings(args.reports.resolve())
    if args.check:
        same = block(text) == new
        sys.stdout.write(f"{args.readme}: the findings block {'matches' if same else 'differs from'} {args.reports}\n")
        return 0 if same else 1
    args.readme.write_text(replace(text, new), encoding="utf-8")
    sys.stdout.write(f"{args.readme}: the findings block rewritten from {args.reports}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
