"""Names a user gives (a user model's column in a sweep, a wall of a walls file): one rule.

A name heads a Markdown table's column, names a pytest test and is selected by
``--xcheck-cases``, which splits at commas and strips spaces. So a name is a
non-empty text without ``|``, a backtick, line breaks or other control
characters, and without spaces at its ends (``" a"`` could never be selected).
Names that would read as something the suite already names are refused where
they would be mistaken for it: a user model named like a built-in method
(:data:`BUILT_IN`, or one of their labels such as ``"micro-assoc (clarabel)"``),
a user's wall named like a paper case or table (checked in
:mod:`comparison.pytest_plugin.walls`), and a name given twice.
"""

from __future__ import annotations

import re

#: The kinds of the built-in methods (:mod:`comparison.runner.methods`); a method's label begins with its kind
#: (``"micro-assoc (clarabel)"``).
BUILT_IN = ("macro", "micro-assoc", "micro-nonassoc")
#: What a name may not hold: a table's cell separator, a backtick, control characters (line breaks included).
_BAD = re.compile(r"[|`\x00-\x1f\x7f]")
#: The rule, as the messages word it.
NAME_RULE = "a non-empty text without '|', '`', line breaks or spaces at its ends"


def label(what: str, value: object) -> str:
    """``value`` when it is a name under the module's rule.

    Raises:
        ValueError: ``"{what} must be {NAME_RULE}, got ..."``.
    """
    if not isinstance(value, str) or not value.strip() or value != value.strip() or _BAD.search(value):
        raise ValueError(f"{what} must be {NAME_RULE}, got {value!r}")
    return value


def own_method(what: str, value: object) -> str:
    """A user model's name: a :func:`label` that is not a built-in method's (``"macro"``, ``"Micro-Assoc"``,
    ``"micro-nonassoc (scheme b)"``): its column would read as that method's.

    Raises:
        ValueError: naming ``what``.
    """
    name = label(what, value)
    folded = name.casefold()
    if any(folded == kind or folded.startswith(f"{kind} ") for kind in BUILT_IN):
        raise ValueError(f"{what} {name!r} is a built-in method's ({', '.join(BUILT_IN)}); give your model a name "
                         "of its own")
    return name


def first_repeated(names: list[str]) -> tuple[int, int] | None:
    """The indices ``(first, again)`` of the first name given twice (``None``: all distinct)."""
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        if name in seen:
            return seen[name], i
        seen[name] = i
    return None
