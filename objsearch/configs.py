"""One base for the frozen dataclasses stored as JSON (training configs, model configs, house
specs): ``JsonConfig``. It gives them one ``to_json`` / ``from_json`` / ``save`` / ``load`` /
``with_overrides`` and one rule on keys.

The rule:

- ``to_json()`` returns JSON-ready data (a dict: nested dataclasses as dicts, tuples as
  lists); JSON text exists only at the file edge (``to_json_text``, ``save``).
- ``from_json(data)`` refuses unknown keys with a ``UserError`` naming the key, the class,
  the file and the fix. A key missing from the data takes the field's default (an older file
  written before the field existed); a missing field without a default is an error. Values
  must have the field's type (an int is accepted for a float); lists become tuples.
- Older files: a renamed or removed field goes into the class's ``LEGACY_KEYS`` table (old
  key -> new key, or ``None``: removed, ignored on read); a change that a table cannot say
  overrides the ``upgrade(data)`` hook, which sees the raw dict before the check.

Also here: ``--set KEY=VALUE`` parsing (``typed_field``, ``apply_overrides``) and range checks.
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import json
import os
import types
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import Any, ClassVar, TypeVar

from objsearch.errors import UserError
from objsearch.fileio import atomic_write

TRUE, FALSE = ("1", "true", "yes"), ("0", "false", "no")
_KIND_NAMES = {int: "an int", float: "a float", bool: "a bool (true/false, 1/0, yes/no)", str: "a str"}

C = TypeVar("C", bound="JsonConfig")


class JsonConfig:
    """Mixin for a frozen dataclass stored as JSON (see the module docstring for the rule).

    Class attributes a subclass may set:

    - ``DESCRIPTION``: what the data is, for errors (``"a house spec"``); default: the class name.
    - ``LEGACY_KEYS``: ``{old key: new key or None}`` for files written by older versions.
    - ``JSON_SORT_KEYS``: sort keys in ``to_json_text`` (default: field order).
    """

    DESCRIPTION: ClassVar[str] = ""
    LEGACY_KEYS: ClassVar[Mapping[str, str | None]] = {}
    JSON_SORT_KEYS: ClassVar[bool] = False

    @classmethod
    def describe(cls) -> str:
        """``"a house spec (HouseSpec)"``: what errors call the data."""
        return f"{cls.DESCRIPTION} ({cls.__name__})" if cls.DESCRIPTION else f"a {cls.__name__}"

    def to_json(self) -> dict:
        """The config as JSON-ready data: a dict in field order, tuples as lists."""
        return to_data(self)

    def to_json_text(self) -> str:
        """The JSON text ``save`` writes: one-space indent, a trailing newline."""
        return json.dumps(self.to_json(), indent=1, sort_keys=self.JSON_SORT_KEYS) + "\n"

    @classmethod
    def upgrade(cls, data: dict) -> dict:
        """The legacy hook: ``data`` as written by an older version -> data of this version.
        The default applies ``LEGACY_KEYS``; override it (calling ``super().upgrade``) for
        changes a table cannot say. Raise ``UserError`` for data that cannot be read."""
        for old, new in cls.LEGACY_KEYS.items():
            if old not in data:
                continue
            value = data.pop(old)
            if new is None:
                continue
            if new in data:
                raise UserError(
                    f"both {old!r} and {new!r} are set, but {old!r} is the old name of {new!r}; keep only {new!r}"
                )
            data[new] = value
        return data

    @classmethod
    def from_json(cls: type[C], data: Any, source: str | os.PathLike | None = None) -> C:
        """The config from ``to_json()`` data. ``source`` (a file, ``checkpoint X``) names
        the data in errors. Unknown keys, missing required keys, values of the wrong type and
        values ``__post_init__`` refuses are a ``UserError``."""
        try:
            return from_data(cls, data)
        except UserError as err:
            where = f"{source}" if source is not None else "the data"
            raise UserError(f"{where} is not {cls.describe()}: {err}") from None

    def save(self, path: str | os.PathLike) -> None:
        """Write ``to_json_text()`` to ``path`` atomically."""
        with atomic_write(path) as f:
            f.write(self.to_json_text())

    @classmethod
    def load(cls: type[C], path: str | os.PathLike) -> C:
        """Read a file written by ``save``; an unreadable or bad file is a ``UserError``."""
        path = Path(path)
        try:
            data = json.loads(path.read_text())
        except OSError as err:
            raise UserError(
                f"cannot read {path} ({err.strerror or err}); pass a {path.name} written by objsearch"
            ) from None
        except ValueError as err:
            raise UserError(f"{path} is not JSON ({err}); pass a {path.name} written by objsearch") from None
        return cls.from_json(data, source=path)

    def with_overrides(self: C, overrides: Mapping[str, str]) -> C:
        """A copy with fields set from ``KEY=VALUE`` strings (``--set``), typed like the fields;
        ``GROUP.KEY`` sets a field of a nested config (``model.stem=16``)."""
        return apply_overrides(self, overrides)


def to_data(value: Any) -> Any:
    """JSON-ready data: dataclasses -> dicts (field order), tuples and lists -> lists."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: to_data(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, (list, tuple)):
        return [to_data(v) for v in value]
    if isinstance(value, dict):
        return {k: to_data(v) for k, v in value.items()}
    return value


