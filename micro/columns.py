"""One declaration per field: :func:`column`, the records built from it, their JSON form and their schema.

A record (:class:`FlatRecord`) is a frozen dataclass that reads as a mapping of its fields. Each field is
declared once, by :func:`column`: its type, its description, where the object it is made from holds its
value (a dotted path of attributes, by default the field's own name) and, where its type does not say
enough, its JSON schema. From that one declaration come

* the record made from an object (:func:`record_of`; a path may start at a second object the caller
  names, ``record_of(cls, result, search=g)`` for ``"search.load_factor"``);
* its JSON form (:meth:`FlatRecord.to_dict`: NaN and the infinities as ``null`` by :func:`json_number`,
  the one NaN-to-null conversion of the suite, tuples as lists) and back (:meth:`FlatRecord.from_dict`);
* its JSON schema (:func:`record_schema`): the type a field declares gives its JSON type (``float``: a
  number or null, ``int``: an integer >= 0, ``str``, ``bool``, a tuple: an array, a mapping: an object),
  and a type can carry its own (:class:`JsonType`: :data:`LoadFactor` is ``#/$defs/lambda``, :data:`Band`
  ``#/$defs/band``), never guessed from the field's name.

The records of the micro results are :mod:`micro.records`; the runner's (the macro record among them) are
:mod:`comparison.runner.records`; the nested parts of ``xcheck micro --json`` (the directions, the
iterated LP's history, the descent) are records too.
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from collections.abc import Iterator, Mapping
from dataclasses import MISSING, dataclass
from typing import Annotated, Any, Self

__all__ = ["Band", "FlatRecord", "JsonType", "LoadFactor", "Seconds", "column", "json_number", "record_of",
           "record_schema"]


@dataclass(frozen=True)
class JsonType:
    """The JSON schema a type stands for, carried by ``Annotated`` (:data:`LoadFactor`)."""

    schema: Mapping[str, Any]


#: A load factor: a number, or null when not computed or failed (the schema's ``#/$defs/lambda``).
LoadFactor = Annotated[float, JsonType({"$ref": "#/$defs/lambda"})]
#: ``[min, max]`` of lambda, or null (the schema's ``#/$defs/band``).
Band = Annotated[tuple[float, float] | None, JsonType({"$ref": "#/$defs/band"})]
#: A duration in seconds.
Seconds = Annotated[float, JsonType({"type": "number", "minimum": 0})]


def json_number(value: float) -> float | None:
    """``value`` as a strict JSON number: a float, or ``None`` for NaN and the infinities (JSON has neither).

    The one NaN-to-null conversion of every record and summary of the suite.
    """
    value = float(value)
    return value if math.isfinite(value) else None


def json_value(value: Any) -> Any:
    """``value`` JSON-ready: NaN and infinities -> None, tuples -> lists, mappings' values likewise."""
    if isinstance(value, float):
        return json_number(value)
    if isinstance(value, tuple | list):
        return [json_value(v) for v in value]
    if isinstance(value, Mapping):
        return {k: json_value(v) for k, v in value.items()}
    return value


def _bare(hint: Any) -> Any:
    """``hint`` without its ``Annotated`` wrapper."""
    return typing.get_args(hint)[0] if typing.get_origin(hint) is Annotated else hint


def _in(hint: Any, value: Any) -> Any:
    """The inverse of :func:`json_value` for a field of type ``hint``."""
    hint = _bare(hint)
    args = typing.get_args(hint)
    optional = isinstance(hint, types.UnionType) and type(None) in args
    if value is None:
        return None if optional else (math.nan if hint is float else value)
    if optional:
        hint = _bare(next(a for a in args if a is not type(None)))
        args = typing.get_args(hint)
    if typing.get_origin(hint) is tuple:
        return tuple(_in(args[0], v) for v in value)
    return float(value) if hint is float else value


def column(doc: str, *, source: str | None = None, schema: Mapping[str, Any] | None = None,
           default: Any = MISSING) -> Any:
    """Declare a record field: the one place its description, its source and its schema are written.

    Args:
        doc: what the field means, in a user's words: the JSON schema's description and the docs' line.
        source: where the object a record is made from holds the value, a dotted path of attributes
            (``"sequence.stop_reason"``; one that starts with a name :func:`record_of` was given starts at
            that object; a ``None`` met on the way gives the field's default); ``None``: the field's name.
        schema: JSON schema keys beyond what the field's type gives (an ``enum``, a ``minimum``).
        default: the value when the object has none (a ``None`` on the path).
    """
    metadata = {"doc": doc, "source": source, "schema": dict(schema or {})}
    return dataclasses.field(default=default, metadata=metadata)


