"""Helpers for the frozen-dataclass configs of training runs: ``--set KEY=VALUE`` parsing
and range checks, with errors that name the field."""

from __future__ import annotations

import dataclasses

from objsearch.errors import UserError

TRUE, FALSE = ("1", "true", "yes"), ("0", "false", "no")


def typed_field(config, key: str, text: str, prefix: str = ""):
    """``text`` converted to the type of ``config``'s field ``key`` (bool, int, float, str,
    or a tuple of ints written ``1,2,3``); nested configs are set through their own fields."""
    types = {f.name: type(getattr(config, f.name)) for f in dataclasses.fields(config)}
    if key not in types or dataclasses.is_dataclass(getattr(config, key)):
        raise UserError(f"unknown config field {prefix}{key!r}; fields: {', '.join(prefix + k for k in sorted(types))}")
    kind = types[key]
    try:
        if kind is bool:
            if text.lower() not in TRUE + FALSE:
                raise ValueError(text)
            return text.lower() in TRUE
        if kind is tuple:
            return tuple(int(v) for v in text.split(","))
        return kind(text)
    except ValueError:
        raise UserError(f"config field {prefix}{key} takes a {kind.__name__}, got {text!r}") from None


def require_at_least(config, names, minimum: int) -> None:
    """Raise ``UserError`` naming the first of ``names`` whose value is below ``minimum``."""
    for name in names:
        if getattr(config, name) < minimum:
            raise UserError(f"config field {name} must be >= {minimum}, got {getattr(config, name)}")
