"""Every figure README.md quotes in "What the comparison shows", against the report's data.

The figures are read from the README's sentences and checked against the fields of ``reports/report.json``
by name (and, for the two studies the report reads rather than recomputes, against its committed tables
``reports/sweeps/errormap.csv`` and ``reports/lowest.csv``, through the report's own readers). A
regenerated report that moves a figure fails here, naming the sentence, the figure and the field.

Each :data:`CLAIMS` entry is a pattern of the README's words, the figures as its groups, and a function
computing them from the data. How a figure compares:

* a value (``0.583``, ``+8.4 %``, a range ``2-26 %``): equal to the data rounded to the README's decimals;
* a bound (``within 9.3 %``, ``up to 24.4 %``): at least the value as the report prints it (one decimal for
  a percentage) and less than one unit of the README's last digit above it;
* a count (``13 of the 14``, ``five sets``): equal.

Every number of the section must belong to a claim or be a label (:data:`LABELS`: a table's or a set's
name, a parameter naming a wall). Rewording the section means updating :data:`CLAIMS`; a sentence no
claim finds fails with the claim's name.
"""

from __future__ import annotations

import json
import math
import re
import tomllib
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
REPORTS = ROOT / "reports"
SECTION = "## What the comparison shows"
#: Table 5 prints λ to three decimals: a set reproduces it "within its rounding" when ours is within half a unit.
TABLE5_ROUNDING = 5e-4
#: Relative differences below this are equal load factors (the LPs are solved to about 1e-6).
SAME = 1e-6
WORDS = {w: i for i, w in enumerate(("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine"))}
#: A number of the section: signs (also the typographic minus), thousands separators, decimals, fractions.
NUMBER = re.compile(r"[−+-]?\d+(?:,\d{3})*(?:\.\d+)?(?:/\d+)?")
#: Numbers that name something rather than quote a result.
LABELS = [r"\bTables? \d+(?: and \d+)?", r"\bSets? \d+", r"\bEqs?\. [\d-]+", r"\bm = 1/2", r"Table 6's 1/3"]


# ------------------------------------------------------------------------------------------------ the data


@cache
def report() -> dict[str, Any]:
    return json.loads((REPORTS / "report.json").read_text(encoding="utf-8"))


def table(name: str) -> list[dict[str, Any]]:
    """A table of report.json (its rows, keyed by column)."""
    tables = report()["tables"]
    assert name in tables, f"report.json has no table {name!r} (it has {sorted(tables)})"
    return list(tables[name])


def column(rows: list[dict[str, Any]], name: str, table_name: str) -> list[Any]:
    """The column ``name`` of ``rows``; fails naming the columns there are."""
    assert rows and name in rows[0], f"report.json's {table_name} has no column {name!r} (it has {list(rows[0])})"
    return [r[name] for r in rows]


def shown(value: Any) -> float:
    """A cell of report.json as a number (percentages are strings such as ``"+24.4"``); NaN for text."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


@cache
def errormap_cells() -> list[Any]:
    from comparison.report.errormap import load

    return load(REPORTS / "sweeps" / "errormap.csv")


@cache
def lowest_rows() -> list[dict[str, Any]]:
    from comparison.report.lowest import load

    return load(REPORTS / "lowest.csv")


# ------------------------------------------------------------------------------------------------ figures


@dataclass(frozen=True)
class Figure:
    """One figure of the README and what the data says it is.

    Attributes:
        text: as the README writes it.
        value: from the data.
        how: ``"value"``, ``"bound"`` or ``"count"`` (module docstring).
        source: where the value comes from, for the failure message.
    """

    text: str
    value: float
    how: str
    source: str

    def problem(self) -> str | None:
        """Why the README's figure does not match, or ``None``."""
        text = self.text.replace("−", "-").replace(",", "")
        if self.how == "count":
            said = WORDS[text] if text in WORDS else int(text)
            return None if said == self.value else f"says {self.text}, {self.source} gives {self.value:g}"
        said = float(text)
        decimals = len(text.split(".")[1]) if "." in text else 0
        if self.how == "value":
            if abs(self.value - said) <= 0.5 * 10**-decimals + 1e-12:  # the value rounded to the README's decimals
                return None
            return f"says {self.text}, {self.source} gives {self.value:.{decimals + 2}f}"
        if self.value <= said + 1e-12 and said - self.value < 10**-decimals:
            return None
        return f"says {self.text} as a bound, {self.source} gives {self.value:g}"


