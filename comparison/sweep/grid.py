"""Sweep grid files: the axes of a sweep and its methods, in TOML.

Format (see ``examples/sweeps/``)::

    name = "errormap"                  # names the output files (default: the file's stem)

    [axes]                             # the paper's Table 4 parameters
    t = [0.5, 1.0, 2.0]                # a list,
    m = ["1/3", "1/2", 1]              # fractions written as strings,
    rows = { from = 12, to = 60, step = 12 }   # a range (both ends included),
    f = 0.6                            # or one value
    p = 0                              # optional (default 0)
    storeys = 3                        # optional (default 1)

    [bond]                             # micro walls only; optional
    first_course = ["full", "half"]    # default "full"
    head_joints = "frictional"         # default "frictional"
    ends = "closers"                   # default "closers"; "cut": the courses end in whatever remains
                                       # (docs/micro/walls.md; only walls of L not a whole number of
                                       # half blocks differ)

    [limits]                           # optional
    max_blocks = 1500                  # non-associative micro walls of more blocks are not run
                                       # (the associative LP runs on every wall: its bound
                                       # gives a verdict where it settles it)
    where_needed = true                # ... but for the walls whose verdict needs it: the macro
                                       # value not above the associative bound (default false)

    [[method]]
    kind = "macro"

    [[method]]
    kind = "micro-assoc"
    solver = "clarabel"                # a micro back end (default "normal-ipm", the library's)

    [[method]]
    kind = "micro-nonassoc"
    scheme = "a"                       # "a" or "b" (default "a")
    selection = "vertex+proximal"      # "vertex", "proximal" or "vertex+proximal"
                                       # (default; scheme b: "vertex")
    max_blocks = 600                   # this method on walls of at most 600 blocks

    [[method]]
    kind = "user"                      # your own macro model, as an extra macro column
    name = "my model"                  # its column's name (default: the function's)
    function = "my_model:load_factor"  # module:function(t, m, rows, f, p, storeys) -> lambda,
                                       # the module found beside the grid file first

A user model is Python code run with your rights, like a ``conftest.py``: its module is imported (its
top-level code runs) only after the whole grid has been checked, and only a grid you trust should name one.

A range is ``{ from, to, step }`` or ``{ from, to, num }`` (``num`` values,
evenly spaced; at most :data:`MAX_AXIS_VALUES`). Every wall is every combination of the axes' values (a
combination whose rows do not split equally over its storeys is recorded as
``not_applicable``); every micro method runs on every bond of every wall, a macro or user
model once per wall (:mod:`~comparison.sweep.usermodel`); a grid
of more than :data:`MAX_CELLS` cells is refused. A malformed file raises
:class:`GridError`, one line naming the file, the key and its line.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from comparison.domain.wall import ENDS
from comparison.runner.methods import MACRO, Method
from comparison.sweep.usermodel import UserModel, check_target, resolve
from comparison.utilities import numbers
from comparison.utilities.inputs import parse_toml, read_input_file
from comparison.utilities.toml_source import TomlSource
from macro import checks

#: The axes, each with its check (the wall vocabulary) and its default (``None``: required).
AXES: dict[str, tuple[Callable[[str, object], float], float | None]] = {
    "t": (checks.positive, None),
    "m": (lambda name, v: checks.in_range(name, v, 0.0, 1.0), None),
    "rows": (checks.positive_int, None),
    "f": (checks.positive, None),
    "p": (checks.non_negative, 0.0),
    "storeys": (checks.positive_int, 1),
}
#: The bond options of the micro walls, with their choices (the first is the default).
BOND: dict[str, tuple[str, ...]] = {"first_course": ("full", "half"), "head_joints": ("frictional", "frictionless"),
                                    "ends": ENDS}
#: Method kinds and the keys each takes.
METHOD_KEYS: dict[str, set[str]] = {
    "macro": {"kind"},
    "micro-assoc": {"kind", "solver", "max_blocks"},
    "micro-nonassoc": {"kind", "scheme", "selection", "max_blocks"},
    "user": {"kind", "name", "function"},
}
#: The kinds of method that give one value per wall (the micro methods give one per bond).
PER_WALL = ("macro", "user")
#: Schemes of the iterated LP.
SCHEMES = ("a", "b")
#: The most values one axis may expand to (a range with a tiny step is a typo, not a sweep).
MAX_AXIS_VALUES = 10_000
#: The most cells (rows of the table) a grid may have: its cells are planned in memory before anything
#: runs (about 0.6 kB each for a micro method), and 100,000 rows are a 30 MB table. A larger
#: grid is refused when read; split it into several sweeps (they share the result cache).
MAX_CELLS = 100_000
#: What a sweep's name may be made of (it names the table, metadata, page and figure files): a letter or
#: digit first (no hidden file, no ``.`` or ``..``, no option-like ``-``), then letters, digits, ``_``,
#: ``-`` or ``.``.
NAME_PATTERN = r"[A-Za-z0-9][A-Za-z0-9_.\-]*"
#: The longest sweep name: file names hold it with a suffix (``-map-<column>.png``) and a temporary
#: file's decoration, and most file systems allow 255 bytes in all.
MAX_NAME_LENGTH = 100
_TOP = {"name", "axes", "bond", "limits", "method"}


class GridError(ValueError):
    """A malformed grid file; the message names the file, the key and its line."""


@dataclass(frozen=True)
class GridMethod:
    """One method of a sweep.

    Attributes:
        method: the method (bond options left at their defaults: the bond is an axis), or a user's
            macro model.
        max_blocks: run it on walls of at most this many blocks (``None``: the grid's limit).
    """

    method: Method | UserModel
    max_blocks: int | None = None


@dataclass(frozen=True)
class Grid:
    """A parsed grid file.

    Attributes:
        name: the sweep's name.
        axes: the values of ``t``, ``m``, ``rows``, ``f``, ``p``, ``storeys``, in that order.
        bond: the values of ``first_course``, ``head_joints`` and ``ends``.
        methods: the methods.
        max_blocks: non-associative micro walls of more blocks are not run (``None``: no limit); the
            associative LP runs on every wall up to its own method's ``max_blocks``.
        where_needed: above ``max_blocks`` the non-associative method still runs on the walls whose
            verdict needs it: where the macro λ is not above the associative LP's of the same bond
            (:func:`comparison.domain.proof.above`), the bound settling nothing there.
    """

    name: str
    axes: Mapping[str, tuple[float, ...]]
    bond: Mapping[str, tuple[str, ...]]
    methods: tuple[GridMethod, ...]
    max_blocks: int | None = None
    where_needed: bool = False

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready description (for the sweep's metadata)."""
        return {
            "name": self.name,
            "axes": {k: list(v) for k, v in self.axes.items()},
            "bond": {k: list(v) for k, v in self.bond.items()},
            "max_blocks": self.max_blocks,
            "where_needed": self.where_needed,
            "methods": [{**m.method.key(), "max_blocks": m.max_blocks} for m in self.methods],
        }


def load_grid(path: str | Path) -> Grid:
    """Read a grid file.

    Raises:
        GridError: unreadable file, TOML syntax error, unknown or missing key,
            or a bad value; the message names the key and its line.
    """
    path = Path(path)
    try:
        text = read_input_file(path).decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise GridError(f"grid {path}: cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    return parse_grid(text, source=str(path), name=path.stem, folder=path.parent)


def parse_grid(text: str, source: str = "<grid>", name: str = "sweep", folder: Path | None = None) -> Grid:
    """Parse the text of a grid file; see :func:`load_grid`. ``folder``: where a user model's module is
    looked for first (the grid file's folder)."""
    try:
        data = parse_toml(text)
    except ValueError as exc:
        raise GridError(f"grid {source}: {exc}") from None
    src = TomlSource(text, source, "grid", GridError)
    for key in data:
        if key not in _TOP:
            raise src.error(f"unknown key {key!r} (allowed: {', '.join(sorted(_TOP))})", "", key)
    label = data.get("name", name)
    if not isinstance(label, str) or not re.fullmatch(NAME_PATTERN, label) or len(label) > MAX_NAME_LENGTH:
        rule = (f"letters, digits, '_', '-' or '.', a letter or digit first, at most {MAX_NAME_LENGTH} "
                "characters (it names the files)")
        long = isinstance(label, str) and len(label) > 40
        shown = f"{label[:40]}... ({len(label)} characters)" if long else label
        raise src.error(f"name must be {rule}, got {shown!r}", "", "name" if "name" in data else None)
    axes = {axis: _axis(_table(data, "axes", src), axis, src) for axis in AXES}
    bond = {key: _bond(_table(data, "bond", src, required=False), key, src) for key in BOND}
    limits = _table(data, "limits", src, required=False)
    _known(limits, {"max_blocks", "where_needed"}, "limits", src)
    max_blocks = _max_blocks(limits, "limits", 0, src)
    where_needed = limits.get("where_needed", False)
    if not isinstance(where_needed, bool):
        raise src.error(f"limits.where_needed must be true or false, got {where_needed!r}", "limits", "where_needed")
    grid = Grid(label, axes, bond, _methods(data, src), max_blocks, where_needed)
    count = cell_count(grid)
    if count > MAX_CELLS:
        sizes = " x ".join(f"{len(v):,} {k}" for k, v in axes.items() if len(v) > 1)
        per_wall = count // math.prod(len(v) for v in axes.values())
        raise GridError(f"grid {source}: {count:,} cells ({sizes} walls, {per_wall} per wall), more than the "
                        f"{MAX_CELLS:,} a sweep may have: split it into smaller grids")
    return _with_user_models(grid, src, folder)


def _with_user_models(grid: Grid, src: TomlSource[GridError], folder: Path | None) -> Grid:
    """``grid`` with its user models' functions imported: the last step of reading a grid, so that no user
    code runs for a grid that is refused."""
    methods = list(grid.methods)
    for index, gm in enumerate(methods):
        if isinstance(gm.method, UserModel):
            try:
                function = resolve(gm.method.target, folder)
            except ValueError as exc:
                raise src.error(f"method.{exc}", "method", "function", index) from None
            methods[index] = replace(gm, method=replace(gm.method, function=function))
    return replace(grid, methods=tuple(methods))


def cell_count(grid: Grid) -> int:
    """The cells of ``grid`` (rows of its table): every wall, times one per macro method and one per bond
    of every micro method; counted without building them."""
    walls = math.prod(len(v) for v in grid.axes.values())
    bonds = math.prod(len(v) for v in grid.bond.values())
    return walls * sum(1 if gm.method.kind in PER_WALL else bonds for gm in grid.methods)


def _table(data: dict[str, Any], table: str, src: TomlSource[GridError], *, required: bool = True) -> dict[str, Any]:
    if table not in data:
        if required:
            raise GridError(f"grid {src.source}: missing table [{table}]")
        return {}
    if not isinstance(data[table], dict):
        raise src.error(f"{table} must be a table, written [{table}]", "", table)
    if table == "axes":
        _known(data[table], set(AXES), table, src)
    elif table == "bond":
        _known(data[table], set(BOND), table, src)
    return data[table]


def _known(entry: dict[str, Any], allowed: set[str], table: str, src: TomlSource[GridError], index: int = 0) -> None:
    for key in entry:
        if key not in allowed:
            raise src.error(f"unknown key {table}.{key} (allowed: {', '.join(sorted(allowed))})", table, key, index)


def _axis(axes: dict[str, Any], axis: str, src: TomlSource[GridError]) -> tuple[float, ...]:
    """The checked, distinct values of one axis."""
    check, default = AXES[axis]
    if axis not in axes:
        if default is None:
            raise src.error(f"missing key axes.{axis}", "axes")
        return (default,)
    raw = axes[axis]
    try:
        values = _expand(raw, axis) if isinstance(raw, dict) else (raw if isinstance(raw, list) else [raw])
        if not values:
            raise ValueError(f"{axis} must have at least one value")
        checked = [check(axis, _number(axis, v)) for v in values]
    except ValueError as exc:
        raise src.error(f"axes.{axis}: {exc}", "axes", axis) from None
    return tuple(dict.fromkeys(checked))


def _number(name: str, value: object) -> object:
    """A fraction string (``"1/3"``) as a float; anything else as it is (the check words it)."""
    if isinstance(value, str):
        fraction = numbers.exact(name, value)
        try:
            return float(fraction)
        except OverflowError:  # beyond the doubles (1e400): infinite, for the axis check to refuse
            return math.inf if fraction > 0 else -math.inf
    return value


def _expand(spec: dict[str, Any], axis: str) -> list[float]:
    """The values of a range ``{from, to, step}`` or ``{from, to, num}``."""
    keys = set(spec)
    if keys not in ({"from", "to", "step"}, {"from", "to", "num"}):
        raise ValueError(f"a range must be {{from, to, step}} or {{from, to, num}}, got keys {sorted(keys)}")
    lo, hi = (float(checks.non_negative(f"{axis}.{k}", _number(axis, spec[k]))) for k in ("from", "to"))
    if hi < lo:
        raise ValueError(f"{axis}: from must not exceed to, got from = {lo:g}, to = {hi:g}")
    if "num" in spec:
        num = checks.positive_int(f"{axis}.num", spec["num"])
        count, step = num, (hi - lo) / (num - 1) if num > 1 else 0.0
    else:
        step = checks.positive(f"{axis}.step", _number(axis, spec["step"]))
        steps = (hi - lo) / step * (1 + 1e-12)  # infinite for a step of 5e-324
        if not steps <= MAX_AXIS_VALUES:
            raise ValueError(f"{axis}: the range gives more than {MAX_AXIS_VALUES} values (step = {step:g})")
        count = math.floor(steps) + 1
    if count > MAX_AXIS_VALUES:
        raise ValueError(f"{axis}: the range gives {count} values, more than {MAX_AXIS_VALUES}")
    return [round(lo + i * step, 12) for i in range(count)]


def _bond(bond: dict[str, Any], key: str, src: TomlSource[GridError]) -> tuple[str, ...]:
    choices = BOND[key]
    raw = bond.get(key, choices[0])
    values = raw if isinstance(raw, list) else [raw]
    try:
        if not values:
            raise ValueError(f"{key} must have at least one value")
        return tuple(dict.fromkeys(checks.choice(key, v, choices) for v in values))
    except ValueError as exc:
        raise src.error(f"bond.{key}: {exc}", "bond", key) from None


def _max_blocks(entry: dict[str, Any], table: str, index: int, src: TomlSource[GridError]) -> int | None:
    if "max_blocks" not in entry:
        return None
    try:
        return checks.positive_int("max_blocks", entry["max_blocks"])
    except ValueError as exc:
        raise src.error(f"{table}.{exc}", table, "max_blocks", index) from None


def _methods(data: dict[str, Any], src: TomlSource[GridError]) -> tuple[GridMethod, ...]:
    entries = data.get("method")
    if not entries:
        raise GridError(f"grid {src.source}: no [[method]] given; a sweep needs at least one")
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        raise src.error("method must be an array of tables, written [[method]]", "", "method")
    methods = [_method(entry, i, src) for i, entry in enumerate(entries)]
    seen: set[str] = set()
    for i, gm in enumerate(methods):
        if gm.method.label in seen:
            if gm.method.kind == "user":
                why = f"method {i + 1}: the name {gm.method.label!r} is another method's"
                raise src.error(why, "method", "name", i)
            raise src.error(f"method {i + 1}: the same method twice ({gm.method.label})", "method", None, i)
        seen.add(gm.method.label)
    return tuple(methods)


def _method(entry: dict[str, Any], index: int, src: TomlSource[GridError]) -> GridMethod:
    import micro

    kind = entry.get("kind")
    if kind not in METHOD_KEYS:
        where = ("method", "kind", index) if "kind" in entry else ("method", None, index)
        raise src.error(f"method.kind must be one of {', '.join(METHOD_KEYS)}, got {kind!r}", *where)
    _known(entry, METHOD_KEYS[kind], "method", src, index)
    if kind == "macro":
        return GridMethod(MACRO)
    if kind == "user":
        return GridMethod(_user(entry, index, src))
    options: dict[str, Any] = {}
    for key, choices in (("solver", micro.SOLVERS), ("scheme", SCHEMES),
                         ("selection", micro.nonassociative.SELECTIONS)):
        if key in METHOD_KEYS[kind] and key in entry:
            try:
                options[key] = checks.choice(f"method.{key}", entry[key], choices)
            except ValueError as exc:
                raise src.error(str(exc), "method", key, index) from None
    solver = options.pop("solver", micro.DEFAULT_SOLVER)
    if kind != "micro-nonassoc":
        return GridMethod(Method(kind, solver=solver), _max_blocks(entry, "method", index, src))
    try:  # the tuning's own check of the pair (a proximal selection needs scheme a)
        changed = micro.Tuning(**options).changed()
    except ValueError as exc:
        raise src.error(f"method.{exc}", "method", "selection", index) from None
    method = Method(kind, tuning=tuple(changed.items()))
    return GridMethod(method, _max_blocks(entry, "method", index, src))


def _user(entry: dict[str, Any], index: int, src: TomlSource[GridError]) -> UserModel:
    """A user's model, its ``function`` checked in form but not imported yet (:func:`_with_user_models`
    imports it once the whole grid is checked)."""
    if "function" not in entry:
        raise src.error("method.function is missing: a user model needs 'module:function'", "method", None, index)
    target = entry["function"]
    try:
        check_target(target)
    except ValueError as exc:
        raise src.error(f"method.{exc}", "method", "function", index) from None
    name = entry.get("name", target.partition(":")[2].strip())
    try:
        return UserModel(name, _not_imported, target.strip())
    except ValueError as exc:
        raise src.error(f"method.{exc}", "method", "name", index) from None


def _not_imported(*args: object) -> object:
    """A user model's function until its module is imported (never called: a grid is returned with its
    models imported)."""
    raise RuntimeError("a user model called before its module was imported")  # pragma: no cover
