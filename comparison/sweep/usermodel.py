"""A user's own macro model as a column of a sweep: ``module:function(t, m, rows, f, p, storeys) -> λ``.

The model takes the paper's Table 4 parameters of a wall, as the pytest
plugin's walls carry them (``t = H/L``, ``m = b/l``, ``rows``, ``f``, ``p``,
``storeys``; a float, a float, an int, a float, a float, an int), and returns
its load factor, a real number (what :func:`~comparison.utilities.numbers.received_number`
accepts, as ``xcheck_table.add`` does). A grid file names it
``module:function`` (``function`` may be a dotted path inside the module); the
module is imported with the grid file's folder first on the import path, so a
``my_model.py`` beside the grid needs no install. The Python API takes the
callable itself (:class:`UserModel`).

A user model is Python code, run with the rights of whoever runs the sweep,
like a ``conftest.py``: its module's top-level code runs when the grid is read
(after the whole grid has been checked), the function once per wall. Run only
grids whose models you trust.

The model runs once per wall in a process of its own, forked from the sweep's
(:mod:`comparison.sweep.isolation`: a model that ends, forks or closes its
descriptors cannot end the sweep; a cluster's workers need not have it), and
its cell records what happened: ``optimal`` with the
value; ``failed`` for a number that is not a load factor (zero, negative, NaN,
infinite, or above :data:`MAX_LOAD_FACTOR`, ``10**400`` included); ``error``
when it raised, called ``sys.exit`` or returned something else than a number
(the message says what). No model can end the sweep (only Ctrl-C does): the
other cells and the page are written. What the model prints goes to standard
error, never to standard output (which carries the paths written, alone under
``-q``), and a model that changes the working directory has it restored after
its call (the sweep's paths are absolute before any user code runs anyway).
"""

from __future__ import annotations

import contextlib
import importlib
import math
import os
import re
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

from comparison.runner.executor.base import describe
from comparison.utilities.names import own_method
from comparison.utilities.numbers import received_number

#: The largest load factor a user model may return. A load factor is the horizontal load over the wall's
#: weight, and friction caps it near ``f`` (the whole wall sliding on its base); a value a million times
#: the weight is a mistake of units or an overflow, not a result, and would swamp every difference the
#: page reports. Zero and negative values are refused too: a wall under its own weight resists some load.
MAX_LOAD_FACTOR = 1e6

@dataclass(frozen=True)
class UserModel:
    """A user's macro model: a callable ``(t, m, rows, f, p, storeys) -> λ`` under a name.

    Attributes:
        name: the column's name in the table, the page and its figures (:func:`comparison.utilities.names.own_method`:
            ``"macro"`` and the micro methods' kinds and labels are taken).
        function: the callable.
        target: where it comes from, ``module:function`` (default: the callable's module and name).
    """

    name: str
    function: Callable[..., object] = field(compare=False)
    target: str = ""
    kind: ClassVar[str] = "user"

    def __post_init__(self) -> None:
        own_method("name", self.name)  # the suite's rule for names (comparison.utilities.names)
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
            with contained():
                value = self.function(t, m, rows, f, p, storeys)
        except KeyboardInterrupt:
            raise
        except BaseException as exc:  # noqa: BLE001 - sys.exit and BaseException included: the sweep goes on
            return math.nan, "error", _what_ended(exc), time.perf_counter() - t0
        seconds = time.perf_counter() - t0
        try:
            lam = received_number(f"{where or 'wall'} / {self.name}", value)
        except TypeError as exc:
            return math.nan, "error", str(exc), seconds
        if not (math.isfinite(lam) and 0 < lam <= MAX_LOAD_FACTOR):
            rule = f"a positive number at most {MAX_LOAD_FACTOR:g}"
            return math.nan, "failed", f"the model returned {_shown(value)}, not a load factor ({rule})", seconds
        return lam, "optimal", "", seconds


def _shown(value: object) -> str:
    """A returned number as the message quotes it (an integer of hundreds of digits by its size)."""
    text = repr(value)
    if isinstance(value, int) and len(text) > 24:
        return f"an integer of {len(text.lstrip('-'))} digits ({text[:8]}...)"
    return text


def _what_ended(exc: BaseException) -> str:
    """A user model's exception in one line; ``sys.exit`` named as such."""
    if isinstance(exc, SystemExit):
        return f"the model called sys.exit({exc.code!r}); a model returns its load factor"
    return describe(exc)


@contextlib.contextmanager
def contained() -> Iterator[None]:
    """Around user code: what it prints goes to standard error, and the working directory it may change
    is restored."""
    try:
        cwd: str | None = os.getcwd()
    except OSError:  # the working directory was removed: nothing to restore
        cwd = None
    try:
        with contextlib.redirect_stdout(sys.stderr):
            yield
    finally:
        if cwd is not None:
            with contextlib.suppress(OSError):
                if os.getcwd() != cwd:
                    os.chdir(cwd)


#: What ``module:function`` may be: a dotted module name, a colon, a dotted attribute path.
_DOTTED = r"[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*"
TARGET_PATTERN = re.compile(rf"\s*(?P<module>{_DOTTED})\s*:\s*(?P<attr>{_DOTTED})\s*")


def check_target(target: object) -> tuple[str, str, str]:
    """``(module, ":", function)`` of a ``module:function`` text, checked in form only (nothing imported).

    Raises:
        ValueError: not a text of Python names of that form.
    """
    match = TARGET_PATTERN.fullmatch(target) if isinstance(target, str) else None
    if match is None:
        raise ValueError(f"function must be 'module:function', got {target!r}")
    return match["module"], ":", match["attr"]


def resolve(target: str, folder: Path | None = None) -> Callable[..., object]:
    """The callable ``module:function`` names, the module imported with ``folder`` first on the path.

    Raises:
        ValueError: not of the form ``module:function``, a module that cannot be imported (the exception
            it raised, in one line), no such attribute, or not callable.
    """
    module_name, _, attr = check_target(target)
    try:
        with _first_on_path(folder), contained():
            module = importlib.import_module(module_name.strip())
    except KeyboardInterrupt:
        raise
    except BaseException as exc:  # noqa: BLE001 - whatever the import raised (sys.exit included), one line
        raise ValueError(f"function {target!r}: cannot import {module_name!r} ({_what_ended(exc)})") from None
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
