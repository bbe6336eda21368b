"""The fields of a results JSON (``objsearch-eval``'s output, a leaderboard submission): ``SCHEMA``,
a JSON Schema document as ``objsearch.sim.suite_schema`` has for suite files, and
``type_problems``, which reports what of a submission does not fit it.

Every string a submission holds has a declared format: what reaches the pages or a terminal
is one of these, never free text (and the pages escape it as well). Two readings differ from
plain JSON Schema: an ``integer`` is an integer as written (``1``, not ``1.0``; never
``true``), and a ``pattern`` must match the whole string, a line break at its end included
(each is written ``^(?:...)(?![\\s\\S])``: the pattern, then nothing at all).

Problems are reported as the fields are read: the top-level fields first, then the
config's, the suite config's strings, the training runs', the split summaries' and last the
episode records'; a level is looked at only when those before it have none, and at most 3
are shown."""

from __future__ import annotations

import json
import re
from functools import lru_cache

from objsearch.sim.goals import PROTOCOLS


def _whole(pattern: str) -> str:
    """``pattern`` matching a whole string only (``re.search`` of ``^pattern$`` would let ``"abc\\n"`` pass)."""
    return rf"^(?:{pattern})(?![\s\S])"


def _string(pattern: str, what: str, optional: bool = False) -> dict:
    """A string field that ``pattern`` matches whole (``optional``: or null)."""
    return {
        "type": ["string", "null"] if optional else "string",
        "pattern": _whole(pattern),
        "description": what + (" (or null)" if optional else ""),
    }


ENTRY_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,99}")  # fullmatch: "abc\n" is no name
_NAME_CHARS = "a letter or digit, then letters, digits, '_', '.' or '-'"
_NAME = _string(ENTRY_NAME.pattern, f"a name: {_NAME_CHARS} (at most 100 characters)")
# a file agent is recorded by its absolute path (objsearch.eval.registry.recorded_spec): any path a checkpoint may have
_AGENT = _string(
    r"[A-Za-z0-9_./:-]{1,200}|[^\x00-\x1f\x7f-\x9f\u2028\u2029]{1,1024}\.py:[A-Za-z_][A-Za-z0-9_.]{0,199}",
    "an agent name or module:Class of letters, digits, '_', '.', '/', ':' or '-' (at most 200 characters), "
    "or path/file.py:Class (a path of at most 1024 characters, no control characters)",
)
_VERSION = _string(
    r"[A-Za-z0-9][A-Za-z0-9_.:+!-]{0,99}",
    "a version: a letter or digit, then letters, digits, '_', '.', ':', '+', '!' or '-' (at most 100 characters)",
)
_COMMIT = _string(r"[0-9a-f]{7,64}", "a git commit: 7 to 64 lowercase hex digits", optional=True)
_SHA256 = _string(r"[0-9a-f]{64}", "a SHA-256 digest: 64 lowercase hex digits", optional=True)
_KEY = _string(r"[0-9a-f]{1,64}", "a perception key: up to 64 lowercase hex digits", optional=True)
_PATH = _string(
    r"[^\x00-\x1f\x7f-\x9f\u2028\u2029]{1,1024}",
    "a path or word of at most 1024 characters, no control characters",
    optional=True,
)


def _text(limit: int) -> dict:
    return _string(
        rf"[^\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029]{{0,{limit}}}",
        f"text of at most {limit} characters, no control characters but tab and line breaks",
    )


_INT = {"type": "integer", "description": "an integer"}
_SEED = {"type": "integer", "minimum": 0, "description": "a non-negative integer"}
_SEEDS = {"type": "array", "items": {"type": "integer", "minimum": 0}, "description": "a list of non-negative integers"}
_NAMES = {
    "type": "array",
    "items": {"type": "string", "pattern": _NAME["pattern"]},
    "description": f"a list of names ({_NAME_CHARS})",
}
_BOOL = {"type": "boolean", "description": "true or false"}
_OPT_NUMBER = {"type": ["number", "null"], "description": "a number or null"}
_OPT_COUNT = {"type": ["integer", "null"], "minimum": 0, "description": "a non-negative integer or null"}


def _object(fields: dict, required: tuple = (), what: str = "an object", **more) -> dict:
    return {"type": "object", "properties": fields, "required": list(required), "description": what, **more}


