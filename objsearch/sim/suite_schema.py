"""The one check of a house suite file, made when it is read (``objsearch.sim.suites.load_suite_file``).

Users open and edit the files ``objsearch suite make`` writes, so a suite file is input: each
field is checked for its type and range (``SCHEMA``, JSON Schema), the fields against each
other (an episode's house and target must have goal poses, ``check_suite_file``), and, once
the houses are loaded, every pose against the house's pose graph: goal poses and starts
on free cells, every start reaching a goal pose in its ``min_steps`` (``check_poses``). A
bad field is a ``UserError`` naming the file, the field's path in it
(``splits.test-seen[3].start``) and what it must be.

``content_digest`` is the identity of a file's content (every field but ``version``): the
version a suite reports is computed from it (``objsearch.sim.suites.suite_version``).
"""

from __future__ import annotations

import difflib
import hashlib
import json

from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.house.generators import GENERATORS
from objsearch.house.rooms import ROOM_SIZE_CLASS, ROOM_TYPES
from objsearch.house.spec import HOUSE_PLACEMENTS
from objsearch.house.stages import ROOM_COUNT_CLASSES, SIZE_CLASSES, SPLITS
from objsearch.sim.env import STARTS
from objsearch.sim.goals import PROTOCOLS, RULES
from objsearch.sim.navgraph import NAVGRAPH_VERSION

# Where a file's starts were drawn: ``objsearch.sim.env.STARTS``, or (the ``rooms`` suite) among the
# poses that do not see the target.
FILE_STARTS = (*STARTS, "not_visible")
_POSE = {
    "type": "array",
    "prefixItems": [
        {"type": "integer", "minimum": 0},
        {"type": "integer", "minimum": 0},
        {"type": "integer", "minimum": 0, "maximum": 3},
    ],
    "minItems": 3,
    "maxItems": 3,
    "description": "a pose [row, column, heading]: two non-negative integers and a heading 0-3",
}
_HOUSE = {
    "type": "object",
    "properties": {
        "seed": {"type": "integer", "minimum": 0, "description": "the house's generator seed"},
        "split": {"enum": list(SPLITS), "description": "the generator split the house was made for"},
        "size_class": {
            "enum": [*SIZE_CLASSES, *ROOM_COUNT_CLASSES, ROOM_SIZE_CLASS, None],
            "description": "the house's size class",
        },
        "generator": {"enum": list(GENERATORS), "description": "the generator version"},
        "placement": {"enum": list(HOUSE_PLACEMENTS), "description": "how its objects are placed (absent: functional)"},
        "room": {
            "enum": list(ROOM_TYPES),
            "description": f"a single room of this type instead of a house: one of {', '.join(ROOM_TYPES)}",
        },
        "path": {"type": "string", "minLength": 1, "description": "the house folder, relative to the suite file"},
        "spec_sha256": {
            "type": "string",
            "pattern": "^[0-9a-f]{64}$",
            "description": "the sha256 of the house's spec (64 hex digits)",
        },
    },
    "required": ["spec_sha256"],
    "additionalProperties": False,
    "description": "a house: {seed, split, size_class, spec_sha256[, generator][, placement][, room]} or "
    "{path, spec_sha256}",
}
_EPISODE = {
    "type": "object",
    "properties": {
        "house": {"type": "string", "description": "a house id of houses"},
        "start": _POSE,
        "target": {"type": "string", "description": "a target category with goal poses in the house"},
        "min_steps": {
            "type": "integer",
            "minimum": 0,
            "description": "the minimal actions to succeed: moves to the nearest goal pose (+1 for STOP under "
            "objectnav)",
        },
        "geodesic": {
            "type": "number",
            "minimum": 0,
            "description": "metres walked from the start to the nearest goal pose (optional; results by distance)",
        },
    },
    "required": ["house", "start", "target", "min_steps"],
    "additionalProperties": False,
    "description": "an episode: {house, start, target, min_steps[, geodesic]}",
}
_NAMES = {"type": "array", "items": {"type": "string"}, "uniqueItems": True, "description": "a list of category names"}
SCHEMA = {
    "type": "object",
    "properties": {
        "suite": {"type": "string", "description": "the suite's name"},
        "version": {"type": "string", "description": "the suite's version"},
        "protocol": {
            "enum": list(PROTOCOLS),
            "description": f"the success protocol: {' or '.join(PROTOCOLS)} (absent: paper)",
        },
        "navgraph": {
            "const": NAVGRAPH_VERSION,
            "description": f"the pose graph the poses are on; this objsearch has {NAVGRAPH_VERSION}: remake the "
            "file with this version",
        },
        "goal_rule": {
            "type": "object",
            "properties": {
                "version": {"type": "string"},
                "kind": {"enum": list(RULES), "description": f"one of {', '.join(RULES)}"},
                "top_k": {"type": "integer", "minimum": 1, "description": "a positive integer"},
                "min_pixels": {"type": "integer", "minimum": 1, "description": "a positive integer"},
                "max_distance": {"type": "number", "exclusiveMinimum": 0, "description": "metres, above 0"},
            },
            "required": ["kind"],
            "additionalProperties": False,
            "description": "the goal rule {kind, top_k, min_pixels, max_distance}",
        },
        "goal_camera": {"type": "object", "description": "the goal camera's settings"},
        "start_steps": {
            "type": "array",
            "items": {"type": "integer", "minimum": 0},
            "minItems": 2,
            "maxItems": 2,
            "description": "[fewest, most] steps of the drawn starts from the goal",
        },
        "starts": {"enum": list(FILE_STARTS), "description": f"where starts were drawn: {' or '.join(FILE_STARTS)}"},
        "seeds": {
            "type": "array",
            "items": {"type": "integer", "minimum": 0},
            "minItems": 1,
            "uniqueItems": True,
            "description": "the seeds a full evaluation plays (absent: the paper's 1, 5, 13, 45, 99)",
        },
        "max_steps": {
            "type": "integer",
            "minimum": 1,
            "description": "an episode's step limit, a positive integer (paper 1000, objectnav 500)",
        },
        "room_max_steps": {
            "type": "object",
            "properties": {
                room: {
                    "type": "integer",
                    "minimum": 1,
                    "description": f"the step limit of a {room}, a positive integer",
                }
                for room in ROOM_TYPES
            },
            "additionalProperties": False,
            "description": "the step limits of single rooms by room type (under max_steps)",
        },
        "categories": {
            "type": "object",
            "additionalProperties": _NAMES,
            "description": "the target categories by group: {seen, unseen} or {targets}",
        },
        "houses": {
            "type": "object",
            "minProperties": 1,
            "additionalProperties": _HOUSE,
            "description": "the evaluation houses by house id, at least one",
        },
        "training_houses": {"type": "object", "additionalProperties": _HOUSE, "description": "houses by house id"},
        "goals": {
            "type": "object",
            "additionalProperties": {
                "type": "object",
                "additionalProperties": {
                    "type": "array",
                    "minItems": 1,
                    "items": _POSE,
                    "description": "the goal poses of a target: a non-empty list of [row, column, heading]",
                },
                "description": "a house's goal poses by target category",
            },
            "description": "goal poses by house id, then target category",
        },
        "splits": {
            "type": "object",
            "minProperties": 1,
            "additionalProperties": {
                "type": "array",
                "minItems": 1,
                "items": _EPISODE,
                "description": "a split: a non-empty list of episodes {house, start, target, min_steps}",
            },
            "description": "the splits by name, at least one",
        },
    },
    "required": [
        "suite",
        "version",
        "navgraph",
        "goal_rule",
        "goal_camera",
        "start_steps",
        "max_steps",
        "categories",
        "houses",
        "training_houses",
        "goals",
        "splits",
    ],
    "additionalProperties": False,
    "description": "a suite file made by objsearch suite make",
}


