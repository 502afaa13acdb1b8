"""A sweep table read as comparisons: on every wall (and bond), each macro column against the micro reference.

The *macro columns* are the paper's macro model (``macro``) and the user's models
(:mod:`~comparison.sweep.usermodel`), each with its value on every wall. The
*micro reference* of a wall in a bond is the non-associative method's value where
it converged (the table's ``load_factor``: the value to quote, its lowest
certified collapse state where the descent found one, of the wall as built; the
iterated LP's own value is the ``iterated_load_factor`` column; where a sliver's
local mechanism governs, the held wall's value beside it is ``held_load_factor``,
never compared), else the associative LP's (an
upper bound of the non-associative load factor, so that a macro value above it is
unsafe for certain). The difference of a column is
``(λ_column − λ_micro) / λ_micro``; a column lies *above* the reference on a wall where it
exceeds :data:`AGREEMENT`.

The *verdict* on a column (:meth:`Wall.verdict`) is :func:`comparison.domain.proof.judge`'s, as ``xcheck
compare`` gives it: unsafe by the associative bound, unsafe by a certified state (the value to quote
where it is the lowest certified state: the table's ``quoted`` column), not refuted (below every state
found), or no verdict (no converged non-associative value, or one not certified below the macro value, and
the bound does not settle it).

Everything here is read from the table's rows (strings, as
:func:`~comparison.sweep.table.read_table` gives them), never recomputed, and
reads a table of an earlier version (without the ``quoted`` columns) too.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from comparison.domain.proof import ACCURACY, ASSOCIATIVE_BOUND, judge
from comparison.sweep.grid import BOND
from comparison.sweep.table import number
from micro.nonassociative.nonassociative_result import QUOTED_LOWEST
from micro.records import SUCCESS_STATUSES

#: Relative difference within which a macro column and the micro reference agree: the solvers' accuracy of
#: the verdict (:data:`comparison.domain.proof.ACCURACY`). Walls where both slide at lambda = f differ by 1e-9 and
#: count as agreeing.
AGREEMENT = ACCURACY
#: The verdicts a page counts, as it words them (:func:`verdict_label`), in this order.
VERDICT_LABELS = ("unsafe, by the associative bound", "unsafe, by a certified state", "not refuted", "no verdict")
#: The margins of the summary: walls where a macro column lies above the micro reference by more than each.
MARGINS = (0.05, 0.10)
#: The kinds whose rows are macro columns (one value per wall).
MACRO_KINDS = ("macro", "user")
#: The status of a macro column's value.
MACRO_OK = "optimal"
#: The axes a wall of the table varies over, in the order the figures prefer them (the heat map's columns
#: and rows first): the paper's parameters, then the bond.
AXES = ("t", "m", "f", "p", "rows", "storeys", "first_course", "head_joints", "ends")
#: How the axes are written in labels.
SYMBOLS = {"t": "t", "m": "m", "f": "f", "p": "p", "rows": "o", "storeys": "N", "first_course": "first course",
           "head_joints": "head joints", "ends": "ends"}
_PARAMS = ("t", "m", "rows", "f", "p", "storeys")


@dataclass(frozen=True)
class Wall:
    """One wall of the table in one bond, with every macro column and the micro values.

    Attributes:
        t, m, rows, f, p, storeys: the wall.
        first_course, head_joints, ends: the bond of its micro values (``""`` when the sweep ran no micro method;
            ``ends`` also in a table before it had that column).
        blocks: blocks of its micro wall (0 when none was built).
        macro: each macro column's value on it, by name (NaN where it gave none).
        assoc: the associative LP's load factor (NaN when not run or failed), of the wall as built.
        nonassoc: the non-associative method's value to quote where it converged (NaN otherwise), of the wall
            as built.
        certified: that value is a certified collapse state (the lowest certified; ``False`` for the iterated
            LP's value and for a table without the ``quoted`` column, which cannot tell).
        local: by micro kind, the local mechanism that governs the wall as built there and the held wall's
            load factor (``(description, lambda held)``; empty when none). ``assoc`` and ``nonassoc`` stay the
            wall as built's.
        half_blocks: the wall's length in half blocks (NaN in a table without that column): not a whole
            number where its courses end in closers or cut pieces.
        mechanism: each macro column's mechanism on it, by name, as the table gives it (the paper's model:
            ``sliding``/``rocking-sliding`` and the hinge storey; empty for a model that gives none).
    """

    t: float
    m: float
    rows: int
    f: float
    p: float
    storeys: int
    first_course: str
    head_joints: str
    blocks: int
    macro: Mapping[str, float]
    assoc: float
    nonassoc: float
    certified: bool = False
    local: Mapping[str, tuple[str, float]] = field(default_factory=dict)
    mechanism: Mapping[str, str] = field(default_factory=dict)
    ends: str = ""
    half_blocks: float = math.nan

    @property
    def cut(self) -> bool:
        """The wall's length is not a whole number of half blocks (its courses end as :attr:`ends` says)."""
        return math.isfinite(self.half_blocks) and abs(self.half_blocks - round(self.half_blocks)) > 1e-9 * max(
            1.0, self.half_blocks)

    @property
    def reference(self) -> float:
        """The micro reference (module docstring)."""
        return self.nonassoc if math.isfinite(self.nonassoc) else self.assoc

    @property
    def reference_kind(self) -> str:
        """``"non-assoc"``, ``"assoc"`` or ``""`` (no micro value)."""
        if math.isfinite(self.nonassoc):
            return "non-assoc"
        return "assoc" if math.isfinite(self.assoc) else ""

    def error(self, column: str) -> float:
        """``(column - reference) / reference`` (NaN without both)."""
        ref, lam = self.reference, self.macro.get(column, math.nan)
        return (lam - ref) / ref if math.isfinite(ref) and math.isfinite(lam) else math.nan

    def verdict(self, column: str) -> tuple[str | None, str | None]:
        """The verdict on ``column`` and its proof (:func:`comparison.domain.proof.judge`)."""
        return judge(self.macro.get(column, math.nan), self.assoc, self.nonassoc if self.certified else math.nan,
                     found_load_factor=self.nonassoc)

    def verdict_label(self, column: str) -> str:
        """The verdict on ``column`` as the page words it (one of :data:`VERDICT_LABELS`)."""
        return verdict_label(*self.verdict(column))

    def value(self, axis: str) -> float | str:
        """The wall's value of ``axis`` (:data:`AXES`)."""
        return getattr(self, axis)

    def parameters(self, axes: Iterable[str] = AXES) -> str:
        """``t = 1, m = 1/3, o = 12, ...`` over ``axes`` (the bond only where there is one)."""
        return ", ".join(f"{SYMBOLS[a]} = {shown(a, self.value(a))}" for a in axes if self.value(a) != "")


