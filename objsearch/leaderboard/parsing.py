"""Reading a submission file (``load_submission``): a results JSON object, within limits on its
size, nesting and numbers, so that a hostile file is refused with a message, never a traceback
or a stall."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from objsearch.errors import UserError

MAX_BYTES = 32 * 2**20  # the largest stored entries (rooms: 4,000 episodes x 5 seeds) are 16 MB
MAX_DEPTH = 16  # a results JSON nests 5 deep (results > episodes > record > task > start)
MAX_DIGITS = 20  # digits of a number: any 64-bit integer; Python's own limit, 4300, is a traceback
_JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"')
_LONG_NUMBER = re.compile(rb"[0-9]{%d,}" % (MAX_DIGITS + 1))
_NOT_BRACKETS = bytes(b for b in range(256) if b not in b"[]{}")
# an exponent of 3 digits or more: the only way a number within MAX_DIGITS can overflow a float
_BIG_EXPONENT = re.compile(rb"[eE][+-]?[0-9]{3,}")


def _past_limits(raw: bytes) -> tuple[str | None, bool]:
    """(what of the JSON text ``raw`` is past ``MAX_DIGITS`` or ``MAX_DEPTH``, if anything;
    whether a number has an exponent large enough to overflow a float): looked for outside its
    strings, before parsing (which would recurse that deep)."""
    skeleton = _JSON_STRING.sub(b'""', raw)
    long = _LONG_NUMBER.search(skeleton)
    if long:
        return f"a number of {len(long.group())} digits (at most {MAX_DIGITS})", False
    brackets = np.frombuffer(skeleton.translate(None, _NOT_BRACKETS), dtype=np.uint8)
    steps = np.where((brackets == ord("[")) | (brackets == ord("{")), 1, -1)
    if steps.size and steps.cumsum().max() > MAX_DEPTH:
        return f"nests deeper than {MAX_DEPTH} levels", False
    return None, _BIG_EXPONENT.search(skeleton) is not None


def _finite(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"the number {text[:30]} is out of range")
    return value


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number JSON allows")


def load_submission(path: str | Path) -> dict:
    """The results dict in the JSON file ``path``; ``UserError`` if it cannot be read, is no
    JSON object, or is past the parsing limits (``MAX_BYTES``, ``MAX_DEPTH``, ``MAX_DIGITS``;
    NaN and infinities are refused too)."""
    path = Path(path)
    try:
        with path.open("rb") as f:
            raw = f.read(MAX_BYTES + 1)
    except OSError as err:
        raise UserError(f"cannot read submission {path}: {err.strerror}") from None
    if len(raw) > MAX_BYTES:
        raise UserError(
            f"submission {path} is larger than the limit of {MAX_BYTES // 2**20} MiB: not a results JSON of objsearch-eval"
        )
    problem, big = _past_limits(raw)
    if problem is None:
        floats = _finite if big else float  # every float is finite unless an exponent is that large
        try:
            data = json.loads(raw.decode("utf-8"), parse_float=floats, parse_constant=_no_constant)
        except RecursionError:  # only past the checks above when the file is no JSON at all
            problem = f"nests deeper than {MAX_DEPTH} levels"
        except ValueError as err:  # also JSONDecodeError, UnicodeDecodeError and the number checks
            problem = str(err)
    if problem is not None:
        raise UserError(f"submission {path} cannot be read as a results JSON: {problem}")
    if not isinstance(data, dict):
        raise UserError(f"submission {path} is not a results object from objsearch-eval")
    return data