def field_path(parts) -> str:
    """``splits.test-seen[3].start`` from the keys and indices ``parts``."""
    out = ""
    for part in parts:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "the file"


def _short(value, limit: int = 60) -> str:
    text = json.dumps(value) if not isinstance(value, str) else repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _fail(source: str, where, problem: str, what: str | None, fix: str):
    expected = f" (expected {what})" if what else ""
    raise UserError(f"suite file {source}: {field_path(where)}: {problem}{expected}; {fix}")


def _schema_problem(error) -> tuple[list, str, str | None]:
    """A ``jsonschema`` error as (the field's path, what is wrong, what it must be)."""
    where, kind, value, schema = list(error.absolute_path), error.validator, error.instance, error.schema
    what = schema.get("description")
    if kind == "additionalProperties":
        extra = sorted(set(value) - set(schema.get("properties", {})))[0]
        return where + [extra], "is not a field here", f"one of {', '.join(schema.get('properties', {}))}"
    if kind == "required":
        missing = next(key for key in error.validator_value if key not in value)
        close = difflib.get_close_matches(missing, [k for k in value if k not in schema.get("properties", {})], n=1)
        problem = f"is missing (the file has {close[0]!r}: misspelt?)" if close else "is missing"
        return where + [missing], problem, schema.get("properties", {}).get(missing, {}).get("description")
    if kind in ("minItems", "minProperties") and len(value) == 0:
        return where, "is empty", what
    if kind in ("type", "enum", "const"):
        verb = {"type": "is not of type", "enum": "is not one of", "const": "is not"}[kind]
        return where, f"{_short(value)} {verb} {_short(error.validator_value)}", what
    if kind in ("minItems", "maxItems"):
        return where, f"{_short(value)} has {len(value)} item(s)", what
    return where, error.message if len(error.message) <= 200 else error.message[:197] + "...", what