def verdict_label(verdict: str | None, proof: str | None) -> str:
    """``"unsafe, by a certified state"``, ``"not refuted"``, ``"no verdict"``, ... (:data:`VERDICT_LABELS`)."""
    if verdict is None:
        return "no verdict"
    return f"{verdict}, by {'the ' if proof == ASSOCIATIVE_BOUND else 'a '}{proof}" if proof else verdict


def verdicts(ws: Sequence[Wall], column: str) -> dict[str, int]:
    """The walls of ``ws`` where ``column`` has a value, counted by verdict (:data:`VERDICT_LABELS`; a
    "safe" verdict, which needs a global search a sweep does not run, would be counted after them)."""
    out = dict.fromkeys(VERDICT_LABELS, 0)
    for w in ws:
        if math.isfinite(w.macro.get(column, math.nan)):
            label = w.verdict_label(column)
            out[label] = out.get(label, 0) + 1
    return out


def shown(axis: str, value: float | str) -> str:
    """An axis' value as the page writes it: ``t`` and ``m`` as short fractions (``2/3``), numbers by ``g``."""
    if isinstance(value, str):
        return value
    if axis in ("t", "m"):
        f = Fraction(value).limit_denominator(12)
        if abs(float(f) - value) < 1e-9:
            return str(f)
    return f"{value:g}"


def success(kind: str, status: str) -> bool:
    """Whether a row of ``kind`` with ``status`` holds a value."""
    return status == MACRO_OK if kind in MACRO_KINDS else status in SUCCESS_STATUSES


def columns(rows: Sequence[Mapping[str, str]]) -> list[str]:
    """The macro columns of the table, in the order of its cells (the paper's model first as the grid lists)."""
    return list(dict.fromkeys(r["method"] for r in rows if r["kind"] in MACRO_KINDS))