def pct_range(m: re.Match[str], lo: float, hi: float, source: str) -> list[Figure]:
    """The figures of a range ``LO-HI`` (groups ``lo`` and ``hi``)."""
    return [Figure(m.group("lo"), lo, "value", f"the least {source}"),
            Figure(m.group("hi"), hi, "value", f"the greatest {source}")]  # fmt: skip


# ------------------------------------------------------------------------------------------------ the claims


def _table5(m: re.Match[str]) -> list[Figure]:
    rows = table("table5")
    paper, ours = column(rows, "λ paper", "table5"), column(rows, "λ ours (Eq. 10)", "table5")
    off = sum(abs(p - o) > TABLE5_ROUNDING for p, o in zip(paper, ours, strict=True))
    return [Figure(m.group("n"), off, "count", "table5: the sets whose |λ ours - λ paper| exceeds 5e-4")]


def _table7(m: re.Match[str]) -> list[Figure]:
    rows = table("table7")
    macro = [abs(shown(v)) for v in column(rows, "Δ % macro vs micro-nonassoc (lowest certified)", "table7")]
    orduna = [abs(shown(v)) for v in column(rows, "Δ % vs Orduña (micro-nonassoc)", "table7")]
    sets = {r["row"] for r in rows}
    all_cases = {r["row"]: r for r in table("all_cases")}
    published = {r["row"]: r["Orduña micro"] for r in rows}
    iterated = [abs(round(100 * (all_cases[s]["micro-nonassoc iterated LP λ"] / published[s] - 1), 1)) for s in sets]
    return [
        Figure(m.group("rows"), max(all_cases[s]["o"] for s in sets), "value", "all_cases' o of Table 7's sets"),
        Figure(m.group("rows"), min(all_cases[s]["o"] for s in sets), "value", "all_cases' o of Table 7's sets"),
        Figure(m.group("within"), max(macro), "bound", "table7's greatest |Δ % macro vs micro-nonassoc|"),
        *pct_range(m, min(orduna), max(orduna), "table7 |Δ % vs Orduña (micro-nonassoc)| of the lowest state"),
        Figure(m.group("ilo"), min(iterated), "value", "all_cases' iterated LP λ against table7's Orduña, least |Δ %|"),
        Figure(m.group("ihi"), max(iterated), "value", "all_cases' iterated LP λ against table7's Orduña, most |Δ %|"),
    ]


def _robustness(m: re.Match[str]) -> list[Figure]:
    rows = table("robustness")
    deltas = [k for k in rows[0] if k.startswith("Δ % macro, ")]
    every = [r for r in rows if r["row"].startswith("base wall") and r["macro above micro in"].split(" of ")[0]
             == r["macro above micro in"].split(" of ")[1] != "0"]
    first = min(int(r["row"].rsplit("= ", 1)[1]) for r in every)
    beyond = [r for r in rows if r["row"].startswith("base wall") and int(r["row"].rsplit("= ", 1)[1]) >= first]
    assert beyond == every, "README: above under every bond from that many rows on; robustness: not on every wall"
    above = [shown(r[k]) for r in beyond for k in deltas if math.isfinite(shown(r[k]))]
    sets = {r["row"]: r for r in rows if r["row"].startswith("Set ")}
    below_every = sorted(s for s, r in sets.items() if r["macro above micro in"].startswith("0 of"))
    said = [f"Set {n}" for n in re.findall(r"\d+", m.group("below"))]
    assert said == below_every, f"README says below under every bond on {said}; robustness: {below_every}"
    s13 = sets[m.group("depends")]
    frictional = [shown(s13[k]) for k in deltas if "frictionless" not in k]
    frictionless = [-shown(s13[k]) for k in deltas if "frictionless" in k]
    assert min(frictional) > 0 and min(frictionless) > 0, "README: Set 13 above with frictional heads only"
    src = "robustness"
    return [
        Figure(m.group("from"), first, "count", f"{src}: the fewest rows above under every bond"),
        *pct_range(m, min(above), max(above), f"{src}: Δ % from that many rows on"),
        Figure(m.group("alo"), min(frictional), "value", f"{src}: {m.group('depends')}, frictional heads, least Δ"),
        Figure(m.group("ahi"), max(frictional), "value", f"{src}: {m.group('depends')}, frictional heads, most Δ"),
        Figure(m.group("blo"), min(frictionless), "value", f"{src}: {m.group('depends')}, frictionless, least -Δ"),
        Figure(m.group("bhi"), max(frictionless), "value", f"{src}: {m.group('depends')}, frictionless, most -Δ"),
    ]