def check_suite_file(data, source: str, fix: str) -> None:
    """Check a suite file's content (``data``, as read): types and ranges, then the fields
    against each other. ``source`` names the file and ``fix`` says how to repair it in
    errors. Raises ``UserError`` for the first bad field."""
    from jsonschema import Draft202012Validator
    from jsonschema.exceptions import best_match

    error = best_match(Draft202012Validator(SCHEMA).iter_errors(data))  # the shallowest: a container before its items
    if error is not None:
        _fail(source, *_schema_problem(error), fix)
    protocol = PROTOCOLS[data.get("protocol", "paper")]
    if data["goal_rule"]["kind"] != protocol.goal_rule.kind:
        _fail(
            source,
            ["goal_rule", "kind"],
            f"{data['goal_rule']['kind']!r} is not the {protocol.name} protocol's rule",
            f"{protocol.goal_rule.kind!r}",
            fix,
        )
    for group in ("houses", "training_houses"):
        for house, info in data[group].items():
            if "seed" not in info and "path" not in info:
                _fail(source, [group, house], "has neither a seed nor a path", _HOUSE["description"], fix)
    objects = {name for name, i in CATEGORY_IDS.items() if i >= FIRST_OBJECT_ID}
    for group, names in data["categories"].items():
        for i, name in enumerate(names):
            if name not in objects:
                _fail(source, ["categories", group, i], f"{name!r} is not an object category", "a category", fix)
    for house, table in data["goals"].items():
        if house not in data["houses"]:
            _fail(source, ["goals", house], f"house {house!r} is not in houses", "a house id of houses", fix)
        for target in table:
            if target not in objects:
                _fail(source, ["goals", house, target], f"{target!r} is not an object category", "a category", fix)
    for split, episodes in data["splits"].items():
        for i, item in enumerate(episodes):
            if item["house"] not in data["houses"]:
                what = f"one of {', '.join(sorted(data['houses']))}"
                _fail(source, ["splits", split, i, "house"], f"house {item['house']!r} is not in houses", what, fix)
            if item["target"] not in data["goals"].get(item["house"], {}):
                _fail(
                    source,
                    ["splits", split, i, "target"],
                    f"{item['target']!r} has no goal poses in house {item['house']} (goals.{item['house']})",
                    f"one of {', '.join(sorted(data['goals'].get(item['house'], {}))) or 'none'}",
                    fix,
                )


def check_poses(data: dict, worlds: dict, source: str, fix: str) -> None:
    """Check every pose of a suite file (``data``, checked by ``check_suite_file``) on its
    houses' pose graphs (``worlds``: house id -> ``World``): goal poses and starts on free
    cells, and every episode's ``min_steps`` the minimal actions to success (the moves to the
    nearest goal pose, and the STOP under a protocol that requires it)."""
    stop = PROTOCOLS[data.get("protocol", "paper")].stop
    ids = {}
    for house, table in data["goals"].items():
        graph = worlds[house].graph
        for target, poses in table.items():
            ids[house, target] = [
                _pose_id(graph, pose, ["goals", house, target, k], source, fix) for k, pose in enumerate(poses)
            ]
    steps = {}
    for split, episodes in data["splits"].items():
        for i, item in enumerate(episodes):
            graph, key = worlds[item["house"]].graph, (item["house"], item["target"])
            start = _pose_id(graph, item["start"], ["splits", split, i, "start"], source, fix)
            if key not in steps:
                steps[key] = graph.shortest_steps(ids[key])
            moves = int(steps[key][start])
            if moves < 0:
                _fail(
                    source,
                    ["splits", split, i, "start"],
                    f"no goal pose of {item['target']} can be reached from {item['start']}",
                    "a start that reaches the target's goal poses",
                    fix,
                )
            if moves + stop != item["min_steps"]:
                counted = " and the STOP" if stop else ""
                _fail(
                    source,
                    ["splits", split, i, "min_steps"],
                    f"is {item['min_steps']}, but the pose graph says {moves + stop} (moves to the nearest goal "
                    f"pose{counted})",
                    None,
                    fix,
                )


def _pose_id(graph, pose, where, source: str, fix: str) -> int:
    try:
        return graph.pose_id(*pose)
    except ValueError:
        _fail(source, where, f"{pose} is not on a free cell of the house (a wall or outside)", "a free pose", fix)


def content_digest(data: dict) -> str:
    """sha256 of a suite file's canonical content (sorted keys, every field but ``version``),
    as read from the file (house paths as written)."""
    content = {key: value for key, value in data.items() if key != "version"}
    return hashlib.sha256(json.dumps(content, sort_keys=True, separators=(",", ":")).encode()).hexdigest()