def walls(rows: Sequence[Mapping[str, str]]) -> list[Wall]:
    """The walls of the table, one per wall and bond of its micro rows (one per wall when there are none),
    in the table's order."""
    macro_cols = columns(rows)
    points: dict[tuple[str, ...], dict[str, Any]] = {}
    for row in rows:
        key = tuple(row[k] for k in _PARAMS)
        w = points.setdefault(key, {"macro": dict.fromkeys(macro_cols, math.nan), "bonds": {}})
        kind, ok = row["kind"], success(row["kind"], row["status"])
        lam = number(row["load_factor"]) if ok else math.nan  # the wall as built's, the value to quote
        if kind in MACRO_KINDS:
            w["macro"][row["method"]] = lam
            if ok and row.get("mechanism"):
                storey = row.get("hinge_storey") or ""
                w.setdefault("mechanism", {})[row["method"]] = row["mechanism"] + (
                    f", hinge at storey {storey}" if storey and row["mechanism"] != "sliding" else "")
            continue
        if row.get("half_blocks"):
            w["half_blocks"] = number(row["half_blocks"])
        bond = w["bonds"].setdefault((row.get("first_course") or "full", row.get("head_joints") or "frictional",
                                      row.get("ends") or ""),
                                     {"micro-assoc": math.nan, "micro-nonassoc": math.nan, "blocks": 0,
                                      "certified": False, "local": {}})
        if row.get("blocks"):
            bond["blocks"] = max(bond["blocks"], int(float(row["blocks"])))
        if kind in ("micro-assoc", "micro-nonassoc") and math.isfinite(lam) and not math.isfinite(bond[kind]):
            bond[kind] = lam  # the first method of its kind in the grid's order
            if row.get("local_mechanism"):
                bond["local"][kind] = (row["local_mechanism"], number(row.get("held_load_factor", "")))
            if kind == "micro-nonassoc":
                bond["certified"] = row.get("quoted") == QUOTED_LOWEST
    out = []
    for key, w in points.items():
        t, m, o, f, p, n = (number(x) for x in key)
        params = (t, m, int(o), f, p, int(n))
        bonds = w["bonds"] or {("", "", ""): {"micro-assoc": math.nan, "micro-nonassoc": math.nan, "blocks": 0,
                                              "local": {}}}
        for (fc, hj, ends), b in sorted(bonds.items(), key=lambda kv: _bond_order(kv[0])):
            out.append(Wall(*params, fc, hj, b["blocks"], dict(w["macro"]), b["micro-assoc"], b["micro-nonassoc"],
                            b.get("certified", False), b["local"], dict(w.get("mechanism", {})), ends,
                            w.get("half_blocks", math.nan)))
    return out


def _bond_order(bond: tuple[str, str, str]) -> tuple[int, ...]:
    return tuple(BOND[k].index(v) if v in BOND[k] else -1 for k, v in zip(BOND, bond, strict=True))


def axis_values(ws: Sequence[Wall], axis: str) -> list[float | str]:
    """The distinct values of ``axis`` over ``ws``, in order (the bond's in the grid file's order of choices)."""
    values = {w.value(axis) for w in ws}
    if axis in BOND:
        return sorted(values, key=lambda v: BOND[axis].index(str(v)) if v in BOND[axis] else -1)
    return sorted(values, key=float)


def varying(ws: Sequence[Wall]) -> list[str]:
    """The axes along which ``ws`` take more than one value, in :data:`AXES`' order."""
    return [a for a in AXES if len(axis_values(ws, a)) > 1]


def part(ws: Sequence[Wall], column: str) -> dict[str, Any]:
    """The counts of ``column`` over the walls of ``ws`` with a difference: ``walls``, ``unsafe`` (above
    :data:`AGREEMENT`), ``above_5pct``, ``above_10pct`` (:data:`MARGINS`), ``agree`` (within
    :data:`AGREEMENT`), ``median`` and ``max`` of the difference (``None`` without walls: JSON has no NaN)."""
    errs = [e for w in ws if math.isfinite(e := w.error(column))]
    return {
        "walls": len(errs),
        "unsafe": sum(e > AGREEMENT for e in errs),
        **{f"above_{round(100 * m)}pct": sum(e > m for e in errs) for m in MARGINS},
        "agree": sum(abs(e) <= AGREEMENT for e in errs),
        "median": statistics.median(errs) if errs else None,
        "max": max(errs) if errs else None,
    }


def summary(ws: Sequence[Wall], column: str, groups: Sequence[str] = ()) -> dict[str, Any]:
    """The counts of ``column`` (:func:`part`) over all walls, against each kind of reference, by the values
    of the axes ``groups`` (``"N=1, o=12"``), the walls by verdict (:func:`verdicts`), and the walls without a
    micro reference (or a value of the column)."""
    compared = [w for w in ws if math.isfinite(w.error(column))]
    by_group: dict[str, Any] = {}
    if groups:
        keys = sorted({tuple(w.value(a) for a in groups) for w in compared},
                      key=lambda k: tuple(_sortable(a, v) for a, v in zip(groups, k, strict=True)))
        for k in keys:
            label = ", ".join(f"{SYMBOLS[a]}={shown(a, v)}" for a, v in zip(groups, k, strict=True))
            by_group[label] = part([w for w in compared if tuple(w.value(a) for a in groups) == k], column)
    return {
        "all": part(compared, column),
        "verdicts": verdicts(ws, column),
        "nonassoc": part([w for w in compared if w.reference_kind == "non-assoc"], column),
        "assoc": part([w for w in compared if w.reference_kind == "assoc"], column),
        "by_group": by_group,
        "no_reference": len(ws) - len(compared),
    }


def _sortable(axis: str, value: float | str) -> tuple[int, float]:
    if axis in BOND:
        return (0, float(BOND[axis].index(str(value)) if value in BOND[axis] else -1))
    return (0, float(value))


def worst(ws: Sequence[Wall], column: str, n: int) -> list[Wall]:
    """The ``n`` walls where ``column`` lies furthest above the micro reference."""
    return sorted((w for w in ws if math.isfinite(w.error(column))), key=lambda w: w.error(column), reverse=True)[:n]