def _beyond(m: re.Match[str]) -> list[Figure]:
    validation = {r["row"] for r in table("table7")}
    rows = [r for r in table("all_cases") if r["row"] not in validation]
    name = "Δ % macro vs micro (non-assoc., else assoc.)"
    built = [r for r, d in zip(rows, column(rows, name, "all_cases"), strict=True) if math.isfinite(shown(d))]
    above = [shown(r[name]) for r in built if shown(r[name]) > 0]
    below = [r for r in built if shown(r[name]) <= 0]
    src = "all_cases beyond Table 7"
    figures = [
        Figure(m.group("above"), len(above), "count", f"{src}: walls with Δ > 0"),
        Figure(m.group("built"), len(built), "count", f"{src}: walls with a Δ"),
        Figure(m.group("rlo"), min(r["o"] for r in built), "value", f"{src}: the fewest rows"),
        Figure(m.group("rhi"), max(r["o"] for r in built), "value", f"{src}: the most rows"),
        *pct_range(m, min(above), max(above), f"{src}: Δ > 0"),
    ]
    assert [r["row"] for r in below] == [m.group("below")], (
        f"README names {m.group('below')} as the only wall below; {src}: {[r['row'] for r in below]}"
    )
    return figures + [
        Figure(m.group("m"), shown(below[0]["m"]), "value", f"all_cases' m of {m.group('below')}"),
        Figure(m.group("d"), shown(below[0][name]), "value", f"all_cases' Δ of {m.group('below')}"),
    ]


def _errormap(m: re.Match[str]) -> list[Figure]:
    summary = report()["errormap"]["summary"]
    part = summary["all"]
    cells = errormap_cells()
    limit = tomllib.loads((ROOT / "examples" / "sweeps" / "errormap.toml").read_text())["limits"]["max_blocks"]
    with_ref = [c for c in cells if math.isfinite(c.error("macro"))]
    from comparison.sweep.compare import AGREEMENT

    def above_from(rows: int) -> bool:
        return all(c.error("macro") > AGREEMENT for c in with_ref if c.rows >= rows and c.m < 1)

    first = min(r for r in {c.rows for c in with_ref} if above_from(r))
    fs = {c.f for c in cells}
    assert len(fs) == 1, f"the error map has several f: {sorted(fs)}"
    assert max(c.blocks for c in with_ref) <= limit
    return [
        Figure(m.group("walls"), part["walls"] + summary["no_reference"], "count", "errormap: walls + no_reference"),
        Figure(m.group("f"), fs.pop(), "value", "errormap.csv's f"),
        Figure(m.group("micro"), part["walls"], "count", "errormap.summary.all.walls"),
        Figure(m.group("limit"), limit, "count", "examples/sweeps/errormap.toml's max_blocks"),
        Figure(m.group("unsafe"), part["unsafe"], "count", "errormap.summary.all.unsafe"),
        Figure(m.group("of"), part["walls"], "count", "errormap.summary.all.walls"),
        Figure(m.group("above10"), part["above_10pct"], "count", "errormap.summary.all.above_10pct"),
        Figure(m.group("max"), round(100 * part["max"], 1), "bound", "errormap.summary.all.max, % (one decimal)"),
        Figure(
            m.group("from"), first, "count", "errormap.csv: the fewest rows from which every wall with m < 1 is unsafe"
        ),
    ]