def from_data(cls: type, data: Any, where: str = "") -> Any:
    """An instance of the dataclass ``cls`` from ``to_data`` data, by the rule of the module
    docstring; nested dataclasses and tuples are built from their type hints. ``where`` is the
    path of ``data`` in the enclosing data (``rooms[0]``), for errors."""
    at = f" at {where}" if where else ""
    if not isinstance(data, Mapping):
        raise UserError(f"expected a JSON object{at} ({cls.__name__}), got {type(data).__name__}")
    data = dict(data)
    if isinstance(cls, type) and issubclass(cls, JsonConfig):
        data = cls.upgrade(data)
    known = {f.name: f for f in dataclasses.fields(cls) if f.init}
    unknown = [key for key in data if key not in known]
    if unknown:
        guess = difflib.get_close_matches(str(unknown[0]), list(known), n=1)
        hint = f" (did you mean {guess[0]!r}?)" if guess else ""
        legacy = (
            f" (a field renamed or removed since belongs in {cls.__name__}.LEGACY_KEYS)"
            if issubclass(cls, JsonConfig)
            else ""
        )
        raise UserError(
            f"unknown key{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))}{at}: {cls.__name__} "
            f"has no such field{hint}; delete it if it is a mistake, or read the file with the objsearch "
            f"version that wrote it{legacy}"
        )
    missing = [
        name
        for name, f in known.items()
        if name not in data and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
    ]
    if missing:
        raise UserError(
            f"missing key{'s' if len(missing) > 1 else ''} {', '.join(map(repr, missing))}{at} "
            f"({cls.__name__} needs {'them' if len(missing) > 1 else 'it'}); the file is incomplete: "
            "write it again with objsearch"
        )
    hints = _hints(cls)
    return cls(
        **{key: _decode(hints.get(key, Any), value, f"{where}.{key}" if where else key) for key, value in data.items()}
    )


@functools.cache
def _hints(cls: type) -> dict[str, Any]:
    return typing.get_type_hints(cls)