RUN = _object(  # an entry of training_runs (objsearch.eval.runs.run_entry)
    {
        "seed": _SEED,
        "weights_sha256": _SHA256,
        "env_steps": _OPT_COUNT,
        "wall_s": _OPT_NUMBER,
        "splits": {"type": "object", "description": "an object"},
        "loaded_checkpoint": _PATH,
    },
    ("seed", "weights_sha256", "env_steps", "wall_s", "splits"),
)
RECORD = _object(  # an episode's record (objsearch.eval.episode)
    {
        "split": _NAME,
        "seed": _INT,
        "episode_id": _INT,
        "goal": _NAME,
        "success": _BOOL,
        "steps": _INT,
        "min_steps": _INT,
        "spl": _OPT_NUMBER,
        "task": {"type": "object", "description": "an object"},
        "error": _text(2000),
        "traceback": _text(20000),
        "training_run": _SEED,
    },
    ("split", "seed", "episode_id", "goal", "success", "steps", "min_steps", "task"),
)
# the strings of a suite's options (the suite checks their values): the perception key is
# shown on the pages; any other string option is a path
SUITE_CONFIG = _object(
    {"perception_key": {"pattern": _KEY["pattern"], "description": _KEY["description"]}},
    additionalProperties={"pattern": _PATH["pattern"], "description": _PATH["description"]},
)
CONFIG = _object(
    {
        "agent": _AGENT,
        "suite": _NAME,
        "splits": _NAMES,
        "seeds": _SEEDS,
        "checkpoint": _PATH,
        "suite_config": SUITE_CONFIG,
        "step_time_limit": _OPT_NUMBER,
        "weights_sha256": _SHA256,
        "training_run": _SEED,
        "episodes": {"type": ["integer", "null"], "minimum": 1, "description": "a positive integer or null"},
        "checkpoints": _PATH,
    },
    ("agent", "suite", "splits", "seeds"),
)
SCHEMA = _object(
    {
        "schema_version": _INT,
        "agent": _AGENT,
        "suite": _NAME,
        "episode_set_version": _VERSION,
        "objsearch_version": _VERSION,
        "git_commit": _COMMIT,
        "seeds": _SEEDS,
        "config": CONFIG,
        "splits": {
            "type": "object",
            "additionalProperties": {"type": "object", "description": "a split's summary"},
            "description": "an object",
        },
        "episodes": {"type": "array", "items": RECORD, "description": "a list"},
        "partial": _BOOL,
        "training_runs": {
            "type": "array",
            "minItems": 1,
            "maxItems": 100,
            "items": RUN,
            "description": "a list of 1 to 100 runs",
        },
        "loaded_checkpoint": _PATH,
        "protocol": {"enum": list(PROTOCOLS), "description": f"one of the protocols {', '.join(PROTOCOLS)}"},
        # written by `objsearch leaderboard verify` into a stored entry; `add` drops a submission's own
        "verified": _object(
            {
                "replayed": {"type": "integer", "minimum": 0},
                "episodes": {"type": "integer", "minimum": 0},
                "sha256": {"type": "string", "pattern": _SHA256["pattern"]},
            },
            ("replayed", "episodes", "sha256"),
            "an object {replayed, episodes, sha256} written by objsearch leaderboard verify",
            additionalProperties=False,
        ),
    },
    (
        "schema_version",
        "agent",
        "suite",
        "episode_set_version",
        "objsearch_version",
        "seeds",
        "config",
        "splits",
        "episodes",
    ),
    "a results JSON of objsearch-eval",
)
REQUIRED = tuple(SCHEMA["required"])


@lru_cache(maxsize=1)
def _validator():
    """A validator of ``SCHEMA`` whose ``integer`` is an int as written (not ``1.0``, not ``true``)."""
    from jsonschema import Draft202012Validator, validators

    integer = lambda checker, x: isinstance(x, int) and not isinstance(x, bool)
    types = Draft202012Validator.TYPE_CHECKER.redefine("integer", integer)
    return validators.extend(Draft202012Validator, type_checker=types)(SCHEMA)