def _lowest(m: re.Match[str]) -> list[Figure]:
    closed = [r for r in lowest_rows() if r["global_status"] == "optimal"]
    lowest_off = [r["wall"] for r in closed if abs(float(r["lowest_over_global"])) > SAME]
    assert not lowest_off, (
        f"README says the lowest certified state is the global minimum every time; lowest.csv: not on {lowest_off}"
    )
    over = [100 * float(r["iterated_over_global"]) for r in closed if float(r["iterated_over_global"]) > SAME]
    src = "lowest.csv where the global search closed"
    return [
        Figure(m.group("closed"), len(closed), "count", f"{src}: walls"),
        *pct_range(m, min(over), max(over), f"{src}: iterated_over_global > 0, %"),
        Figure(m.group("n"), len(over), "count", f"{src}: walls with iterated_over_global > 0"),
    ]


@dataclass(frozen=True)
class Claim:
    """A sentence of the section (a pattern over its text, whitespace collapsed) and its figures."""

    name: str
    pattern: str
    figures: Callable[[re.Match[str]], list[Figure]]


N = r"[−+-]?\d+(?:,\d{3})*(?:\.\d+)?"
CLAIMS = [
    Claim("Table 5 within its rounding", r"Table 5 within its rounding but for (?P<n>\w+) sets", _table5),
    Claim(
        "Table 7: macro against micro, iterated LP against Orduña",
        rf"\(Table 7, (?P<rows>\d+) rows\)\*\* the macro λ lies within (?P<within>{N}) % of the micro values, and "
        rf"the lowest certified non-associative state comes within (?P<lo>{N})-(?P<hi>{N}) % of Orduña's micro "
        rf"values \(the iterated LP's own fixed point within (?P<ilo>{N})-(?P<ihi>{N}) %\)",
        _table7,
    ),
    Claim(
        "under every bond",
        rf"From (?P<from>\d+) rows on, the macro λ lies above the micro one under every bond where the micro "
        rf"model settles \(by (?P<lo>{N})-(?P<hi>{N}) %\); on Table 7's walls it lies below under every bond on "
        rf"(?P<below>Sets [\d, and]+?), while on (?P<depends>Set \d+) the verdict depends on the head joints: above "
        rf"by (?P<alo>{N})-(?P<ahi>{N}) % with frictional ones, below by (?P<blo>{N})-(?P<bhi>{N}) % with "
        rf"frictionless ones",
        _robustness,
    ),
    Claim(
        "beyond Table 7",
        rf"On (?P<above>\d+) of the (?P<built>\d+) other walls the micro model can build \((?P<rlo>\d+)-(?P<rhi>\d+) "
        rf"rows\) the macro λ exceeds the micro λ by (?P<lo>{N})-(?P<hi>{N}) % \(below it only (?P<below>Set \d+), "
        rf"m = (?P<m>{N}): (?P<d>{N}) %\)",
        _beyond,
    ),
    Claim(
        "the error map",
        rf"\((?P<walls>\d+) walls: t × m × rows × storeys at f = (?P<f>{N}), the micro model on the (?P<micro>\d+) "
        rf"of up to (?P<limit>[\d,]+) blocks\): the macro λ lies above the micro one on (?P<unsafe>\d+) of "
        rf"(?P<of>\d+) walls, by more than 10 % on (?P<above10>\d+), by up to (?P<max>{N}) %; from (?P<from>\d+) "
        rf"rows on it is above on every wall with m < 1",
        _errormap,
    ),
    Claim(
        "the lowest state and the global search",
        rf"where the global search closes \((?P<closed>\d+) small walls\) the lowest certified state is the global "
        rf"minimum every time, while the iterated LP is (?P<lo>{N})-(?P<hi>{N}) % above it on (?P<n>\d+)",
        _lowest,
    ),
]
#: The rows of the README's table of the Table 5 wall by rows, and the field of report.json's sensitivity
#: table each comes from ("macro above micro": computed from the two).
TABLE_ROWS = {"macro λ": "macro λ", "micro λ, lowest certified": "micro-nonassoc (lowest certified) λ"}


# ------------------------------------------------------------------------------------------------ the README


def section() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert SECTION in text, f"README.md has no section {SECTION!r}"
    return text.split(SECTION, 1)[1].split("\n## ", 1)[0]


