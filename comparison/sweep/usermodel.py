"""A user's own macro model as a column of a sweep: ``module:function(t, m, rows, f, p, storeys) -> λ``.

The model takes the paper's Table 4 parameters of a wall, as the pytest
plugin's walls carry them (``t = H/L``, ``m = b/l``, ``rows``, ``f``, ``p``,
``storeys``; a float, a float, an int, a float, a float, an int), and returns
its load factor, a real number (what :func:`~comparison.numbers.received_number`
accepts, as ``xcheck_table.add`` does). A grid file names it
``module:function`` (``function`` may be a dotted path inside the module); the
module is imported with the grid file's folder first on the import path, so a
``my_model.py`` beside the grid needs no install. The Python API takes the
callable itself (:class:`UserModel`).

The model runs in the sweep's own process, once per wall (a cluster's workers
need not have it), and its cell records what happened: ``optimal`` with the
value, ``failed`` for a value that is not finite (NaN, infinite), ``error`` when
it raised or returned something else than a number (the message says what).
"""

from __future__ import annotations

import contextlib
import importlib
import math
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

from comparison.names import own_method
from comparison.numbers import received_number
from comparison.runner.executor.base import describe


@dataclass(frozen=True)
class UserModel:
    """A user's macro model: a callable ``(t, m, rows, f, p, storeys) -> λ`` under a name.

    Attributes:
        name: the column's name in the table, the page and its figures (:func:`comparison.names.own_method`:
            ``"macro"`` and the micro methods' kinds and labels are taken).
        function: the callable.
        target: where it comes from, ``module:function`` (default: the callable's module and name).
    """

    name: str
    function: Callable[..., object] = field(compare=False)
    target: str = ""
    kind: ClassVar[str] = "user"

    def __post_init__(self) -> None:
        own_method("name", self.name)  # the suite's rule for names (comparison.names)
        if not callable(self.function):
            raise TypeError(f"{self.name}: function must be callable, got {self.function!r}")
        if not self.target:
            module = getattr(self.function, "__module__", "?")
            object.__setattr__(self, "target", f"{module}:{getattr(self.function, '__qualname__', '?')}")

    @property
    def label(self) -> str:
        """The column's name."""
        return self.name

    def key(self) -> dict[str, Any]:
        """A JSON-ready description (for the sweep's metadata)."""
        return {"kind": self.kind, "name": self.name, "function": self.target}

    def evaluate(self, t: float, m: float, rows: int, f: float, p: float, storeys: int,
                 where: str = "") -> tuple[float, str, str, float]:
        """The model on one wall: ``(λ, status, message, seconds)`` (module docstring for the statuses).

        ``where`` names the wall in the message of a value that is not a number.
        """
        t0 = time.perf_counter()
        try:
            value = self.function(t, m, rows, f, p, storeys)
        except Exception as exc:  # noqa: BLE001 - the cell's outcome; the sweep goes on
            return math.nan, "error", describe(exc), time.perf_counter() - t0
        seconds = time.perf_counter() - t0
        try:
            lam = received_number(f"{where or 'wall'} / {self.name}", value)
        except TypeError as exc:
            return math.nan, "error", str(exc), seconds
        if not math.isfinite(lam):
            return lam, "failed", f"the model returned {lam}", seconds
        return lam, "optimal", "", seconds


def resolve(target: str, folder: Path | None = None) -> Callable[..., object]:
    """The callable ``module:function`` names, the module imported with ``folder`` first on the path.

    Raises:
        ValueError: not of the form ``module:function``, a module that cannot be imported (the exception
            it raised, in one line), no such attribute, or not callable.
    """
    module_name, sep, attr = str(target).partition(":")
    if not sep or not module_name.strip() or not attr.strip():
        raise ValueError(f"function must be 'module:function', got {target!r}")
    try:
        with _first_on_path(folder):
            module = importlib.import_module(module_name.strip())
    except Exception as exc:  # noqa: BLE001 - whatever the import raised, one line
        raise ValueError(f"function {target!r}: cannot import {module_name!r} ({describe(exc)})") from None
    obj: object = module
    for part in attr.strip().split("."):
        if not hasattr(obj, part):
            raise ValueError(f"function {target!r}: {module_name} has no {attr.strip()!r}")
        obj = getattr(obj, part)
    if not callable(obj):
        raise ValueError(f"function {target!r} is not callable ({type(obj).__name__})")
    return obj


@contextlib.contextmanager
def _first_on_path(folder: Path | None) -> Iterator[None]:
    """``folder`` first on ``sys.path`` for the duration (nothing for ``None``)."""
    if folder is None:
        yield
        return
    entry = str(Path(folder).resolve())
    sys.path.insert(0, entry)
    try:
        yield
    finally:
        with contextlib.suppress(ValueError):
            sys.path.remove(entry)
