"""``--tuning KEY=VALUE``: the research knobs of the non-associative method (:class:`micro.Tuning`), read by
each knob's type, numbers by the suite's rule (:mod:`comparison.utilities.numbers`)."""

from __future__ import annotations

import types
import typing
from typing import TYPE_CHECKING, Any

from comparison.cli.options import SOLVER_COUNT_MAX, UsageError
from comparison.utilities import numbers

if TYPE_CHECKING:  # pragma: no cover - typing only
    from micro import Tuning


def parse_tuning(items: list[str]) -> Tuning:
    """The :class:`micro.Tuning` of ``--tuning KEY=VALUE`` items (values read by the knob's type:
    ``true``/``false``, numbers, ``none`` where a knob may be unset).

    Raises:
        UsageError: one line naming the key (an unknown key lists the knobs).
    """
    import micro
    from micro.nonassociative import TUNING_KNOBS

    hints = typing.get_type_hints(micro.Tuning)
    values: dict[str, Any] = {}
    for item in items:
        key, eq, text = item.partition("=")
        key = key.strip().replace("-", "_")
        if not eq or not key:
            raise UsageError(f"--tuning must be KEY=VALUE, got {item!r}")
        if key not in TUNING_KNOBS:
            raise UsageError(f"--tuning {key}: unknown knob; the knobs are {', '.join(TUNING_KNOBS)}")
        values[key] = _knob_value(key, text.strip(), hints[key])
    try:
        return micro.Tuning(**values)
    except ValueError as exc:
        raise UsageError(f"--tuning {exc}") from None


def _knob_value(key: str, text: str, hint: Any) -> Any:
    """``text`` read as the knob ``key`` of type ``hint`` (its annotation, resolved): a choice among a
    ``Literal``'s values, a bool, an int, a float, ``none``/``auto`` where the knob may be ``None``.

    The type is read from the annotation's structure, not from its text (``"int" in "Literal['interior', ...]"``
    once made ``start`` and ``global_bounds`` integers that could not be set)."""
    union = typing.get_origin(hint) in (typing.Union, types.UnionType)
    kinds = typing.get_args(hint) if union else (hint,)
    optional = type(None) in kinds
    (kind,) = (k for k in kinds if k is not type(None))
    if optional and text.lower() in ("none", "auto"):
        return None
    if typing.get_origin(kind) is typing.Literal:
        choices = typing.get_args(kind)
        if text not in choices:
            more = ", none" if optional else ""
            raise UsageError(f"--tuning {key} must be one of {', '.join(map(str, choices))}{more}, got {text!r}")
        return text
    if kind is bool:
        flags = {**dict.fromkeys(("true", "yes", "on", "1"), True), **dict.fromkeys(("false", "no", "off", "0"), False)}
        if text.lower() not in flags:
            raise UsageError(f"--tuning {key} must be true or false, got {text!r}")
        return flags[text.lower()]
    if kind is int:  # within HiGHS' integers here; the library's check words the knob's own minimum
        try:
            number = numbers.exact(f"--tuning {key}", text)
        except ValueError:
            number = None
        if number is None or number.denominator != 1 or abs(number) > SOLVER_COUNT_MAX:
            raise UsageError(f"--tuning {key} must be an integer of at most {SOLVER_COUNT_MAX:,}, got {text!r}")
        return int(number)
    if kind is float:
        try:
            return float(numbers.exact(f"--tuning {key}", text))
        except (ValueError, OverflowError):
            raise UsageError(f"--tuning {key} must be a number ({numbers.NUMBER_RULE}), got {text!r}") from None
    return text