def split(text: str) -> tuple[str, list[list[str]]]:
    """The section's prose (whitespace collapsed) and its markdown table's rows of cells."""
    prose, rows = [], []
    for line in text.splitlines():
        if line.strip().startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if not all(set(c) <= set("-: ") for c in cells):
                rows.append(cells)
        else:
            prose.append(line)
    return " ".join(" ".join(prose).split()), rows


def table_figures(rows: list[list[str]]) -> Iterator[Figure]:
    """The figures of the table of the Table 5 wall by rows."""
    assert rows and rows[0][0] == "rows of the Table 5 wall", f"README's table starts {rows[:1]}"
    sens = {r["value"]: r for r in table("sensitivity") if r["parameter"] == "rows"}
    by_label = {r[0]: r[1:] for r in rows[1:]}
    unknown = set(by_label) - set(TABLE_ROWS) - {"macro above micro"}
    assert not unknown, f"README's table has rows {sorted(unknown)} that no field of report.json is named for"
    for i, o in enumerate(rows[0][1:]):
        assert o in sens, f"README's table has {o} rows; report.json's sensitivity has {sorted(sens)}"
        values = {label: shown(column([sens[o]], field, "sensitivity")[0]) for label, field in TABLE_ROWS.items()}
        for label, field in TABLE_ROWS.items():
            yield Figure(by_label[label][i], values[label], "value", f"sensitivity rows / {o}: {field}")
        said = by_label["macro above micro"][i].removesuffix("%").strip()
        excess = 100 * (values["macro λ"] / values["micro λ, lowest certified"] - 1)
        yield Figure(said, excess, "value", f"sensitivity rows / {o}: macro λ over micro-nonassoc λ, %")


def test_every_figure_of_the_findings_matches_the_report() -> None:
    """Issue 44, item 4: the README said "the macro λ lies within 9 % of the micro values" on Table 7 while
    REPORT.md shows -9.3 % for Set 11. Every figure of "What the comparison shows" is checked against the
    report's data by the field it comes from."""
    prose, rows = split(section())
    problems = []
    for claim in CLAIMS:
        m = re.search(claim.pattern, prose)
        if m is None:
            problems.append(f"{claim.name}: README no longer says it as the claim's pattern reads; update CLAIMS")
            continue
        for figure in claim.figures(m):
            if (why := figure.problem()) is not None:
                problems.append(f"{claim.name}: README {why} (in '{m.group(0)[:90]}...')")
    for figure in table_figures(rows):
        if (why := figure.problem()) is not None:
            problems.append(f"table of the Table 5 wall by rows: README {why}")
    assert not problems, "README.md's findings against reports/:\n" + "\n".join(problems)


def test_every_number_of_the_findings_is_checked_or_a_label() -> None:
    """No figure of the section escapes the test above: each number lies in a claim's sentence, in the
    checked table, or is a label."""
    prose, _ = split(section())
    covered = [m.span() for claim in CLAIMS if (m := re.search(claim.pattern, prose))]
    covered += [m.span() for label in LABELS for m in re.finditer(label, prose)]
    loose = [
        prose[max(0, n.start() - 30) : n.end() + 10]
        for n in NUMBER.finditer(prose)
        if not any(a <= n.start() and n.end() <= b for a, b in covered)
    ]
    assert not loose, "README's findings quote numbers no claim checks (add a claim or a label): " + " | ".join(loose)


@pytest.mark.parametrize(
    ("text", "value", "how", "ok"),
    [
        ("9", 9.3, "bound", False),  # the README's words before issue 44
        ("9.3", 9.3, "bound", True),
        ("10", 9.3, "bound", True),
        ("12", 9.3, "bound", False),  # true, but not tight
        ("24", 24.4, "bound", False),
        ("2", 2.1, "value", True),
        ("26", 26.2, "value", True),
        ("0.583", 0.58252, "value", True),
        ("0.582", 0.58252, "value", False),
        ("+8.4", 8.35, "value", True),
        ("−0.6", -0.6, "value", True),
        ("five", 5, "count", True),
        ("1,500", 1500, "count", True),
        ("13", 14, "count", False),
    ],
)
def test_how_a_figure_compares(text: str, value: float, how: str, ok: bool) -> None:
    assert (Figure(text, value, how, "data").problem() is None) is ok
