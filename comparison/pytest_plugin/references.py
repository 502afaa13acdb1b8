"""The reference values the plugin ships, and the assertion helper that checks a value against one.

``references.json`` (package data, written by ``xcheck references``, see
:mod:`comparison.pytest_plugin.generate`) holds one cell per (case, method,
quantity): its value, its tolerance and where it comes from. Methods:

* ``macro``, ``micro-assoc``, ``micro-nonassoc``: this package's results
  (for ``micro-nonassoc`` the lowest certified collapse state, the value to quote; beside it the
  iterated LP's own ``iterated_load_factor`` and the ends of its mechanism band, ``band_min`` and
  ``band_max``);
* ``paper`` and ``orduna-micro``, ``orduna-macro``, ``debuhan-defelice``,
  ``speranza``: the values Argiento, Maione & Casapulla (2018) publish, with
  half a unit of their last printed decimal as tolerance.

A cell whose method gave no number on that wall (a micro wall that cannot be
built, a sequence that did not converge, a wall the report leaves out) is kept
with ``value`` ``None`` and its status, so that a test asking for it learns why.
"""

from __future__ import annotations

import json
import math
import numbers
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import asdict, dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from comparison.domain.cases import PaperCase, case
from comparison.utilities.numbers import received_number

#: The data file inside the package.
DATA_FILE = "references.json"

#: The cell every method has.
LOAD_FACTOR = "load_factor"

#: This package's methods, which can also be computed for walls without shipped cells.
COMPUTABLE = ("macro", "micro-assoc", "micro-nonassoc")


def shipped() -> Any:
    """The references file shipped with the package (a path-like resource)."""
    return resources.files("comparison.pytest_plugin").joinpath(DATA_FILE)


def case_label(wall: PaperCase | str) -> str:
    """The label a case is stored under (``"Ref"``, ``"Set 12"``) from a case or a name (``"12"``, ``"Set 12"``).

    A name that is not one of the paper's cases is returned as it is (a user's wall).

    Raises:
        TypeError: ``wall`` is neither a case nor a string (``None``, ``12``).
    """
    if isinstance(wall, PaperCase):
        return wall.label
    if not isinstance(wall, str):
        raise TypeError(f"wall must be a case (PaperCase) or a name such as 'Set 12', got {wall!r} "
                        f"({type(wall).__name__})")
    try:
        return case(wall).label
    except ValueError:
        return wall


@dataclass(frozen=True)
class Reference:
    """One reference cell.

    Attributes:
        case: the case's label (``"Set 12"``).
        method: who computed or published it (``"micro-nonassoc"``, ``"paper"``, ...).
        cell: the quantity (``"load_factor"``, ``"alpha_c_deg"``, ``"band_min"``, ...).
        value: the value (``None``: the method gave none on this wall, see ``status``).
        tolerance: how precisely the value is known (absolute; ``None`` with ``value``).
        source: where the value comes from (table, solver, settings).
        status: the method's status on this wall (``"converged"``, ``"cycling"``, ``"published"``, ...).
    """

    case: str
    method: str
    cell: str
    value: float | None
    tolerance: float | None
    source: str
    status: str = ""

    @property
    def name(self) -> str:
        """``"Set 12 / micro-nonassoc / load_factor"``."""
        return f"{self.case} / {self.method} / {self.cell}"

    def allowed(self, rel: float = 0.0, abs: float = 0.0) -> float:
        """The half-width a value may be off: the reference's tolerance, plus ``rel`` of its value, plus ``abs``.

        Raises:
            MissingReference: the cell has no value.
            TypeError, ValueError: ``rel`` or ``abs`` is not a finite number >= 0 (:func:`widening`).
        """
        rel, abs = widening("rel", rel), widening("abs", abs)
        if self.value is None or self.tolerance is None:
            raise MissingReference(f"{self.name}: no reference value ({self.status or 'not computed'})")
        return self.tolerance + rel * math.fabs(self.value) + abs