def _follow(obj: Any, roots: Mapping[str, Any], f: dataclasses.Field[Any]) -> Any:
    """The value of field ``f``: its source path followed from ``obj`` (or from the root it names), its
    default where the path breaks off at a ``None`` before its end.

    Raises:
        TypeError: the path breaks off and the field has no default.
    """
    path = (f.metadata.get("source") or f.name).split(".")
    value = roots[path[0]] if path[0] in roots else getattr(obj, path[0])
    for name in path[1:]:
        if value is None:
            if f.default is MISSING:
                raise TypeError(f"record field {f.name!r}: {'.'.join(path)!r} breaks off at None and there is "
                                "no default")
            return f.default
        value = getattr(value, name)
    return value


R = typing.TypeVar("R", bound="FlatRecord")


def record_of(cls: type[R], obj: Any, **roots: Any) -> R:
    """The record ``cls`` of ``obj``: every field read along its :func:`column` source, a path that starts
    with a name of ``roots`` starting at that object.

    Raises:
        AttributeError: a source names what ``obj`` does not have.
    """
    return cls(**{f.name: _follow(obj, roots, f) for f in dataclasses.fields(cls)})


def _json_type(name: str, hint: Any) -> dict[str, Any]:
    """The JSON schema the declared type ``hint`` of field ``name`` gives (module docstring)."""
    if typing.get_origin(hint) is Annotated:
        marks = [m for m in hint.__metadata__ if isinstance(m, JsonType)]
        if marks:
            return dict(marks[0].schema)
        hint = _bare(hint)
    if isinstance(hint, types.UnionType):
        inner = [a for a in typing.get_args(hint) if a is not type(None)]
        out = _json_type(name, inner[0])
        kind = out.get("type")
        return {**out, "type": [kind, "null"]} if isinstance(kind, str) else {"anyOf": [out, {"type": "null"}]}
    if hint is float:
        return {"type": ["number", "null"]}
    if hint is bool:
        return {"type": "boolean"}
    if hint is int:
        return {"type": "integer", "minimum": 0}
    if hint is str:
        return {"type": "string"}
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if origin is tuple:
        return {"type": "array", "items": _json_type(name, args[0])}
    if origin in (dict, Mapping):
        return {"type": "object", "additionalProperties": _json_type(name, args[1])}
    raise TypeError(f"record field {name!r}: no JSON type for {hint!r}")


def record_schema(cls: type[FlatRecord], *, inherited: bool = True) -> dict[str, dict[str, Any]]:
    """The JSON schema of each field of record ``cls`` (``inherited=False``: the fields ``cls`` adds to its
    base), from its declared type and its :func:`column` declaration: an object's ``properties``."""
    hints = typing.get_type_hints(cls, include_extras=True)
    base = set() if inherited else {f.name for c in cls.__mro__[1:] if dataclasses.is_dataclass(c)
                                    for f in dataclasses.fields(c)}
    return {f.name: {**_json_type(f.name, hints[f.name]), **f.metadata["schema"], "description": f.metadata["doc"]}
            for f in dataclasses.fields(cls) if f.name not in base}


def object_schema(cls: type[FlatRecord], description: str = "") -> dict[str, Any]:
    """The JSON schema of a record ``cls`` as a nested object: its properties, every one required."""
    out: dict[str, Any] = {"type": "object", "additionalProperties": False}
    if description:
        out["description"] = description
    props = record_schema(cls)
    return {**out, "required": list(props), "properties": props}


@dataclass(frozen=True)
class FlatRecord(Mapping[str, Any]):
    """A record: a frozen dataclass whose fields are :func:`column` declarations, a read-only mapping of
    them (``rec["load_factor"]``, ``dict(rec)``, ``list(rec)`` gives the names in order)."""

    def __getitem__(self, key: str) -> Any:
        """``rec[name]``: the field ``name`` (as in memory: NaN, tuples).

        Raises:
            KeyError: ``name`` is not a field.
        """
        if key not in self.__dataclass_fields__:
            raise KeyError(key)
        return getattr(self, key)

    def __iter__(self) -> Iterator[str]:
        """The field names, in order."""
        return (f.name for f in dataclasses.fields(self))

    def __len__(self) -> int:
        return len(dataclasses.fields(self))

    def to_dict(self) -> dict[str, Any]:
        """The JSON form: plain values (NaN and infinities -> ``None``, tuples -> lists)."""
        return {f.name: json_value(getattr(self, f.name)) for f in dataclasses.fields(self)}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Self:
        """The record :meth:`to_dict` wrote (``None`` -> NaN for numbers).

        Raises:
            KeyError: a field is missing from ``data``.
        """
        hints = typing.get_type_hints(cls, include_extras=True)
        return cls(**{f.name: _in(hints[f.name], data[f.name]) for f in dataclasses.fields(cls)})
