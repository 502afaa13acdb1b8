"""The walls a downstream test runs on: the paper's cases, a selection of them, or the user's own list.

Each wall is a :class:`comparison.domain.cases.PaperCase` (the paper's Table 4
parameters ``t, m, rows, f, p, storeys``, ``label``, and ``spec()`` for the
dimensional wall); a user's wall is a :class:`UserWall`, the same without
published values.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from comparison.domain.cases import CASES, PaperCase, case, cases_in_table
from comparison.domain.wall import WallSpec
from comparison.utilities import names, numbers
from comparison.utilities.inputs import parse_toml, read_input_file

#: The paper's tables that hold cases.
TABLES = ("5", "6", "7", "8", "9")

#: The keys of a wall in a walls file, and their defaults.
WALL_KEYS: Mapping[str, Any] = {"name": None, "t": None, "m": None, "rows": None, "f": None, "p": 0.0, "storeys": 1}


@dataclass(frozen=True)
class UserWall(PaperCase):
    """A wall of the user's list, in the paper's parameters (no published values)."""

    @property
    def label(self) -> str:
        """The wall's name as given."""
        return self.case


def select_cases(selection: str, own: Sequence[UserWall] = ()) -> tuple[PaperCase, ...]:
    """The walls a comma-separated ``selection`` names: tables (``"7"``, ``"table 9"``), the paper's cases
    (``"Ref"``, ``"Set 12"``, ``"12"``), ``"all"`` (every paper case), or the names of ``own`` walls
    (``"my squat wall"``; a name of your own wall is read as that wall first, then a table, then a case).

    Returns:
        The paper's cases selected, in the paper's order, then the own walls named, in the file's order.

    Raises:
        ValueError: a name that is neither a table, a case nor one of ``own``.
    """
    if not isinstance(selection, str):
        raise TypeError(f"--xcheck-cases must be a comma-separated string such as '7' or 'Ref,Set 12', got "
                        f"{selection!r} ({type(selection).__name__})")
    out: dict[str, PaperCase] = {}
    mine: dict[str, UserWall] = {}
    own_by_name = {w.label: w for w in own}
    for raw in (s.strip() for s in selection.split(",") if s.strip()):
        key = raw.lower().removeprefix("table").strip()
        if raw in own_by_name:
            mine[raw] = own_by_name[raw]
            continue
        if key == "all":
            found: tuple[PaperCase, ...] = CASES
        elif raw.lower().startswith("table") or (key.isdigit() and cases_in_table(key)):
            found = cases_in_table(key)
            if not found:
                raise ValueError(f"--xcheck-cases: no table {key!r} (tables 5, 6, 7, 8, 9)")
        else:
            try:
                found = (case(raw),)
            except ValueError:
                walls = f", nor a wall of --xcheck-walls ({', '.join(own_by_name)})" if own else ""
                raise ValueError(f"--xcheck-cases: {raw!r} is neither a table (5, 6, 7, 8, 9), a paper case (Ref, "
                                 f"Set 1..17){walls}") from None
        out |= {c.label: c for c in found}
    if not out and not mine:
        raise ValueError(f"--xcheck-cases: no wall selected by {selection!r}: name a table ('7'), a case "
                         "('Set 12'), 'all' or a wall of --xcheck-walls")
    return (*(c for c in CASES if c.label in out), *(w for w in own if w.label in mine))


def paper_cases(*tables: str, known_gaps: Mapping[str, str] | None = None) -> list[Any]:
    """The paper's cases of ``tables`` (all when none) as ``pytest.param`` values, for ``parametrize``.

    Args:
        tables: ``"5"``, ``"6"``, ``"7"``, ``"8"``, ``"9"`` (``"table 7"`` too).
        known_gaps: cases your method is known to miss (``{"Set 11": "why"}``): their tests are
            marked ``xfail(strict=True)`` with the reason, so they report as expected failures
            and fail again the day they pass (then drop the entry).

    Raises:
        TypeError: a table that is not a string (``7``), or ``known_gaps`` that is not a mapping of case
            names to reasons (``["Set 11"]``, ``{"Set 11": None}``).
        ValueError: a table the paper does not have (``"99"``: no silently empty selection, whose tests
            pytest would skip and pass), a known gap that names no case or a case outside the selection,
            or an empty reason.
    """
    chosen: dict[str, PaperCase] = {}
    for table in tables:
        if not isinstance(table, str):
            raise TypeError(f"paper_cases: tables must be strings such as '7', got {table!r} ({type(table).__name__})")
        found = cases_in_table(table.strip().lower().removeprefix("table").strip())
        if not found:
            raise ValueError(f"paper_cases: no table {table!r} (tables {', '.join(TABLES)})")
        chosen |= {c.label: c for c in found}
    cases = tuple(c for c in CASES if not tables or c.label in chosen)
    gaps = _known_gaps(known_gaps)
    stray = sorted(set(gaps) - {c.label for c in cases})
    if stray:
        raise ValueError(f"known_gaps: {', '.join(stray)} not among the selected cases")
    return [
        pytest.param(c, id=c.label, marks=[pytest.mark.xfail(reason=gaps[c.label], strict=True)])
        if c.label in gaps
        else pytest.param(c, id=c.label)
        for c in cases
    ]