def _decode(hint: Any, value: Any, where: str) -> Any:
    """``value`` (JSON data) checked against and converted to the type ``hint``."""
    origin = typing.get_origin(hint)
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        return value if isinstance(value, hint) else from_data(hint, value, where)
    if origin in (typing.Union, types.UnionType):
        args = typing.get_args(hint)
        if value is None and type(None) in args:
            return None
        rest = [a for a in args if a is not type(None)]
        return _decode(rest[0], value, where) if len(rest) == 1 else value
    if origin is tuple or hint is tuple:
        if not isinstance(value, (list, tuple)):
            raise UserError(f"{where} must be a list, got {value!r}")
        args = typing.get_args(hint)
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_decode(args[0], v, f"{where}[{i}]") for i, v in enumerate(value))
        if args and len(args) != len(value):
            raise UserError(f"{where} must be a list of {len(args)}, got {value!r}")
        return (
            tuple(_decode(a, v, f"{where}[{i}]") for i, (a, v) in enumerate(zip(args, value))) if args else tuple(value)
        )
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise UserError(f"{where} must be a number, got {value!r}")
        return value
    if hint is int and (isinstance(value, bool) or not isinstance(value, int)):
        raise UserError(f"{where} must be an integer, got {value!r}")
    if hint in (str, bool, dict, list) and not isinstance(value, hint):
        raise UserError(f"{where} must be a {hint.__name__}, got {value!r}")
    if origin in (dict, list) and not isinstance(value, origin):
        raise UserError(f"{where} must be a {origin.__name__}, got {value!r}")
    return value


def _field_kind(config, key: str) -> Any:
    """The type of ``config``'s field ``key``: its hint, Optional stripped; else the value's type."""
    hint = _hints(type(config)).get(key)
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        rest = [a for a in typing.get_args(hint) if a is not type(None)]
        hint = rest[0] if len(rest) == 1 else None
    return hint if hint is not None else type(getattr(config, key))


def typed_field(config, key: str, text: str, prefix: str = ""):
    """``text`` converted to the type of ``config``'s field ``key`` (bool, int, float, str,
    or a tuple of ints written ``1,2,3``); nested configs are set through their own fields."""
    names = [f.name for f in dataclasses.fields(config)]
    if key not in names:
        guess = difflib.get_close_matches(key, names, n=1)
        hint = f" (did you mean {prefix}{guess[0]}?)" if guess else ""
        raise UserError(
            f"unknown config field {prefix + key!r} of {type(config).__name__}{hint}; "
            f"fields: {', '.join(prefix + k for k in sorted(names))}"
        )
    if dataclasses.is_dataclass(getattr(config, key)):
        raise UserError(f"config field {prefix}{key} is a group of fields; set them as {prefix}{key}.FIELD=VALUE")
    kind = _field_kind(config, key)
    origin, args = typing.get_origin(kind), typing.get_args(kind)
    try:
        if kind is bool:
            if text.lower() not in TRUE + FALSE:
                raise ValueError(text)
            return text.lower() in TRUE
        if kind is tuple or origin is tuple:
            item = args[0] if args and args[0] in (int, float, str) else int
            return tuple(item(v) for v in text.split(",")) if text else ()
        return kind(text)
    except (TypeError, ValueError):
        if origin is tuple or kind is tuple:
            name = "a comma-separated list (1,2,3)"
        else:
            name = _KIND_NAMES.get(kind, f"a {getattr(kind, '__name__', kind)}")
        raise UserError(f"config field {prefix}{key} takes {name}, got {text!r}") from None


def apply_overrides(config, overrides: Mapping[str, str], prefix: str = ""):
    """A copy of the dataclass ``config`` with fields set from ``KEY=VALUE`` strings, typed
    by ``typed_field``; ``GROUP.KEY`` reaches a nested dataclass field. Unknown fields and
    values of the wrong type are a ``UserError``; so is a value ``__post_init__`` refuses."""
    changes, nested = {}, {}
    groups = {f.name for f in dataclasses.fields(config) if dataclasses.is_dataclass(getattr(config, f.name))}
    for key, text in overrides.items():
        head, dot, rest = key.partition(".")
        if dot and head in groups:
            nested.setdefault(head, {})[rest] = text
        else:
            changes[key] = typed_field(config, key, text, prefix)
    for head, sub in nested.items():
        changes[head] = apply_overrides(getattr(config, head), sub, f"{prefix}{head}.")
    return dataclasses.replace(config, **changes)


def require_at_least(config, names, minimum: int) -> None:
    """Raise ``UserError`` naming the first of ``names`` whose value is below ``minimum``."""
    for name in names:
        if getattr(config, name) < minimum:
            raise UserError(f"config field {name} must be >= {minimum}, got {getattr(config, name)}")