def _cell(where: str, raw: object) -> Reference:
    """The reference cell ``raw`` of a references file, checked (see :meth:`References.load`)."""
    if not isinstance(raw, dict):
        raise BadReferences(f"{where}: a cell must be an object, got {raw!r}"[:300])
    try:
        ref = Reference(**raw)
    except TypeError as exc:
        raise BadReferences(f"{where}: {exc}".replace("Reference.__init__() ", "")) from None
    for key in ("case", "method", "cell", "source", "status"):
        if not isinstance(getattr(ref, key), str):
            raise BadReferences(f"{where}: {key} must be a string, got {getattr(ref, key)!r}")
    where = f"{where} ({ref.name})"
    value, tolerance = ref.value, ref.tolerance
    if value is None or tolerance is None:
        if value is not None or tolerance is not None:
            raise BadReferences(f"{where}: value and tolerance are both numbers or both null, got {value!r} "
                                f"and {tolerance!r}")
        return ref
    for key, x in (("value", value), ("tolerance", tolerance)):
        if isinstance(x, bool) or not isinstance(x, numbers.Real) or not math.isfinite(x):
            raise BadReferences(f"{where}: {key} must be a finite number, got {x!r}")
    if not 0.0 <= tolerance <= math.fabs(value):
        raise BadReferences(f"{where}: tolerance must be a number from 0 to the value's magnitude "
                            f"({math.fabs(value)!r}), got {tolerance!r}: a wider one passes any value near it")
    return ref


def widening(name: str, value: object) -> float:
    """``rel`` or ``abs`` of :meth:`References.check` as a float: a finite number >= 0.

    ``NaN`` would make every comparison false and pass any value; a string (``"5%"``) or ``None`` is a bug of
    the test, named here.

    Raises:
        TypeError: not a number (``"5%"``, ``None``, ``True``).
        ValueError: NaN, infinite or negative.
    """
    hint = " (0.05 for 5 %)" if name == "rel" else ""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number >= 0{hint}, got {value!r} ({type(value).__name__})")
    try:
        x = float(value)
    except OverflowError:  # an int beyond the doubles
        x = math.inf
    if not math.isfinite(x) or x < 0.0:
        raise ValueError(f"{name} must be a finite number >= 0{hint}, got {value!r}")
    return x


def checked_name(what: str, value: object) -> str:
    """A method or cell name: a string (``None`` or a number is a bug of the test)."""
    if not isinstance(value, str):
        raise TypeError(f"{what} must be a string such as {'load_factor' if what == 'cell' else 'paper'!r}, "
                        f"got {value!r} ({type(value).__name__})")
    return value


class BadReferences(ValueError):
    """A references file that cannot be used (the message names the file and the cell)."""


class MissingReference(LookupError):
    """A (case, method, cell) without a reference value."""


class ReferenceMismatch(AssertionError):
    """A value outside its reference's interval; the message names the case, the method and the cell."""


def _fmt(x: float) -> str:
    return f"{x:.4f}" if 1e-4 <= math.fabs(x) < 1e4 else f"{x:.3e}"