def _known_gaps(known_gaps: object) -> dict[str, str]:
    """``known_gaps`` of :func:`paper_cases` by case label, each reason a non-empty string."""
    if known_gaps is None:
        return {}
    if not isinstance(known_gaps, Mapping):
        raise TypeError(f"known_gaps must map case names to reasons ({{'Set 11': 'why'}}), got {known_gaps!r} "
                        f"({type(known_gaps).__name__})")
    gaps: dict[str, str] = {}
    for name, reason in known_gaps.items():
        try:
            label = case(name).label
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"known_gaps: {exc}") from None
        if not isinstance(reason, str):
            raise TypeError(f"known_gaps[{name!r}] must be the reason, a string, got {reason!r} "
                            f"({type(reason).__name__})")
        if not reason.strip():
            raise ValueError(f"known_gaps[{name!r}]: the reason is empty; say why the case is a known gap")
        gaps[label] = reason
    return gaps


def walls_from_file(path: str | Path) -> tuple[UserWall, ...]:
    """The walls of a TOML file: one ``[[wall]]`` table each, with ``name``, ``t``, ``m`` (``"1/3"``
    allowed), ``rows``, ``f`` and optionally ``p`` (default 0) and ``storeys`` (default 1).

    Raises:
        ValueError: the file cannot be read, or a wall is malformed (naming the file, the wall and the key).
    """
    p = Path(path)
    try:
        data = parse_toml(read_input_file(p).decode("utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise ValueError(f"{p}: {exc}") from None
    walls = data.get("wall")
    if not isinstance(walls, list) or not walls:
        raise ValueError(f"{p}: no [[wall]] tables")
    out = tuple(_wall(f"{p}: wall[{i}]", w) for i, w in enumerate(walls))
    twice = names.first_repeated([w.label for w in out])
    if twice is not None:
        first, again = twice
        raise ValueError(f"{p}: wall[{again}]: the name {out[again].label!r} is wall[{first}]'s; each wall needs a "
                         "name of its own (it names its tests and its row of the table)")
    return out


def _wall(where: str, w: Any) -> UserWall:
    if not isinstance(w, dict):
        raise ValueError(f"{where}: not a table")
    unknown = sorted(set(w) - set(WALL_KEYS))
    missing = sorted(k for k, v in WALL_KEYS.items() if v is None and k not in w)
    if unknown or missing:
        problems = [*(f"unknown key {k!r}" for k in unknown), *(f"missing {k!r}" for k in missing)]
        raise ValueError(f"{where}: " + "; ".join(problems))
    v = {**WALL_KEYS, **w}
    try:
        names.label("name", v["name"])
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None
    if _paper_name(v["name"]):
        raise ValueError(f"{where}: the name {v['name']!r} is the paper's (a case, a table or 'all'); your wall "
                         "would be selected and compared as that one: give it a name of its own")
    try:
        m = _fraction("m", v["m"]) if isinstance(v["m"], str) else v["m"]
        WallSpec.from_paper(t=v["t"], m=m, rows=v["rows"], f=v["f"], p=v["p"], storeys=v["storeys"])
    except (ValueError, ZeroDivisionError, TypeError) as exc:
        raise ValueError(f"{where} ({v['name']}): {exc}") from None
    return UserWall(v["name"], v["t"], m, v["rows"], v["f"], v["p"], v["storeys"], tables=())


def _paper_name(name: str) -> bool:
    """Whether ``name`` is what :func:`select_cases` and the references read as the paper's (``"Ref"``, ``"12"``,
    ``"set 12"``, ``"7"``, ``"table 7"``, ``"all"``)."""
    key = name.strip().lower().removeprefix("table").strip()
    if key == "all" or cases_in_table(key):
        return True
    try:
        case(name)
    except (TypeError, ValueError):
        return False
    return True


def _fraction(name: str, text: str) -> float:
    """A number written as text in a walls file (``"1/3"``)."""
    try:
        return float(numbers.exact(name, text))
    except numbers.OutOfRange:
        raise
    except (ValueError, OverflowError):  # not a number; beyond the doubles (1e400)
        raise ValueError(f"{name} must be a number or a fraction such as \"1/3\", got {text!r}") from None


def cases_and_walls(selection: str | None, walls_file: str | None) -> Sequence[PaperCase]:
    """What ``--xcheck-cases`` and ``--xcheck-walls`` select.

    * neither: every paper case;
    * ``--xcheck-walls`` alone: the file's walls alone;
    * ``--xcheck-cases`` alone: the tables and cases it names;
    * both: the tables and cases named, and the file's walls that the selection names, or all of them
      when it names none (``--xcheck-cases 7 --xcheck-walls walls.toml``: Table 7 and your walls;
      ``--xcheck-cases "my squat wall" --xcheck-walls walls.toml``: that wall alone).

    Raises:
        ValueError: an unreadable walls file, or a name that is neither a table, a case nor a wall of the file.
    """
    own = walls_from_file(walls_file) if walls_file else ()
    if not selection:
        return list(own) if own else list(CASES)
    chosen = select_cases(selection, own)
    if own and not any(isinstance(c, UserWall) for c in chosen):
        chosen = (*chosen, *own)
    return list(chosen)