def _short(value, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _place(path: list) -> tuple[tuple, str, tuple]:
    """Where a field at ``path`` (keys and indices from the results' top) is reported: (level,
    in the order the levels are read, then the item's index; the name of its object in
    messages; the object's path)."""
    head = path[0] if path else None
    if head == "config" and len(path) >= 3 and path[1] == "suite_config":
        return (2,), "config.suite_config", ("config", "suite_config")
    if head == "config" and len(path) >= 2:
        return (1,), "config", ("config",)
    if head == "training_runs" and len(path) >= 2:
        return (3, path[1]), f"training_runs[{path[1]}]", ("training_runs", path[1])
    if head == "splits" and len(path) >= 2:
        return (4, path[1]), f"summary of split {path[1]!r}", ("splits", path[1])
    if head == "episodes" and len(path) >= 2:
        return (5, path[1]), f"episodes[{path[1]}]", ("episodes", path[1])
    return (0,), "results", ()


def _schema_at(keys: tuple) -> dict:
    """The part of ``SCHEMA`` that describes the value at ``keys``."""
    schema = SCHEMA
    for key in keys:
        if isinstance(key, int):
            schema = schema["items"]
        else:
            schema = schema.get("properties", {}).get(key) or schema["additionalProperties"]
    return schema


def _value_at(results: dict, keys: tuple):
    for key in keys:
        results = results[key]
    return results


def _token(schema: dict | None, value):
    """What of ``value`` decides whether it fits ``schema``: its type alone where the schema
    says only a type (or nothing), else the value itself (with its type: ``1`` is not ``True``)."""
    if schema is None or schema.keys() <= {"type", "description"}:
        return type(value).__name__
    if isinstance(value, (dict, list)):
        return type(value).__name__, json.dumps(value, sort_keys=True)
    return type(value).__name__, value


def _kind(record) -> tuple:
    """Records of one kind fit ``RECORD`` alike: each field's ``_token``."""
    if not isinstance(record, dict):
        return (None, _token({"const": None}, record))
    fields = RECORD["properties"]
    return tuple(sorted((key, _token(fields.get(key), value)) for key, value in record.items()))


def _errors(results: dict):
    """(path, keyword) of every place ``results`` does not fit ``SCHEMA``. The records, tens of
    thousands in an entry, are validated once per kind (``_kind``); of the records of a kind,
    only the first 3 are reported (``type_problems`` shows 3 problems at most)."""
    validator, records = _validator(), results.get("episodes")
    if not isinstance(records, list):
        records = []
    for error in validator.iter_errors({**results, "episodes": []} if records else results):
        yield list(error.absolute_path), error.validator
    kinds: dict[tuple, list[int]] = {}
    for i, record in enumerate(records):
        kinds.setdefault(_kind(record), []).append(i)
    fits = validator.evolve(schema=RECORD)
    for indices in kinds.values():
        errors = [(list(e.absolute_path), e.validator) for e in fits.iter_errors(records[indices[0]])]
        for i in indices[:3]:
            for path, keyword in errors:
                yield ["episodes", i, *path], keyword


def type_problems(results: dict) -> list[str]:
    """Fields of ``results`` whose type is not the one a results JSON has (at most 3 shown)."""
    found: dict[tuple, dict] = {}  # level -> {field (None: the object itself): problem}
    where: dict[tuple, tuple] = {}  # level -> the object's path
    for path, keyword in _errors(results):
        missing = keyword == "required"
        level, name, keys = _place(path + [None] if missing else path)
        where[level], problems = keys, found.setdefault(level, {})
        if missing and len(path) == len(keys):  # fields of a level's object are missing
            for key in _schema_at(keys)["required"]:
                if key not in _value_at(results, keys):
                    problems[key] = f"{name} has no field {key!r}"
        elif len(path) == len(keys):  # the object itself is no object (an item of a list, a summary)
            problems[None] = f"{name} is {_short(_value_at(results, keys))}, not an object"
        else:  # a field of it, or something within that field: the field is reported
            key = path[len(keys)]
            value, what = _value_at(results, keys)[key], _schema_at((*keys, key))["description"]
            problems[key] = f"{name} field {key!r} is {_short(value)}, not {what}"
    if not found:
        return []
    first = min(found)[0]  # only the first level with problems is reported
    out = []
    splits = list(results.get("splits", {})) if first == 4 else []
    # items in the order they are given (list items by index, split summaries as the results hold them)
    for level in sorted(
        (level for level in found if level[0] == first), key=lambda lv: splits.index(lv[1]) if splits else lv
    ):
        keys = where[level]
        # fields in the order they are declared; a suite config's strings in the order they are given
        order = list(_value_at(results, keys)) if level == (2,) else list(_schema_at(keys).get("properties", {}))
        out += [found[level][key] for key in sorted(found[level], key=lambda k: -1 if k is None else order.index(k))]
    return out[:3]