class References:
    """The shipped reference cells, looked up by case, method and cell.

    Args:
        cells: the reference cells.
        meta: how they were made (versions, tolerance rules).
    """

    def __init__(self, cells: Iterable[Reference], meta: Mapping[str, Any] | None = None) -> None:
        self._cells = {(c.case, c.method, c.cell): c for c in cells}
        self.meta: Mapping[str, Any] = meta or {}

    @classmethod
    def load(cls, path: str | Path | None = None) -> References:
        """The references of ``path``, by default the ones shipped with the package.

        Raises:
            BadReferences: the file cannot be read, is not JSON of the form :meth:`to_json` writes, or holds
                a cell no check could honestly use (a NaN, infinite or negative tolerance, or one wider than
                its value, which would pass any value near it); the message names the file and the cell.
        """
        source = shipped() if path is None else Path(path)
        try:
            text = source.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise BadReferences(f"{source}: cannot be read ({getattr(exc, 'strerror', None) or exc})") from None
        try:
            data = json.loads(text)
        except (ValueError, RecursionError) as exc:
            raise BadReferences(f"{source}: not JSON ({exc})" if text.strip() else f"{source}: empty") from None
        cells = data.get("cells") if isinstance(data, dict) else None
        if not isinstance(cells, list) or not cells:
            raise BadReferences(f"{source}: no list of reference cells under 'cells'")
        meta = data.get("meta", {})
        return cls((_cell(f"{source}: cells[{i}]", c) for i, c in enumerate(cells)),
                   meta if isinstance(meta, dict) else {})

    def extended(self, cells: Iterable[Reference]) -> References:
        """These references and ``cells`` (which replace cells of the same case, method and cell)."""
        return References([*self, *cells], self.meta)

    def __iter__(self) -> Iterator[Reference]:
        return iter(self._cells.values())

    def __len__(self) -> int:
        return len(self._cells)

    def all_methods(self) -> tuple[str, ...]:
        """Every method with a cell, in the order first met."""
        return tuple(dict.fromkeys(m for (_c, m, _cell) in self._cells))

    def methods(self, wall: PaperCase | str) -> tuple[str, ...]:
        """The methods with a load-factor cell on ``wall`` (valued or not)."""
        label = case_label(wall)
        return tuple(m for (c, m, cell) in self._cells if c == label and cell == LOAD_FACTOR)

    def get(self, wall: PaperCase | str, method: str, cell: str = LOAD_FACTOR) -> Reference:
        """The cell of ``method`` on ``wall``.

        Raises:
            MissingReference: no such cell (the message lists the methods that ``wall`` has).
        """
        __tracebackhide__ = True  # as in check()
        label = case_label(wall)
        method, cell = checked_name("method", method), checked_name("cell", cell)
        try:
            return self._cells[(label, method, cell)]
        except KeyError:
            have = ", ".join(self.methods(label)) or "none: not one of the paper's cases"
            raise MissingReference(f"{label} / {method} / {cell}: no such reference (methods: {have})") from None

    def value(self, wall: PaperCase | str, method: str, cell: str = LOAD_FACTOR) -> float | None:
        """The value of a cell (``None`` when the method gave none on that wall)."""
        __tracebackhide__ = True  # as in check()
        return self.get(wall, method, cell).value

    def check(
        self,
        wall: PaperCase | str,
        method: str,
        value: float,
        cell: str = LOAD_FACTOR,
        *,
        rel: float = 0.0,
        abs: float = 0.0,
    ) -> Reference:
        """Assert that ``value`` lies within the reference's tolerance, widened by ``rel`` and ``abs``.

        Args:
            wall: the case (``PaperCase`` or a name such as ``"Set 12"``).
            method: the reference to check against (``"micro-nonassoc"``, ``"paper"``, ...).
            value: the value to check (e.g. your model's load factor).
            cell: the quantity.
            rel: allowed relative difference on top of the reference's own tolerance
                (how far your model may be from the reference: 0.05 for 5 %); a finite number >= 0.
            abs: allowed absolute difference on top of it; a finite number >= 0.

        Returns:
            The reference cell.

        Raises:
            TypeError: ``value`` is not a number (``None``, a string), naming the case, the method and
                what was received (:func:`received_number`); ``wall``, ``method``, ``cell``, ``rel`` or
                ``abs`` of the wrong type (``rel="5%"``), naming it.
            ValueError: ``rel`` or ``abs`` NaN, infinite or negative (a NaN would pass any value).
            ReferenceMismatch: ``value`` is outside, e.g. for 0.25 with ``rel=0.02``: ``Set 14 /
                micro-nonassoc / load_factor: 0.2500 outside 0.2658 ± 0.0066 (lowest certified collapse state
                (the value to quote), ...; reference tolerance 0.0013 + 2 % of the reference)`` (the numbers
                those of ``references.json``, held to it by a test). Under pytest the failure shows the
                test's line and this message, not this function's source (``__tracebackhide__``).
            MissingReference: there is no reference value for that cell.
        """
        __tracebackhide__ = True  # a failure shows the test's line and this message, not this function's source
        rel, abs = widening("rel", rel), widening("abs", abs)
        label, method, cell = case_label(wall), checked_name("method", method), checked_name("cell", cell)
        value = received_number(f"{label} / {method} / {cell}: xcheck_references.check", value)
        ref = self.get(wall, method, cell)
        allowed = ref.allowed(rel, abs)
        assert ref.value is not None  # allowed() raised otherwise
        if not math.isfinite(value) or math.fabs(value - ref.value) > allowed:
            widened = "" if rel == 0 and abs == 0 else f"; reference tolerance {_fmt(ref.tolerance or 0.0)}"
            widened += f" + {100 * rel:g} % of the reference" if rel else ""
            widened += f" + {_fmt(abs)}" if abs else ""
            raise ReferenceMismatch(
                f"{ref.name}: {_fmt(value)} outside {_fmt(ref.value)} ± {_fmt(allowed)} ({ref.source}{widened})"
            )
        return ref

    def to_json(self) -> str:
        """The references as ``references.json`` stores them (one cell per line)."""
        lines = [json.dumps(asdict(c), ensure_ascii=False) for c in self._cells.values()]
        meta = json.dumps(self.meta, indent=1, ensure_ascii=False)
        return '{\n"meta": ' + meta + ',\n"cells": [\n' + ",\n".join(lines) + "\n]}\n"
